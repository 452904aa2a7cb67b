-- Yanking (as crates.io's): a yanked version stays fetchable by its number, so that lock files
-- naming it keep working, but it is offered to no new resolution. A yank is a row here, so that
-- versions stay immutable; unyanking deletes the row.
CREATE TABLE version_yank (
    version_id INTEGER PRIMARY KEY REFERENCES grammar_version (id),
    yanked_by INTEGER NOT NULL REFERENCES account (id),
    yanked_at INTEGER NOT NULL,
    reason TEXT
);

-- Each grammar's current version: its newest version not yanked (none when all are yanked).
-- Rule queries and search offer only these.
CREATE VIEW current_version AS
SELECT v.grammar_id, v.id AS version_id, v.version
FROM grammar_version v
WHERE NOT EXISTS (SELECT 1 FROM version_yank y WHERE y.version_id = v.id)
  AND NOT EXISTS (
    SELECT 1 FROM grammar_version w
    WHERE w.grammar_id = v.grammar_id AND w.version > v.version
      AND NOT EXISTS (SELECT 1 FROM version_yank y WHERE y.version_id = w.id));
