-- Rate-limit counters, shared by every process serving the database: one row per key (a token's
-- hash, a caller's address) and fixed window, counted up by one UPSERT … RETURNING per request.
-- Windows that have ended are pruned. (migrations/sqlite/0005_rate_limit.sql)
CREATE TABLE rate_limit (
    key TEXT COLLATE "C" NOT NULL,
    window_start BIGINT NOT NULL,
    hits BIGINT NOT NULL,
    PRIMARY KEY (key, window_start)
);
CREATE INDEX rate_limit_window ON rate_limit (window_start);
