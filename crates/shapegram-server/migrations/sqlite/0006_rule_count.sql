-- Each version records how many rules its index has, so that an audit can tell a complete index
-- from a partial one (and a grammar without rules from a lost index). Versions published before
-- have none recorded.
ALTER TABLE grammar_version ADD COLUMN rule_count INTEGER;
