//! The index keys of a goal program's rules, as a grammar repository stores them to find the
//! rules that may apply to a shape without scanning (see `docs/repository.md`).

use crate::Program;
use crate::goals::{GoalId, GoalRules};

/// What a goal rule's goal, tag and attribute predicates ask of a shape, as keys: `g:NAME` for
/// an open goal (`fulfills`, `goal`), `t:NAME` for a tag (`is`, `tag`, `using` blocks), `a:NAME`
/// for an attribute (`has`, and every attribute the rule reads). A goal local to the rule's
/// grammar is marked `lg:NAME` (`lt:NAME` as a tag): no other grammar's shape asks for it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RuleKeys {
    /// Keys the shape must all have, sorted and without repeats.
    pub positive: Vec<String>,
    /// One list per negated predicate (`!goal`, `!is`, `!has`): the shape must lack at least
    /// one of its keys.
    pub negative: Vec<Vec<String>>,
    /// Whether a positive key is a local goal or tag.
    pub local: bool,
    /// Whether the rule has `if(…)` or `!if(…)` conditions, which the keys do not capture.
    pub conditional: bool,
}

impl Program {
    /// The keys of each goal rule, in rule order; `None` for a program of symbol rules.
    pub fn goal_rule_keys(&self) -> Option<Vec<RuleKeys>> {
        let rules = self.goals.as_deref()?;
        Some(
            rules
                .rules
                .iter()
                .map(|rule| {
                    let goal = |prefix: &str, g: &GoalId| goal_key(rules, prefix, *g);
                    let attr = |a: &u32| format!("a:{}", rules.attributes[*a as usize]);
                    let mut positive: Vec<String> = rule
                        .goals
                        .iter()
                        .map(|g| goal("g", g))
                        .chain(rule.tags.iter().map(|t| goal("t", t)))
                        .chain(rule.attrs.iter().map(attr))
                        .collect();
                    positive.sort();
                    positive.dedup();
                    let negative = (rule
                        .not_goals
                        .iter()
                        .map(|set| set.iter().map(|g| goal("g", g)).collect::<Vec<_>>()))
                    .chain(
                        rule.not_tags
                            .iter()
                            .map(|set| set.iter().map(|t| goal("t", t)).collect()),
                    )
                    .chain(
                        rule.not_attrs
                            .iter()
                            .map(|set| set.iter().map(attr).collect()),
                    )
                    .collect();
                    RuleKeys {
                        local: positive.iter().any(|k| k.starts_with('l')),
                        positive,
                        negative,
                        conditional: !rule.conditions.is_empty(),
                    }
                })
                .collect(),
        )
    }
}

fn goal_key(rules: &GoalRules, prefix: &str, goal: GoalId) -> String {
    let goal = &rules.goals[goal as usize];
    let local = if goal.local.is_some() { "l" } else { "" };
    format!("{local}{prefix}:{}", goal.name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_syntax::{SourceFile, parse};

    #[test]
    fn keys_of_goal_rules() {
        let text = r#"
local "split-legs"
axiom chair size(1, 1, 1)
fulfills(chair) --> split(y) { ~1 : +support | ~1 : +"split-legs" }
using is(chair) {
    fulfills(support) !has(Done) --> set(@Leg.Size, 1)
    fulfills("split-legs") if(@Leg.Size > 0) --> void
}
"#;
        let parsed = parse(&SourceFile::new("chair.goal", text));
        assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
        let (program, diagnostics) = Program::compile_library(&[("chair", &parsed.grammar)]);
        let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
        let keys = program.goal_rule_keys().expect("a goal program");
        let positive: Vec<Vec<&str>> = keys
            .iter()
            .map(|k| k.positive.iter().map(String::as_str).collect())
            .collect();
        assert_eq!(
            positive,
            [
                vec!["g:chair"],
                vec!["g:support", "t:chair"],
                vec!["a:Leg.Size", "lg:split-legs", "t:chair"],
            ]
        );
        assert_eq!(keys[1].negative, [vec!["a:Done".to_owned()]]);
        assert_eq!(
            keys.iter()
                .map(|k| (k.local, k.conditional))
                .collect::<Vec<_>>(),
            [(false, false), (false, false), (true, true)]
        );
    }

    #[test]
    fn symbol_programs_have_no_goal_rules() {
        let parsed = parse(&SourceFile::new("a.cga", "Lot --> extrude(1) Mass"));
        let (program, _) = Program::compile(&parsed.grammar);
        assert_eq!(program.expect("compiles").goal_rule_keys(), None);
    }
}
