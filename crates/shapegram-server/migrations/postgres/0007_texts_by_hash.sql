-- Lock files fetch the versions they pin by the SHA-256 of their text (GET /api/v1/texts/…),
-- which survives renames. (migrations/sqlite/0007_texts_by_hash.sql)
CREATE INDEX grammar_version_sha256 ON grammar_version (sha256);
