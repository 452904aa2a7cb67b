-- Each version records how many rules its index has, so that an audit can tell a complete index
-- from a partial one (and a grammar without rules from a lost index). Versions published before
-- have none recorded. (migrations/sqlite/0006_rule_count.sql)
ALTER TABLE grammar_version ADD COLUMN rule_count BIGINT;
