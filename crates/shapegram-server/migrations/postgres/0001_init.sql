-- Accounts, tokens, friends, grammars, versions and their rule index: the SQLite schema
-- (migrations/sqlite/0001_init.sql) in PostgreSQL's types. Times are seconds since the Unix
-- epoch. Names have a canonical form (lower case, `_` as `-`) that is unique, as crates.io
-- treats crate names. Canonical names and index keys compare byte by byte (COLLATE "C"), as
-- SQLite compares them, whatever the database's locale: lists come in the same order.

CREATE TABLE account (
    id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    name TEXT NOT NULL,
    canon TEXT COLLATE "C" NOT NULL UNIQUE,
    password_hash TEXT NOT NULL,
    created_at BIGINT NOT NULL
);

CREATE TABLE api_token (
    id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    account_id BIGINT NOT NULL REFERENCES account (id),
    name TEXT NOT NULL,
    hash BYTEA NOT NULL UNIQUE,
    prefix TEXT NOT NULL,
    created_at BIGINT NOT NULL,
    revoked_at BIGINT
);
CREATE INDEX api_token_account ON api_token (account_id);

-- One row per pair: a request until accepted_at is set, then a friendship both ways.
CREATE TABLE friendship (
    requester_id BIGINT NOT NULL REFERENCES account (id),
    addressee_id BIGINT NOT NULL REFERENCES account (id),
    created_at BIGINT NOT NULL,
    accepted_at BIGINT,
    PRIMARY KEY (requester_id, addressee_id),
    CHECK (requester_id <> addressee_id)
);
CREATE INDEX friendship_addressee ON friendship (addressee_id, requester_id);

CREATE TABLE grammar (
    id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    owner_id BIGINT NOT NULL REFERENCES account (id),
    name TEXT NOT NULL,
    canon TEXT COLLATE "C" NOT NULL,
    visibility TEXT NOT NULL CHECK (visibility IN ('public', 'friends', 'private')),
    latest_version BIGINT NOT NULL DEFAULT 0,
    created_at BIGINT NOT NULL,
    updated_at BIGINT NOT NULL,
    UNIQUE (owner_id, canon)
);

-- Immutable: rows are inserted, never updated or deleted.
CREATE TABLE grammar_version (
    id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    grammar_id BIGINT NOT NULL REFERENCES grammar (id),
    version BIGINT NOT NULL,
    text TEXT NOT NULL,
    sha256 TEXT NOT NULL,
    publisher_id BIGINT NOT NULL REFERENCES account (id),
    published_at BIGINT NOT NULL,
    UNIQUE (grammar_id, version)
);

-- The rule index (research §4.2): positive keys in rule_key, negated predicates in rule_neg.
CREATE TABLE rule (
    id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    version_id BIGINT NOT NULL REFERENCES grammar_version (id),
    idx BIGINT NOT NULL,
    n_pos BIGINT NOT NULL,
    local BOOLEAN NOT NULL,
    conditional BOOLEAN NOT NULL,
    UNIQUE (version_id, idx)
);

CREATE TABLE rule_key (
    key TEXT COLLATE "C" NOT NULL,
    rule_id BIGINT NOT NULL REFERENCES rule (id),
    PRIMARY KEY (key, rule_id)
);
CREATE INDEX rule_key_rule ON rule_key (rule_id);

CREATE TABLE rule_neg (
    rule_id BIGINT NOT NULL REFERENCES rule (id),
    grp BIGINT NOT NULL,
    key TEXT COLLATE "C" NOT NULL,
    PRIMARY KEY (rule_id, grp, key)
);

-- Every publish, in order: what a lock file will record its position in. A publish inserts
-- its entry last, numbered one past the greatest under a lock on this table held until it
-- commits, so that the numbers follow the commits without gaps (a sequence would leave one
-- for each publish that rolls back after taking a number), as SQLite's rowids do.
CREATE TABLE publish_log (
    seq BIGINT PRIMARY KEY,
    version_id BIGINT NOT NULL UNIQUE REFERENCES grammar_version (id),
    logged_at BIGINT NOT NULL
);
