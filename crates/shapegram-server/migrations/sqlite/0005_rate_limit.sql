-- Rate-limit counters, shared by every process serving the database: one row per key (a token's
-- hash, a caller's address) and fixed window, counted up by one UPSERT … RETURNING per request.
-- Windows that have ended are pruned.
CREATE TABLE rate_limit (
    key TEXT NOT NULL,
    window_start INTEGER NOT NULL,
    hits INTEGER NOT NULL,
    PRIMARY KEY (key, window_start)
) WITHOUT ROWID;
CREATE INDEX rate_limit_window ON rate_limit (window_start);
