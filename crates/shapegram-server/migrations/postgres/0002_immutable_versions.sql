-- Published versions, their rule index and the publish log are never changed or removed: the
-- database refuses it, whatever code asks (TRUNCATE too). (Yanking, later, will be a separate
-- table.)

CREATE FUNCTION refuse_change() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    RAISE EXCEPTION '%', TG_ARGV[0] USING ERRCODE = 'restrict_violation';
END;
$$;

CREATE TRIGGER grammar_version_immutable BEFORE UPDATE OR DELETE ON grammar_version
    FOR EACH ROW EXECUTE FUNCTION refuse_change('published versions are immutable');
CREATE TRIGGER grammar_version_no_truncate BEFORE TRUNCATE ON grammar_version
    FOR EACH STATEMENT EXECUTE FUNCTION refuse_change('published versions are immutable');

CREATE TRIGGER rule_immutable BEFORE UPDATE OR DELETE ON rule
    FOR EACH ROW EXECUTE FUNCTION refuse_change('published versions are immutable');
CREATE TRIGGER rule_no_truncate BEFORE TRUNCATE ON rule
    FOR EACH STATEMENT EXECUTE FUNCTION refuse_change('published versions are immutable');

CREATE TRIGGER rule_key_immutable BEFORE UPDATE OR DELETE ON rule_key
    FOR EACH ROW EXECUTE FUNCTION refuse_change('published versions are immutable');
CREATE TRIGGER rule_key_no_truncate BEFORE TRUNCATE ON rule_key
    FOR EACH STATEMENT EXECUTE FUNCTION refuse_change('published versions are immutable');

CREATE TRIGGER rule_neg_immutable BEFORE UPDATE OR DELETE ON rule_neg
    FOR EACH ROW EXECUTE FUNCTION refuse_change('published versions are immutable');
CREATE TRIGGER rule_neg_no_truncate BEFORE TRUNCATE ON rule_neg
    FOR EACH STATEMENT EXECUTE FUNCTION refuse_change('published versions are immutable');

CREATE TRIGGER publish_log_append_only BEFORE UPDATE OR DELETE ON publish_log
    FOR EACH ROW EXECUTE FUNCTION refuse_change('the publish log is append-only');
CREATE TRIGGER publish_log_no_truncate BEFORE TRUNCATE ON publish_log
    FOR EACH STATEMENT EXECUTE FUNCTION refuse_change('the publish log is append-only');
