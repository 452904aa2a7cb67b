-- Lock files fetch the versions they pin by the SHA-256 of their text (GET /api/v1/texts/…),
-- which survives renames.
CREATE INDEX grammar_version_sha256 ON grammar_version (sha256);
