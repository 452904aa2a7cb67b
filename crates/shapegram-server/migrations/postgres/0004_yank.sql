-- Yanking (as crates.io's): a yanked version stays fetchable by its number, so that lock files
-- naming it keep working, but it is offered to no new resolution. A yank is a row here, so that
-- versions stay immutable; unyanking deletes the row. (migrations/sqlite/0004_yank.sql)
CREATE TABLE version_yank (
    version_id BIGINT PRIMARY KEY REFERENCES grammar_version (id),
    yanked_by BIGINT NOT NULL REFERENCES account (id),
    yanked_at BIGINT NOT NULL,
    reason TEXT
);

-- Each grammar's current version: its newest version not yanked (NULL when all are yanked),
-- the one rule queries and search offer. Kept by the store in the transaction of every publish,
-- yank and unyank, so that queries join it as cheaply as latest_version.
ALTER TABLE grammar ADD COLUMN current_version BIGINT;
UPDATE grammar SET current_version = latest_version;
