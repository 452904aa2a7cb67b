-- Accounts, tokens, friends, grammars, versions and their rule index.
-- Times are seconds since the Unix epoch. Names have a canonical form (lower case, `_` as `-`)
-- that is unique, as crates.io treats crate names.

CREATE TABLE account (
    id INTEGER PRIMARY KEY,
    name TEXT NOT NULL,
    canon TEXT NOT NULL UNIQUE,
    password_hash TEXT NOT NULL,
    created_at INTEGER NOT NULL
);

CREATE TABLE api_token (
    id INTEGER PRIMARY KEY,
    account_id INTEGER NOT NULL REFERENCES account (id),
    name TEXT NOT NULL,
    hash BLOB NOT NULL UNIQUE,
    prefix TEXT NOT NULL,
    created_at INTEGER NOT NULL,
    revoked_at INTEGER
);
CREATE INDEX api_token_account ON api_token (account_id);

-- One row per pair: a request until accepted_at is set, then a friendship both ways.
CREATE TABLE friendship (
    requester_id INTEGER NOT NULL REFERENCES account (id),
    addressee_id INTEGER NOT NULL REFERENCES account (id),
    created_at INTEGER NOT NULL,
    accepted_at INTEGER,
    PRIMARY KEY (requester_id, addressee_id),
    CHECK (requester_id <> addressee_id)
);
CREATE INDEX friendship_addressee ON friendship (addressee_id, requester_id);

CREATE TABLE grammar (
    id INTEGER PRIMARY KEY,
    owner_id INTEGER NOT NULL REFERENCES account (id),
    name TEXT NOT NULL,
    canon TEXT NOT NULL,
    visibility TEXT NOT NULL CHECK (visibility IN ('public', 'friends', 'private')),
    latest_version INTEGER NOT NULL DEFAULT 0,
    created_at INTEGER NOT NULL,
    updated_at INTEGER NOT NULL,
    UNIQUE (owner_id, canon)
);

-- Immutable: rows are inserted, never updated or deleted.
CREATE TABLE grammar_version (
    id INTEGER PRIMARY KEY,
    grammar_id INTEGER NOT NULL REFERENCES grammar (id),
    version INTEGER NOT NULL,
    text TEXT NOT NULL,
    sha256 TEXT NOT NULL,
    publisher_id INTEGER NOT NULL REFERENCES account (id),
    published_at INTEGER NOT NULL,
    UNIQUE (grammar_id, version)
);

-- The rule index (research §4.2): positive keys in rule_key, negated predicates in rule_neg.
CREATE TABLE rule (
    id INTEGER PRIMARY KEY,
    version_id INTEGER NOT NULL REFERENCES grammar_version (id),
    idx INTEGER NOT NULL,
    n_pos INTEGER NOT NULL,
    local INTEGER NOT NULL,
    conditional INTEGER NOT NULL,
    UNIQUE (version_id, idx)
);

CREATE TABLE rule_key (
    key TEXT NOT NULL,
    rule_id INTEGER NOT NULL REFERENCES rule (id),
    PRIMARY KEY (key, rule_id)
);
CREATE INDEX rule_key_rule ON rule_key (rule_id);

CREATE TABLE rule_neg (
    rule_id INTEGER NOT NULL REFERENCES rule (id),
    grp INTEGER NOT NULL,
    key TEXT NOT NULL,
    PRIMARY KEY (rule_id, grp, key)
);

-- Every publish, in order: what a lock file will record its position in.
CREATE TABLE publish_log (
    seq INTEGER PRIMARY KEY,
    version_id INTEGER NOT NULL UNIQUE REFERENCES grammar_version (id),
    logged_at INTEGER NOT NULL
);
