-- Rule queries (POST /api/v1/queries) also offer the rules that need no key at all: a partial
-- index finds them without scanning every rule.
CREATE INDEX rule_unkeyed ON rule (id) WHERE n_pos = 0;
