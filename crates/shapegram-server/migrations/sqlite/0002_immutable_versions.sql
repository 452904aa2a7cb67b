-- Published versions, their rule index and the publish log are never changed or removed: the
-- database refuses it, whatever code asks. (Yanking, later, will be a separate table.)

CREATE TRIGGER grammar_version_no_update BEFORE UPDATE ON grammar_version
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;
CREATE TRIGGER grammar_version_no_delete BEFORE DELETE ON grammar_version
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;

CREATE TRIGGER rule_no_update BEFORE UPDATE ON rule
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;
CREATE TRIGGER rule_no_delete BEFORE DELETE ON rule
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;

CREATE TRIGGER rule_key_no_update BEFORE UPDATE ON rule_key
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;
CREATE TRIGGER rule_key_no_delete BEFORE DELETE ON rule_key
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;

CREATE TRIGGER rule_neg_no_update BEFORE UPDATE ON rule_neg
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;
CREATE TRIGGER rule_neg_no_delete BEFORE DELETE ON rule_neg
BEGIN SELECT RAISE(ABORT, 'published versions are immutable'); END;

CREATE TRIGGER publish_log_no_update BEFORE UPDATE ON publish_log
BEGIN SELECT RAISE(ABORT, 'the publish log is append-only'); END;
CREATE TRIGGER publish_log_no_delete BEFORE DELETE ON publish_log
BEGIN SELECT RAISE(ABORT, 'the publish log is append-only'); END;
