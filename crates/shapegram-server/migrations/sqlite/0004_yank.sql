-- Yanking (as crates.io's): a yanked version stays fetchable by its number, so that lock files
-- naming it keep working, but it is offered to no new resolution. A yank is a row here, so that
-- versions stay immutable; unyanking deletes the row.
CREATE TABLE version_yank (
    version_id INTEGER PRIMARY KEY REFERENCES grammar_version (id),
    yanked_by INTEGER NOT NULL REFERENCES account (id),
    yanked_at INTEGER NOT NULL,
    reason TEXT
);

-- Each grammar's current version: its newest version not yanked (NULL when all are yanked),
-- the one rule queries and search offer. Kept by the store in the transaction of every publish,
-- yank and unyank, so that queries join it as cheaply as latest_version.
ALTER TABLE grammar ADD COLUMN current_version INTEGER;
UPDATE grammar SET current_version = latest_version;
