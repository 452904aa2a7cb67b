//! Goal grammars (Ilčík and Wimmer's declarative shape grammars): what a shape should become,
//! and which rules may make it so.
//!
//! A shape of a goal grammar carries [`Semantics`]: the goals it should still fulfil, the tags
//! of those it fulfilled, named attributes and the grammar of the rule that made it. A rule has
//! predicates instead of a symbol; it applies to a shape with open goals when they all hold.
//! Rules of the grammar being derived come first, then those of the shape's own grammar, then
//! the rest of the library, then grammars found in a repository (see [`Candidates`]); among several candidates of one tier one is
//! drawn from the shape's random stream. The rules that fulfil (or ask for) a goal are indexed by it, and
//! the rules whose goal, tag and attribute predicates hold for a given semantics are found once
//! per distinct semantics, so a step costs the same whatever the size of the library.
//!
//! Goals local to a grammar (`local split_legs`, or `.goal("…")` in the Michelangelo notation)
//! are told apart from goals of the same name elsewhere by their grammar: only that grammar's
//! rules fulfil them.

use std::sync::Arc;

use rustc_hash::{FxHashMap, FxHashSet};
use shapegram_syntax::Span;

use crate::program::{CExpr, RuleId, Sym};
use crate::value::Value;

/// Index of a goal (and tag) in [`GoalRules::goals`].
pub(crate) type GoalId = u32;
/// Index of a named attribute in [`GoalRules::attributes`].
pub(crate) type AttrId = u32;
/// Index of a grammar in a library.
pub(crate) type GrammarId = u16;

/// A goal's name and, for a local goal, the grammar it belongs to.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct GoalName {
    pub name: Arc<str>,
    pub local: Option<GrammarId>,
}

/// What a shape of a goal grammar is and should become.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Semantics {
    /// Goals still open, sorted.
    pub goals: Vec<GoalId>,
    /// Goals fulfilled, sorted; never one of `goals`.
    pub tags: Vec<GoalId>,
    /// Named attributes, sorted by name.
    pub attrs: Vec<(AttrId, Value)>,
    /// The grammar of the rule that made the shape (the axiom's for an axiom).
    pub grammar: GrammarId,
}

impl Semantics {
    /// Opens goals; a goal that was a tag is open again.
    pub fn open(&mut self, goals: &[GoalId]) {
        for &g in goals {
            if let Err(at) = self.goals.binary_search(&g) {
                self.goals.insert(at, g);
            }
            if let Ok(at) = self.tags.binary_search(&g) {
                self.tags.remove(at);
            }
        }
    }

    /// Turns goals into tags.
    pub fn fulfil(&mut self, goals: &[GoalId]) {
        for &g in goals {
            if let Ok(at) = self.goals.binary_search(&g) {
                self.goals.remove(at);
            }
            if let Err(at) = self.tags.binary_search(&g) {
                self.tags.insert(at, g);
            }
        }
    }

    /// Sets an attribute.
    pub fn set(&mut self, attr: AttrId, value: Value) {
        match self.attrs.binary_search_by_key(&attr, |(a, _)| *a) {
            Ok(at) => self.attrs[at].1 = value,
            Err(at) => self.attrs.insert(at, (attr, value)),
        }
    }

    /// An attribute's value.
    pub fn get(&self, attr: AttrId) -> Option<&Value> {
        self.attrs
            .binary_search_by_key(&attr, |(a, _)| *a)
            .ok()
            .map(|at| &self.attrs[at].1)
    }

    fn has_goals(&self, goals: &[GoalId]) -> bool {
        goals.iter().all(|g| self.goals.binary_search(g).is_ok())
    }

    fn has_tags(&self, tags: &[GoalId]) -> bool {
        tags.iter().all(|g| self.tags.binary_search(g).is_ok())
    }

    fn has_attrs(&self, attrs: &[AttrId]) -> bool {
        attrs.iter().all(|a| self.get(*a).is_some())
    }

    /// What rule candidates depend on: everything but the attribute values.
    fn key(&self) -> CandidateKey {
        let mut ids = Vec::with_capacity(self.goals.len() + self.tags.len() + self.attrs.len() + 2);
        ids.extend_from_slice(&self.goals);
        ids.push(u32::MAX);
        ids.extend_from_slice(&self.tags);
        ids.push(u32::MAX);
        ids.extend(self.attrs.iter().map(|(a, _)| *a));
        CandidateKey {
            grammar: self.grammar,
            ids: ids.into_boxed_slice(),
        }
    }
}

/// The compiled predicates and effects of one goal rule.
#[derive(Debug, Default)]
pub(crate) struct GoalRule {
    pub grammar: GrammarId,
    /// Goals the shape must have open (fulfilled ones and `goal(…)`), sorted.
    pub goals: Vec<GoalId>,
    /// Goals turned into tags on every shape the rule makes.
    pub fulfills: Vec<GoalId>,
    /// Goals added to every shape the rule makes.
    pub adds: Vec<GoalId>,
    /// Tags the shape must have.
    pub tags: Vec<GoalId>,
    /// Attributes the shape must have (`has(…)`, and every attribute the rule reads).
    pub attrs: Vec<AttrId>,
    /// `!goal(…)`, `!is(…)`, `!has(…)`: sets of which the shape must lack at least one member.
    pub not_goals: Vec<Vec<GoalId>>,
    pub not_tags: Vec<Vec<GoalId>>,
    pub not_attrs: Vec<Vec<AttrId>>,
    /// `if(…)` (true) and `!if(…)` (false) conditions.
    pub conditions: Vec<(CExpr, bool)>,
    /// Relative chance among the candidates (`@Weight(w)`; 1 by default).
    pub weight: f64,
    /// The rule's head, for messages.
    pub span: Span,
}

impl GoalRule {
    /// Whether the goal, tag and attribute predicates hold for `s` (conditions aside).
    fn admits(&self, s: &Semantics) -> bool {
        s.has_goals(&self.goals)
            && s.has_tags(&self.tags)
            && s.has_attrs(&self.attrs)
            && self.not_goals.iter().all(|g| !s.has_goals(g))
            && self.not_tags.iter().all(|t| !s.has_tags(t))
            && self.not_attrs.iter().all(|a| !s.has_attrs(a))
    }
}

/// A shape a derivation starts from.
#[derive(Debug)]
pub(crate) struct Axiom {
    pub goals: Vec<GoalId>,
    /// A box of this size at the origin; `None` starts from each lot.
    pub size: Option<[CExpr; 3]>,
    /// The symbol its shape is named by (its first goal).
    pub symbol: Sym,
    pub grammar: GrammarId,
}

/// The goal rules of a library and what finds them.
#[derive(Debug, Default)]
pub(crate) struct GoalRules {
    pub goals: Vec<GoalName>,
    pub attributes: Vec<Arc<str>>,
    /// The grammars' names, by [`GrammarId`].
    pub grammars: Vec<String>,
    /// The first grammar that came from a repository rather than the user's own files (the
    /// library's grammars from here on), when any did: their rules are tried last.
    pub repository_from: Option<GrammarId>,
    /// By [`RuleId`]: every rule of a goal program is a goal rule.
    pub rules: Vec<GoalRule>,
    pub axioms: Vec<Axiom>,
    /// The symbol each goal names a shape by, when it is the goal a successor adds first.
    pub goal_symbols: Vec<Sym>,
    /// Rules by the first goal they need open.
    by_goal: FxHashMap<GoalId, Vec<RuleId>>,
    /// Rules that need no goal open (they match any shape with open goals).
    unkeyed: Vec<RuleId>,
    /// Synchronizations, by their index: their names, for messages.
    pub syncs: Vec<Arc<str>>,
    /// By [`RuleId`]: what applying the rule does to the shape's semantics, packed apart from
    /// the predicates, since that is all a step reads of a rule besides its body.
    effects: Vec<Effects>,
}

/// What applying a rule does to semantics: its grammar, and the goals it fulfils and adds,
/// inline when there are few of them (the rule's own lists otherwise).
#[derive(Clone, Copy, Debug, Default)]
struct Effects {
    grammar: GrammarId,
    /// How many of `inline` are fulfilled goals and how many added ones; `u8::MAX` for
    /// fulfilled goals when the rule has more than `inline` holds.
    fulfills: u8,
    adds: u8,
    inline: [GoalId; 6],
}

impl GoalRules {
    /// Indexes the rules by goal; call once all rules are in.
    pub fn index(&mut self) {
        self.effects = self
            .rules
            .iter()
            .map(|rule| {
                let mut effects = Effects {
                    grammar: rule.grammar,
                    fulfills: u8::MAX,
                    ..Effects::default()
                };
                let (f, a) = (rule.fulfills.len(), rule.adds.len());
                if f + a <= effects.inline.len() {
                    effects.fulfills = f as u8;
                    effects.adds = a as u8;
                    effects.inline[..f].copy_from_slice(&rule.fulfills);
                    effects.inline[f..f + a].copy_from_slice(&rule.adds);
                }
                effects
            })
            .collect();
        self.by_goal.clear();
        self.unkeyed.clear();
        for (i, rule) in self.rules.iter().enumerate() {
            match rule.goals.first() {
                Some(g) => self.by_goal.entry(*g).or_default().push(i as RuleId),
                None => self.unkeyed.push(i as RuleId),
            }
        }
    }

    /// The rules whose goal, tag and attribute predicates hold for `s`, in tiers (see
    /// [`Candidates`]), each in rule order.
    fn candidates(&self, s: &Semantics) -> Candidates {
        let mut found: Vec<RuleId> = s
            .goals
            .iter()
            .filter_map(|g| self.by_goal.get(g))
            .flatten()
            .chain(&self.unkeyed)
            .copied()
            .filter(|&r| self.rules[r as usize].admits(s))
            .collect();
        found.sort_unstable();
        let mut tiers: [Vec<RuleId>; TIERS] = Default::default();
        for r in found {
            let grammar = self.rules[r as usize].grammar;
            let tier = if grammar == MAIN {
                0
            } else if grammar == s.grammar {
                1
            } else if self.repository_from.is_some_and(|first| grammar >= first) {
                3
            } else {
                2
            };
            tiers[tier].push(r);
        }
        let weights = tiers.each_ref().map(|list| {
            let uniform = list.iter().all(|&r| self.rules[r as usize].weight == 1.0);
            if uniform {
                return Vec::new();
            }
            let mut total = 0.0;
            list.iter()
                .map(|&r| {
                    total += self.rules[r as usize].weight;
                    total
                })
                .collect()
        });
        let conditional = tiers.each_ref().map(|list| {
            list.iter()
                .any(|&r| !self.rules[r as usize].conditions.is_empty())
        });
        Candidates {
            tiers,
            weights,
            conditional,
        }
    }

    /// Applies rule `rule` to semantics: its fulfilled goals become tags, its added goals open,
    /// and the shape joins the rule's grammar.
    pub fn apply(&self, rule: RuleId, s: &mut Semantics) {
        let effects = &self.effects[rule as usize];
        if effects.fulfills == u8::MAX {
            let rule = &self.rules[rule as usize];
            s.fulfil(&rule.fulfills);
            s.open(&rule.adds);
        } else {
            let (f, a) = (usize::from(effects.fulfills), usize::from(effects.adds));
            s.fulfil(&effects.inline[..f]);
            s.open(&effects.inline[f..f + a]);
        }
        s.grammar = effects.grammar;
    }

    /// The grammar of a rule.
    pub fn grammar_of(&self, rule: RuleId) -> GrammarId {
        self.effects[rule as usize].grammar
    }

    /// A goal's name as users write it (local goals with their grammar).
    pub fn goal_name(&self, goal: GoalId) -> String {
        let g = &self.goals[goal as usize];
        match g.local {
            Some(grammar) => format!("{} (local to {})", g.name, self.grammars[grammar as usize]),
            None => g.name.to_string(),
        }
    }
}

/// The grammar being derived: the first of a library.
pub(crate) const MAIN: GrammarId = 0;

/// How many tiers [`Candidates`] has.
pub(crate) const TIERS: usize = 4;

/// The rules that may rewrite a shape, before their conditions are evaluated, in the order they
/// are tried: the rules of the grammar being derived (so that it overrides what the library
/// does, as the paper's metallic support overrides the chair's), then those of the grammar of
/// the rule that made the shape (so that a design stays together), then the rest of the user's
/// library, then grammars from a repository (local rules first, as the paper's cloud lookup).
#[derive(Debug, Default)]
pub(crate) struct Candidates {
    tiers: [Vec<RuleId>; TIERS],
    /// Each tier's weights, summed up to each rule; empty when they are all 1.
    weights: [Vec<f64>; TIERS],
    /// Whether any rule of the tier has `if` conditions.
    conditional: [bool; TIERS],
}

/// The rules of one tier of [`Candidates`].
pub(crate) struct Tier<'a> {
    pub rules: &'a [RuleId],
    /// Their weights, summed up to each rule; empty when they are all 1.
    pub cumulative: &'a [f64],
    /// Whether any of them has `if` conditions.
    pub conditional: bool,
}

impl Tier<'_> {
    /// The index of the rule a uniform draw `x` in `0..1` picks, by weight.
    pub fn pick(&self, x: f64) -> usize {
        let n = self.rules.len();
        match self.cumulative.last() {
            None => ((x * n as f64) as usize).min(n - 1),
            Some(total) => self
                .cumulative
                .partition_point(|&c| c <= x * total)
                .min(n - 1),
        }
    }
}

impl Candidates {
    /// Tier `tier` (`0..TIERS`).
    pub fn tier(&self, tier: usize) -> Tier<'_> {
        Tier {
            rules: &self.tiers[tier],
            cumulative: &self.weights[tier],
            conditional: self.conditional[tier],
        }
    }
}

/// What candidates are found by: a shape's grammar, goals, tags and attribute names.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct CandidateKey {
    grammar: GrammarId,
    ids: Box<[u32]>,
}

/// Candidates found so far, by semantics: most shapes of a derivation share the semantics of
/// many others.
#[derive(Debug, Default)]
pub(crate) struct CandidateCache {
    found: FxHashMap<CandidateKey, Arc<Candidates>>,
    /// Semantics for which no rule applied: their shapes kept goals open.
    unmatched: FxHashSet<CandidateKey>,
}

impl CandidateCache {
    /// The candidates for `s`.
    pub fn get(&mut self, rules: &GoalRules, s: &Semantics) -> Arc<Candidates> {
        self.found
            .entry(s.key())
            .or_insert_with(|| Arc::new(rules.candidates(s)))
            .clone()
    }
}

/// What a shape sought rules for, by name: its open goals, its tags and the names of its
/// attributes, without the goals local to a grammar (no other grammar's rule can fulfil or ask
/// for them).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GoalQuery {
    /// Open goals, by name, sorted.
    pub goals: Vec<Arc<str>>,
    /// Tags, by name, sorted.
    pub tags: Vec<Arc<str>>,
    /// Attribute names, sorted.
    pub attributes: Vec<Arc<str>>,
}

impl CandidateCache {
    /// Notes that no rule applied to a shape with semantics `s`.
    pub fn miss(&mut self, s: &Semantics) {
        self.unmatched.insert(s.key());
    }

    /// What the shapes that found (or missed) their candidates here sought: one query per
    /// distinct semantics with a global goal open.
    pub fn queries(&self, rules: &GoalRules) -> Vec<GoalQuery> {
        sorted_queries(rules, self.found.keys())
    }

    /// What the shapes that no rule applied to sought (see [`CandidateCache::queries`]).
    pub fn unmatched(&self, rules: &GoalRules) -> Vec<GoalQuery> {
        sorted_queries(rules, self.unmatched.iter())
    }
}

/// The distinct queries of candidate keys, sorted.
fn sorted_queries<'k>(
    rules: &GoalRules,
    keys: impl Iterator<Item = &'k CandidateKey>,
) -> Vec<GoalQuery> {
    let mut queries: Vec<GoalQuery> = keys.filter_map(|key| query(rules, key)).collect();
    queries.sort();
    queries.dedup();
    queries
}

/// A key's query, by name; `None` when it has no global goal open.
fn query(rules: &GoalRules, key: &CandidateKey) -> Option<GoalQuery> {
    let mut parts = key.ids.split(|&id| id == u32::MAX);
    let global = |ids: &[GoalId]| -> Vec<Arc<str>> {
        let mut names: Vec<Arc<str>> = ids
            .iter()
            .map(|&g| &rules.goals[g as usize])
            .filter(|g| g.local.is_none())
            .map(|g| g.name.clone())
            .collect();
        names.sort();
        names
    };
    let goals = global(parts.next()?);
    let tags = global(parts.next()?);
    let mut attributes: Vec<Arc<str>> = parts
        .next()?
        .iter()
        .map(|&a| rules.attributes[a as usize].clone())
        .collect();
    attributes.sort();
    (!goals.is_empty()).then_some(GoalQuery {
        goals,
        tags,
        attributes,
    })
}

/// A leaf's goals, tags and attributes, by name: what outputs carry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LeafSemantics {
    /// Goals no rule fulfilled, in the order of the library's goals.
    pub goals: Vec<Arc<str>>,
    /// Goals fulfilled.
    pub tags: Vec<Arc<str>>,
    /// Named attributes.
    pub attributes: Vec<(Arc<str>, Value)>,
}

impl LeafSemantics {
    /// The names of `s`.
    pub(crate) fn of(rules: &GoalRules, s: &Semantics) -> Self {
        let name = |g: &GoalId| rules.goals[*g as usize].name.clone();
        Self {
            goals: s.goals.iter().map(name).collect(),
            tags: s.tags.iter().map(name).collect(),
            attributes: s
                .attrs
                .iter()
                .map(|(a, v)| (rules.attributes[*a as usize].clone(), v.clone()))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fulfilled_goals_become_tags_and_reopened_ones_stop_being_tags() {
        let mut s = Semantics {
            goals: vec![1, 4],
            ..Semantics::default()
        };
        s.fulfil(&[4]);
        assert_eq!(
            (s.goals.as_slice(), s.tags.as_slice()),
            (&[1][..], &[4][..])
        );
        s.open(&[4, 2]);
        assert_eq!(
            (s.goals.as_slice(), s.tags.as_slice()),
            (&[1, 2, 4][..], &[][..])
        );
    }

    #[test]
    fn negated_predicates_ask_that_not_all_members_hold() {
        let rule = GoalRule {
            goals: vec![1],
            not_tags: vec![vec![7, 8]],
            ..GoalRule::default()
        };
        let mut s = Semantics {
            goals: vec![1],
            tags: vec![7],
            ..Semantics::default()
        };
        assert!(rule.admits(&s));
        s.tags.push(8);
        assert!(!rule.admits(&s));
    }
}
