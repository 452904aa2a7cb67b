//! Goal grammars in the engine: shapes start from axioms, and whenever a shape's statements end
//! (or a `+goal` successor names new goals) the rules its semantics call for are sought (see
//! [`crate::goals`]). A shape no rule matches, or whose goals are all fulfilled, is a leaf with
//! the geometry it has.

use std::sync::Arc;

use shapegram_geom::{DMat3, DVec3, Scope};
use shapegram_syntax::Span;

use super::derive::{Batch, in_batches, initial_shape, rule_counts};
use super::machine::{Engine, Phase, Task, Work};
use super::{Derivation, DeriveOptions, Fallible, InitialShape, TreeNode};
use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::goals::{Candidates, GoalId, GoalRules, LeafSemantics, Semantics, TIERS, Tier};
use crate::program::{Program, RuleId, Sym};
use crate::rng::child_seed;
use crate::shape::{Geometry, State};
use crate::value::Value;

/// Space left between axioms of a given size, which stand side by side along x.
const AXIOM_GAP: f64 = 1.0;

/// Derives a goal grammar library: each axiom with a size is one box at the origin (the next
/// beside it along x), each axiom without one starts from every lot.
pub(super) fn run_goals(
    program: &Program,
    rules: &GoalRules,
    lots: &[InitialShape],
    options: &DeriveOptions,
) -> Result<Derivation, DeriveError> {
    if rules.axioms.is_empty() {
        return Err(DeriveError::general(format!(
            "the grammar `{}` has no axiom to start from",
            rules.grammars.first().map_or("", String::as_str)
        ))
        .with_hint("declare one: `axiom chair size(0.4, 0.8, 0.4)` (or `new Axiom(\"chair\").Size(0.4, 0.8, 0.4);`); a grammar without axioms serves others as their library"));
    }
    if let Some(rule) = &options.start_rule {
        return Err(DeriveError::general(format!(
            "goal grammars start from their axioms, not from a rule (`{rule}`)"
        ))
        .with_hint("declare the shapes to start from with `axiom goals size(x, y, z)`"));
    }
    if let Some(axiom) = rules.axioms.iter().find(|a| a.size.is_none())
        && lots.is_empty()
    {
        let goal = program.symbol_name(axiom.symbol);
        return Err(DeriveError::general(format!(
            "the axiom `{goal}` has no size, and there are no lots for it to start from"
        ))
        .with_hint("give it a size (`axiom … size(x, y, z)`) or derive it on lots"));
    }
    if !options.attrs.is_empty() {
        return Err(
            DeriveError::general("goal grammars have no attributes to set from outside")
                .with_hint("give the axiom's shapes attributes with a rule: `set(@name, value)`"),
        );
    }
    let starts: Vec<(usize, Option<usize>)> = rules
        .axioms
        .iter()
        .enumerate()
        .flat_map(|(a, axiom)| match axiom.size {
            Some(_) => vec![(a, None)],
            None => (0..lots.len()).map(|l| (a, Some(l))).collect(),
        })
        .collect();
    let names = program.symbol_names();
    // Boxes stand side by side: each one's x offset is known only after sizing those before it,
    // which is cheap, so they are sized first.
    let mut offsets = Vec::with_capacity(starts.len());
    let mut x = 0.0;
    for (i, &(a, lot)) in starts.iter().enumerate() {
        match (&rules.axioms[a].size, lot) {
            (Some(_), _) => {
                let size = axiom_size(program, rules, a, child_seed(options.seed, i as u64))?;
                offsets.push(Some((x, size)));
                x += size.x + AXIOM_GAP;
            }
            (None, _) => offsets.push(None),
        }
    }
    let batches = in_batches(program, starts.len(), None, |batch, i| {
        let (axiom, lot) = starts[i];
        let (scope, geometry) = match (offsets[i], lot) {
            (Some((x, size)), _) => (
                Scope {
                    origin: DVec3::new(x, 0.0, 0.0),
                    axes: DMat3::IDENTITY,
                    size,
                },
                Geometry::Box,
            ),
            (None, Some(l)) => initial_shape(&lots[l].footprint)?,
            (None, None) => unreachable!("an axiom without a size starts from a lot"),
        };
        let start = Start {
            axiom,
            index: i as u32,
            seed: child_seed(options.seed, i as u64),
            scope,
            geometry,
        };
        derive_axiom(program, rules, start, &names, options, batch)
    });
    let mut all = Derivation {
        names: names.clone(),
        ..Derivation::default()
    };
    let mut counts = vec![0usize; program.rules.len()];
    for batch in batches {
        all.absorb_batch(batch, &mut counts)?;
    }
    all.stats.leaves = all.leaves.len();
    all.stats.rules = rule_counts(program, &counts);
    all.stats.steps = counts.iter().sum();
    let mut per_grammar = vec![0usize; rules.grammars.len()];
    for (rule, n) in rules.rules.iter().zip(&counts) {
        per_grammar[rule.grammar as usize] += n;
    }
    all.stats.grammars = rules.grammars.iter().cloned().zip(per_grammar).collect();
    for list in [&mut all.queries, &mut all.unmatched] {
        list.sort();
        list.dedup();
    }
    Ok(all)
}

/// An axiom's size: its expressions evaluated with the random stream of its first shape.
fn axiom_size(
    program: &Program,
    rules: &GoalRules,
    axiom: usize,
    seed: u64,
) -> Result<DVec3, DeriveError> {
    let Some(exprs) = &rules.axioms[axiom].size else {
        return Ok(DVec3::ZERO);
    };
    let mut ev = Evaluator::new(program, seed, DVec3::ZERO);
    let mut state = State::initial(0, Scope::default(), Geometry::Box, seed);
    let mut size = DVec3::ZERO;
    for (i, e) in exprs.iter().enumerate() {
        let v = ev.number(e, &mut state, &[])?;
        if !(v.is_finite() && v >= 0.0) {
            return Err(DeriveError::at(
                format!("an axiom's size is a number of at least 0, not {v}"),
                e.span,
            )
            .in_file(rules.axioms[axiom].grammar));
        }
        size[i] = v;
    }
    Ok(size)
}

/// Where one derivation of an axiom starts.
struct Start {
    axiom: usize,
    index: u32,
    seed: u64,
    scope: Scope,
    geometry: Geometry,
}

fn derive_axiom(
    program: &Program,
    rules: &GoalRules,
    start: Start,
    names: &[Arc<str>],
    options: &DeriveOptions,
    batch: &mut Batch,
) -> Result<(), DeriveError> {
    let axiom = &rules.axioms[start.axiom];
    let mut state = State::initial(axiom.symbol, start.scope, start.geometry, start.seed);
    state.semantics = Some(Arc::new(Semantics {
        goals: axiom.goals.clone(),
        grammar: axiom.grammar,
        ..Semantics::default()
    }));
    let mut ev = Evaluator::new(program, start.seed, start.scope.origin);
    ev.object_axes = start.scope.axes;
    ev.assets = options.assets.as_deref();
    ev.lot = start.index;
    ev.lot_number = u64::from(start.index);
    let mut engine = Engine::new(program, ev, names, options, Phase::Only, batch);
    if engine.tree.is_some() {
        let attrs = engine.node_attrs(&state.attrs);
        let tree = engine.tree.as_mut().expect("checked above");
        state.node = tree.len() as u32;
        tree.push(TreeNode {
            name: names[axiom.symbol as usize].clone(),
            parent: None,
            scope: start.scope,
            lot: start.index,
            section: 0,
            attrs,
            rule: None,
        });
    }
    engine.shapes = 1;
    let mut first = Vec::with_capacity(1);
    engine.seek(&mut state, &mut first)?;
    if let Some(work) = first.pop() {
        match options.generations {
            Some(n) => engine.run_generations(work, n)?,
            None => engine.run_depth_first(work)?,
        }
    }
    batch.queries.extend(engine.goal_cache.queries(rules));
    batch.unmatched.extend(engine.goal_cache.unmatched(rules));
    engine.finish(batch);
    Ok(())
}

impl<'p> Engine<'p> {
    /// The library's goal rules (only called for goal programs).
    fn goal_rules(&self) -> &'p GoalRules {
        self.program
            .goals
            .as_deref()
            .expect("goal operations run in goal programs only")
    }

    /// Before a goal rule's body runs: its fulfilled goals become tags, its added goals open,
    /// and the shape (with all it makes) belongs to the rule's grammar.
    pub(super) fn enter_goal_rule(&self, state: &mut State, rule: RuleId) {
        let rules = self.goal_rules();
        rules.apply(rule, Arc::make_mut(state.semantics.get_or_insert_default()));
    }

    /// `+goal …`: the shape goes on with these goals open, as a new shape named `symbol`.
    pub(super) fn goal_successor(
        &mut self,
        state: &mut State,
        goals: &[GoalId],
        symbol: Sym,
        span: Span,
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        Arc::make_mut(state.semantics.get_or_insert_default()).open(goals);
        state.symbol = symbol;
        self.admit(state, span)?;
        self.seek(state, out)
    }

    /// A shape whose statements are done: rewritten next by a rule its goals call for, or a
    /// leaf when its goals are fulfilled or no rule matches.
    pub(super) fn seek(&mut self, state: &mut State, out: &mut Vec<Work>) -> Fallible<()> {
        let open = state
            .semantics
            .as_ref()
            .is_some_and(|s| !s.goals.is_empty());
        let rule = if open { self.choose(state)? } else { None };
        if open && rule.is_none() {
            let semantics = state.semantics.as_deref().expect("open goals");
            self.goal_cache.miss(semantics);
        }
        match rule {
            Some(rule) => {
                let state = Box::new(state.take());
                out.push(Work::Rewrite(Task {
                    state,
                    rule,
                    args: Vec::new(),
                }));
            }
            None => self.leaf(state, out),
        }
        Ok(())
    }

    /// The rule that rewrites a shape: drawn (by weight) from the first tier of candidates (see
    /// [`Candidates`]) with one whose conditions hold; `None` when there is none.
    fn choose(&mut self, state: &mut State) -> Fallible<Option<RuleId>> {
        let rules = self.goal_rules();
        let semantics = state.semantics.clone().unwrap_or_default();
        let candidates = self.goal_cache.get(rules, &semantics);
        for tier in 0..TIERS {
            if let Some(rule) = self.draw(&candidates, tier, state)? {
                return Ok(Some(rule));
            }
        }
        Ok(None)
    }

    /// A candidate of one tier whose conditions hold, drawn by weight among those that do. A
    /// few draws from the whole tier come first (a draw that holds is what drawing among the
    /// holding ones would give, and most do); after them every condition is evaluated once and
    /// one of the rules that hold is drawn.
    fn draw(
        &mut self,
        candidates: &Candidates,
        tier: usize,
        state: &mut State,
    ) -> Fallible<Option<RuleId>> {
        /// Draws from the whole tier before its conditions are evaluated all at once.
        const TRIES: usize = 4;
        let tier = candidates.tier(tier);
        let draw = |state: &mut State| match tier.rules.len() {
            1 => tier.rules[0],
            _ => tier.rules[tier.pick(state.rng.next_f64())],
        };
        if tier.rules.is_empty() {
            return Ok(None);
        }
        if !tier.conditional {
            return Ok(Some(draw(state)));
        }
        for _ in 0..TRIES {
            let rule = draw(state);
            if self.conditions_hold(rule, state)? {
                return Ok(Some(rule));
            }
        }
        let rules = self.goal_rules();
        let mut holding = Vec::new();
        let mut sums = Vec::new();
        let mut total = 0.0;
        for &rule in tier.rules {
            if self.conditions_hold(rule, state)? {
                total += rules.rules[rule as usize].weight;
                holding.push(rule);
                sums.push(total);
            }
        }
        let holding_tier = Tier {
            rules: &holding,
            cumulative: &sums,
            conditional: false,
        };
        Ok(match holding.len() {
            0 => None,
            1 => Some(holding[0]),
            _ => Some(holding[holding_tier.pick(state.rng.next_f64())]),
        })
    }

    /// Whether a rule's `if(…)` conditions hold for the shape.
    fn conditions_hold(&mut self, rule: RuleId, state: &mut State) -> Fallible<bool> {
        let goal_rule = &self.goal_rules().rules[rule as usize];
        for (condition, wanted) in &goal_rule.conditions {
            let holds = self
                .ev
                .condition(condition, state, &[])
                .map_err(|e| e.in_file(goal_rule.grammar))?;
            if holds != *wanted {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// `sync(s)`: the shape takes the random stream of the first shape that joined `s` in this
    /// derivation, so that it and its children choose the rules that one and its children did.
    pub(super) fn synchronize(&mut self, state: &mut State, sync: u32) {
        let seed = *self.syncs.entry(sync).or_insert(state.seed);
        state.synchronize(seed);
    }

    /// `set(@name, value)`.
    pub(super) fn set_goal_attr(&self, state: &mut State, attr: u32, value: Value) {
        Arc::make_mut(state.semantics.get_or_insert_default()).set(attr, value);
    }

    /// A leaf's semantics by name; consecutive leaves of one shape's parts share them.
    pub(super) fn leaf_semantics(&mut self, state: &State) -> Option<Arc<LeafSemantics>> {
        let semantics = state.semantics.as_ref()?;
        if let Some((last, named)) = &self.last_semantics
            && Arc::ptr_eq(last, semantics)
        {
            return Some(named.clone());
        }
        let named = Arc::new(LeafSemantics::of(self.goal_rules(), semantics));
        self.last_semantics = Some((semantics.clone(), named.clone()));
        Some(named)
    }

    /// The error of a derivation that took more than the allowed steps, naming what kept it
    /// going.
    pub(super) fn too_many_steps(&self, state: &State, rule: RuleId) -> DeriveError {
        let program = self.program;
        let name = program.symbol_name(program.rules[rule as usize].symbol);
        let Some(rules) = program.goals.as_deref() else {
            return DeriveError::general(format!(
                "the derivation took more than {} steps (rule `{name}` was applied last)",
                self.options.max_steps
            ))
            .with_hint("a rule that keeps making successors needs a condition that ends it");
        };
        let open: Vec<String> = state
            .semantics
            .iter()
            .flat_map(|s| &s.goals)
            .map(|g| format!("`{}`", rules.goal_name(*g)))
            .collect();
        let goal_rule = &rules.rules[rule as usize];
        DeriveError::at(
            format!(
                "the derivation took more than {} steps: goal {} kept being sought (rule `{name}` applied last)",
                self.options.max_steps,
                if open.is_empty() { "none".to_owned() } else { open.join(", ") },
            ),
            goal_rule.span,
        )
        .in_file(goal_rule.grammar)
        .with_hint("a rule that gives its shapes a goal it fulfils, itself or through other rules, needs a condition that ends it (`if(scope.sx > 1)`)")
        .with_hint("raise the limit with --max-steps if the model is just large")
    }
}
