//! The engine of one lot: the machine's state, its work queue (depth first or in generations),
//! rule bodies and statements, the limits, and where new shapes and leaves go.

use std::rc::Rc;
use std::sync::Arc;
use std::time::Instant;

use shapegram_geom::Scope;
use shapegram_syntax::Span;

use super::derive::Batch;
use super::footprint::{SetbackOutputs, footprint, reverse_normals};
use super::implicit::implicit;
use super::insert::trim;
use super::kinematics::LastRotation;
use super::palette::{Paint, Palette};
use super::reuse::Previous;
use super::scope::{align_to_axes, align_to_bbox, center};
use super::split::Layouts;
use super::statements::Cursor;
use super::trace::Recorder;
use super::{DeriveOptions, Fallible, Leaf, LeafExtras, Symbol, TreeNode, push_leaf};
use crate::context::{Occluder, Parked, SnapPlane};
use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::goals::{CandidateCache, LeafSemantics, Semantics};
use crate::ops::Op;
use crate::program::{CBody, CExpr, CStmt, Program, RuleId, Sym};
use crate::shape::{Geometry, State};
use crate::texturing::COLORMAP;
use crate::value::Value;
use rustc_hash::FxHashMap;

/// One shape waiting for its rule.
pub(super) struct Task {
    pub(super) state: Box<State>,
    pub(super) rule: RuleId,
    pub(super) args: Vec<Value>,
}

/// What a rule application leaves behind, in order: shapes to rewrite and finished leaves.
/// Keeping both in one list makes the leaves come out in depth-first order of the tree.
pub(super) enum Work {
    Rewrite(Task),
    Leaf(Box<State>),
}

/// Which phase of a derivation the engine runs (see [`crate::context`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Phase {
    /// The grammar has no context rules: a single phase.
    Only,
    /// Phase 1: shapes with context rules wait; occluders and snap planes are recorded.
    Gather,
    /// Phase 2: the waiting shapes derive, asking about the shapes of phase 1.
    Answer,
}

/// The engine deriving one lot: the program, the evaluator with the lot's constants, what the
/// lot made so far and the limits it counts against.
pub(super) struct Engine<'p> {
    pub(super) program: &'p Program,
    pub(super) ev: Evaluator<'p>,
    pub(super) names: &'p [Arc<str>],
    pub(super) options: &'p DeriveOptions,
    pub(super) tree: Option<Vec<TreeNode>>,
    pub(super) leaves: Vec<Leaf>,
    /// The paints of the batch's leaves.
    pub(super) palette: Palette,
    /// The tree node of each of the lot's reports (`ev.reports`), when there is a tree.
    pub(super) report_nodes: Vec<u32>,
    pub(super) counts: Vec<usize>,
    /// Rule applications so far; the clock is read every 1024 of them.
    pub(super) applications: usize,
    /// How many successors the rule being applied has named so far (`getTreeKey`).
    pub(super) successors: u32,
    pub(super) shapes: usize,
    started: Instant,
    /// Where the outputs of the rule being applied start on the depth-first stack: while none
    /// is there, a new leaf is next in depth-first order and goes straight to `leaves`.
    /// `usize::MAX` when rewriting in generations.
    pub(super) base: usize,
    /// Split layouts to reuse (splits nest, so there can be several in use).
    pub(super) layouts: Layouts<'p>,
    /// Allocations of rewritten shapes, for the next shapes that wait for their rules (the
    /// boxes themselves are what is kept).
    #[allow(clippy::vec_box)]
    spare: Vec<Box<State>>,
    pub(super) phase: Phase,
    /// The rule being applied: the files it names are looked for beside its own file first.
    pub(super) rule: crate::RuleId,
    /// The generation being rewritten (generations mode).
    generation: u32,
    /// Shapes of this lot waiting for phase 2 (phase 1 only).
    pub(super) parked: Vec<Parked>,
    /// Occluders recorded in phase 1, numbered within the batch.
    pub(super) occluders: Vec<Occluder>,
    /// Snap planes recorded in phase 1.
    pub(super) snaps: Vec<SnapPlane>,
    /// The lot's kinematic skeleton, when the grammar builds one.
    pub(super) skeleton: Option<shapegram_kinematics::Skeleton>,
    /// What the lot records for deriving it again, when the derivation keeps a trace.
    pub(super) recorder: Option<Recorder>,
    /// The lot's previous derivation, when deriving it again.
    pub(super) previous: Option<Previous<'p>>,
    /// The rotation joints took last (see [`LastRotation`]).
    pub(super) last_rotation: LastRotation,
    /// Goal grammars: the rules found so far for each distinct semantics.
    pub(super) goal_cache: CandidateCache,
    /// Goal grammars: each synchronization's random seed (the first member's).
    pub(super) syncs: FxHashMap<u32, u64>,
    /// Goal grammars: the last leaf's semantics and their names.
    pub(super) last_semantics: Option<(Arc<Semantics>, Arc<LeafSemantics>)>,
    /// The attribute values the last tree node got, and the shape values they were copied
    /// from: shapes share their values until a `set`, so nodes share them too.
    node_attrs: Option<NodeAttrs>,
    /// The initial shape's scope and geometry, for `resetGeometry`.
    pub(super) initial: Option<(Scope, Geometry)>,
}

/// A shape's attribute values and the copy of them its tree node kept.
type NodeAttrs = (Rc<Vec<Value>>, Arc<[Value]>);

impl<'p> Engine<'p> {
    /// An engine deriving into the lists of `batch` (taken from it until [`Engine::finish`]).
    pub(super) fn new(
        program: &'p Program,
        ev: Evaluator<'p>,
        names: &'p [Arc<str>],
        options: &'p DeriveOptions,
        phase: Phase,
        batch: &mut Batch,
    ) -> Self {
        Self {
            program,
            ev,
            names,
            options,
            tree: options.keep_tree.then(|| std::mem::take(&mut batch.tree)),
            leaves: std::mem::take(&mut batch.leaves),
            palette: std::mem::take(&mut batch.palette),
            report_nodes: Vec::new(),
            counts: vec![0; program.rules.len()],
            applications: 0,
            successors: 0,
            shapes: 0,
            started: Instant::now(),
            rule: 0,
            base: usize::MAX,
            layouts: Layouts::default(),
            spare: Vec::new(),
            phase,
            generation: 0,
            parked: Vec::new(),
            occluders: std::mem::take(&mut batch.occluders),
            snaps: Vec::new(),
            skeleton: None,
            recorder: None,
            previous: None,
            last_rotation: LastRotation::default(),
            goal_cache: CandidateCache::default(),
            syncs: FxHashMap::default(),
            last_semantics: None,
            node_attrs: None,
            initial: None,
        }
    }

    /// A shape's attribute values as its tree node keeps them.
    pub(super) fn node_attrs(&mut self, attrs: &Rc<Vec<Value>>) -> Arc<[Value]> {
        if let Some((source, kept)) = &self.node_attrs
            && Rc::ptr_eq(source, attrs)
        {
            return kept.clone();
        }
        let kept: Arc<[Value]> = Arc::from(attrs.as_slice());
        self.node_attrs = Some((attrs.clone(), kept.clone()));
        kept
    }

    /// Hands the results back to the batch.
    pub(super) fn finish(mut self, batch: &mut Batch) {
        if let Some(mut recorder) = self.recorder.take() {
            recorder.trace.consts = self.ev.const_log.take().unwrap_or_default();
            batch.traces.push(recorder.trace);
        }
        if let Some(previous) = &self.previous {
            batch.reused += previous.reused;
        }
        batch.leaves = self.leaves;
        batch.palette = self.palette;
        batch.tree = self.tree.unwrap_or_default();
        batch.reports.extend(self.ev.reports);
        batch.report_nodes.extend(self.report_nodes);
        batch.prints.extend(self.ev.prints);
        batch.print_lots.extend(self.ev.print_lots);
        batch.shapes += self.shapes;
        for (c, n) in batch.counts.iter_mut().zip(&self.counts) {
            *c += n;
        }
        batch.occluders = self.occluders;
        batch.snaps.extend(self.snaps);
        if let Some(skeleton) = self.skeleton {
            batch.skeleton_room = batch.skeleton_room.max(skeleton.len());
            batch.skeletons.push((self.ev.lot, skeleton));
        }
    }

    /// Derives `first` and all that comes of it, depth first: leaves in depth-first order.
    pub(super) fn run_depth_first(&mut self, first: Work) -> Fallible<()> {
        let mut stack = vec![first];
        let tracing = self.recorder.is_some() || self.previous.is_some();
        loop {
            if tracing {
                // Subtrees end when the stack is back where it was below their shapes.
                self.close_applications(stack.len());
                self.leave_fresh(stack.len());
            }
            let Some(work) = stack.pop() else {
                break;
            };
            match work {
                Work::Leaf(mut state) => self.emit(&mut state),
                Work::Rewrite(task) => {
                    let base = stack.len();
                    if tracing {
                        if self.reuse(&task, base)? {
                            continue;
                        }
                        self.open_application(&task, base);
                    }
                    self.base = base;
                    self.apply(task, &mut stack)?;
                    // Reversed, so the first child is derived first.
                    stack[base..].reverse();
                }
            }
        }
        self.base = usize::MAX;
        Ok(())
    }

    /// Derives `first` in parallel generations (every shape of one generation rewritten
    /// before the next), stopping after `generations` of them.
    pub(super) fn run_generations(&mut self, first: Work, generations: u32) -> Fallible<()> {
        let mut current = vec![first];
        for generation in 0..generations {
            self.generation = generation;
            let mut next = Vec::new();
            for work in current {
                match work {
                    Work::Leaf(state) => next.push(Work::Leaf(state)),
                    Work::Rewrite(task) => self.apply(task, &mut next)?,
                }
            }
            current = next;
            if !current.iter().any(|w| matches!(w, Work::Rewrite(_))) {
                break;
            }
        }
        // Shapes still waiting for their rule when the generations run out are leaves too.
        for work in current {
            match work {
                Work::Leaf(mut state) | Work::Rewrite(Task { mut state, .. }) => {
                    self.emit(&mut state)
                }
            }
        }
        Ok(())
    }

    /// Records in the tree (when kept) that `task`'s rule rewrote its shape.
    pub(super) fn note_rule(&mut self, task: &Task) {
        if let Some(node) = self
            .tree
            .as_mut()
            .and_then(|tree| tree.get_mut(task.state.node as usize))
        {
            node.rule = Some(task.rule);
        }
    }

    /// Applies a shape's rule; new shapes waiting for rules go to `out`, in order.
    pub(super) fn apply(&mut self, mut task: Task, out: &mut Vec<Work>) -> Fallible<()> {
        if self.phase == Phase::Gather && self.program.context_rules[task.rule as usize] {
            self.parked.push(Parked {
                generation: self.generation,
                rule: task.rule,
                args: task.args,
                state: (*task.state).freeze(),
            });
            return Ok(());
        }
        self.counts[task.rule as usize] += 1;
        self.applications += 1;
        self.successors = 0;
        self.note_rule(&task);
        if self
            .applications
            .is_multiple_of(super::control::CHECK_EVERY as usize)
        {
            self.check_time(task.rule)?;
        }
        if self.applications > self.options.max_steps {
            return Err(self.too_many_steps(&task.state, task.rule));
        }
        let program = self.program;
        self.rule = task.rule;
        if let Some(goals) = &program.goals {
            self.enter_goal_rule(&mut task.state, task.rule);
            let grammar = goals.grammar_of(task.rule);
            let body = &program.rules[task.rule as usize].body;
            return self
                .run_body(body, &mut task.state, &task.args, out)
                .map_err(|e| e.in_file(grammar));
        }
        let mut result = self.run_body(
            &program.rules[task.rule as usize].body,
            &mut task.state,
            &task.args,
            out,
        );
        if let Some(origins) = &program.origins {
            result = result.map_err(|e| e.in_file(origins.rules[task.rule as usize]));
        }
        if self.spare.len() < 64 {
            // Only the allocation is kept: no need to hold on to a mesh.
            task.state.geometry = Geometry::Empty;
            self.spare.push(task.state);
        }
        result
    }

    fn run_body(
        &mut self,
        body: &'p CBody,
        state: &mut State,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let stmts = self.branch_of(body, state, args)?;
        self.run_stmts(stmts, state, args, out)
    }

    /// The statements of the branch of `body` that `case` and percentage arms choose for the
    /// shape (drawing from its random stream for the percentages).
    fn branch_of(
        &mut self,
        mut body: &'p CBody,
        state: &mut State,
        args: &[Value],
    ) -> Fallible<&'p [CStmt]> {
        loop {
            body = match body {
                CBody::Sequence(stmts) => return Ok(stmts),
                CBody::Cases(arms, otherwise) => {
                    let mut chosen = &**otherwise;
                    for (cond, branch) in arms {
                        if self.ev.condition(cond, state, args)? {
                            chosen = branch;
                            break;
                        }
                    }
                    chosen
                }
                CBody::Stochastic(arms, otherwise) => {
                    let draw = state.rng.next_f64() * 100.0;
                    let mut acc = 0.0;
                    let mut chosen = &**otherwise;
                    for (percent, branch) in arms {
                        acc += self.ev.number(percent, state, args)?;
                        if draw < acc {
                            chosen = branch;
                            break;
                        }
                    }
                    chosen
                }
            };
        }
    }

    /// Runs statements on a shape. A shape that made no successors and no parts, and was not
    /// deleted, is a leaf. The shape is used up: what is left of it afterwards is to be dropped.
    pub(super) fn run_stmts(
        &mut self,
        stmts: &'p [CStmt],
        state: &mut State,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let mut produced = false;
        // What `center` centres in: the scope the statements started with, or the last pushed
        // (only kept when a `center` needs it).
        let centers = stmts
            .iter()
            .any(|s| matches!(s, CStmt::Op(Op::Center(_), _) | CStmt::Branch(_)));
        let mut anchor = if centers {
            state.scope
        } else {
            Scope::default()
        };
        let mut saved: Vec<(State, Scope)> = Vec::new();
        let mut cursor = Cursor::new(stmts);
        while let Some(stmt) = cursor.next() {
            let last = cursor.at_end();
            match stmt {
                CStmt::Branch(body) => {
                    let chosen = self.branch_of(body, state, args)?;
                    cursor.enter(chosen);
                }
                CStmt::Push => {
                    saved.push((state.clone(), anchor));
                    anchor = state.scope;
                }
                CStmt::Pop(span) => {
                    let Some((mut restored, outer)) = saved.pop() else {
                        return Err(DeriveError::at("`]` without a matching `[`", *span));
                    };
                    // The shape's identity goes on: children made inside the brackets keep
                    // their seeds distinct from those made after.
                    restored.children = state.children;
                    restored.rng = state.rng.clone();
                    *state = restored;
                    anchor = outer;
                }
                // Inside brackets, `NIL` deletes the pushed copy: the statements up to the
                // matching `]` are skipped (`[ case c: Lamp else: NIL ] Base` makes the base).
                CStmt::Nil if !saved.is_empty() => cursor.skip_to_pop(),
                CStmt::Nil => return Ok(()),
                CStmt::Successor {
                    symbol,
                    rule,
                    args: exprs,
                    terminal,
                    span,
                } => {
                    let values = if exprs.is_empty() {
                        Vec::new()
                    } else {
                        exprs
                            .iter()
                            .map(|e| self.ev.eval(e, state, args))
                            .collect::<Fallible<Vec<_>>>()?
                    };
                    let rule = rule.filter(|_| !terminal);
                    if last {
                        // A successor that ends the statements takes the shape itself.
                        state.make_child();
                        return self.successor(state, *symbol, rule, values, *span, out);
                    }
                    let mut child = state.spawn();
                    self.successor(&mut child, *symbol, rule, values, *span, out)?;
                    produced = true;
                }
                CStmt::Op(op, span) => {
                    produced |= self.op(op, *span, state, &anchor, args, out)?;
                }
                CStmt::Goals {
                    goals,
                    symbol,
                    span,
                } => {
                    let goals = goals.as_slice();
                    if last {
                        state.make_child();
                        return self.goal_successor(state, goals, *symbol, *span, out);
                    }
                    let mut child = state.spawn();
                    self.goal_successor(&mut child, goals, *symbol, *span, out)?;
                    produced = true;
                }
            }
        }
        if !produced {
            if self.program.goals.is_some() {
                // The shape goes on towards its goals.
                return self.seek(state, out);
            }
            self.leaf(state, out);
        }
        Ok(())
    }

    /// Counts a new shape against the limits and enters it in the derivation tree. The shape
    /// still carries its parent's node number, which becomes its parent link.
    pub(super) fn admit(&mut self, state: &mut State, span: Span) -> Fallible<()> {
        if self.tree.is_some() {
            let attrs = self.node_attrs(&state.attrs);
            let tree = self.tree.as_mut().expect("checked above");
            tree.push(TreeNode {
                name: self.names[state.symbol as usize].clone(),
                parent: Some(state.node),
                scope: state.scope,
                lot: self.ev.lot,
                section: state.section,
                attrs,
                rule: None,
            });
            state.node = (tree.len() - 1) as u32;
        }
        self.count(state.depth, state.symbol, span)
    }

    /// Counts a new shape of the given depth and symbol against the limits.
    #[inline]
    pub(super) fn count(&mut self, depth: u32, symbol: Sym, span: Span) -> Fallible<()> {
        self.shapes += 1;
        if self.shapes > self.options.max_shapes || depth > self.options.max_depth {
            return Err(self.over_limit(symbol, span));
        }
        Ok(())
    }

    /// The error of a shape past a limit (kept out of [`Engine::count`], which runs for every
    /// shape).
    #[cold]
    #[inline(never)]
    fn over_limit(&self, symbol: Sym, span: Span) -> DeriveError {
        if self.shapes > self.options.max_shapes {
            let rule = self.busiest_rule();
            return DeriveError::at(
                format!(
                    "the derivation made more than {} shapes; rule `{rule}` was applied most often",
                    self.options.max_shapes
                ),
                span,
            )
            .with_hint("a rule that keeps making successors needs a condition that ends it");
        }
        let name = self.program.symbol_name(symbol);
        if self.program.goals.is_some() {
            return DeriveError::at(
                format!(
                    "the derivation is more than {} shapes deep at `{name}`: goal rules keep making shapes whose goals call for them again",
                    self.options.max_depth
                ),
                span,
            )
            .with_hint("a goal that leads back to itself through rules needs a condition that ends it (`if(scope.sx > 1)`) or a rule that fulfils it without a successor");
        }
        DeriveError::at(
            format!(
                "the derivation is more than {} shapes deep at `{name}`: a rule keeps rewriting without end",
                self.options.max_depth
            ),
            span,
        )
        .with_hint("guard the recursion with `case …` on the scope size or a counter parameter")
    }

    fn busiest_rule(&self) -> &str {
        let (i, _) = self
            .counts
            .iter()
            .enumerate()
            .max_by_key(|&(i, n)| (*n, std::cmp::Reverse(i)))
            .unwrap_or((0, &0));
        self.program
            .rules
            .get(i)
            .map_or("?", |r| self.program.symbol_name(r.symbol))
    }

    fn check_time(&self, rule: RuleId) -> Fallible<()> {
        if let Some(control) = &self.options.control
            && control.tick()
        {
            return Err(DeriveError::general("the derivation was cancelled"));
        }
        if let Some(budget) = self.options.time_budget
            && self.started.elapsed() > budget
        {
            let name = self
                .program
                .symbol_name(self.program.rules[rule as usize].symbol);
            return Err(DeriveError::general(format!(
                "the derivation took longer than {budget:?} (last rule: `{name}`, busiest: `{}`)",
                self.busiest_rule()
            )));
        }
        Ok(())
    }

    /// A new shape for a successor symbol: rewritten later with its rule, or a leaf.
    fn successor(
        &mut self,
        state: &mut State,
        symbol: Sym,
        rule: Option<RuleId>,
        args: Vec<Value>,
        span: Span,
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        state.symbol = symbol;
        if self.program.tree_keys {
            state.tree_key = state
                .tree_key
                .iter()
                .copied()
                .chain([self.successors])
                .collect();
        }
        self.successors += 1;
        self.admit(state, span)?;
        match rule {
            Some(rule) => {
                let state = match self.spare.pop() {
                    Some(mut spare) => {
                        *spare = state.take();
                        spare
                    }
                    None => Box::new(state.take()),
                };
                out.push(Work::Rewrite(Task { state, rule, args }));
            }
            None => self.leaf(state, out),
        }
        Ok(())
    }

    /// A finished shape: a leaf now when it is next in depth-first order, else later. Takes
    /// what it needs from the state.
    pub(super) fn leaf(&mut self, state: &mut State, out: &mut Vec<Work>) {
        if out.len() == self.base {
            self.emit(state);
        } else {
            out.push(Work::Leaf(Box::new(state.take())));
        }
    }

    /// Adds a shape to the leaves (unless it has no geometry), taking its geometry.
    fn emit(&mut self, state: &mut State) {
        if matches!(state.geometry, Geometry::Empty) {
            return;
        }
        if self.phase == Phase::Gather {
            let occluder = Occluder::of(state, None, self.ev.lot);
            let occluder = self.posable(occluder, state.section, &state.scope, &state.geometry);
            self.occluders.extend(occluder);
        }
        let semantics = self.leaf_semantics(state);
        let extras = LeafExtras::of(
            state.material.take(),
            state.texturing.take(),
            state.section,
            semantics,
        );
        let paint = self.palette.id(Paint {
            color: state.color,
            painted: state.painted,
        });
        let geometry = std::mem::replace(&mut state.geometry, Geometry::Empty);
        let node = self.tree.is_some().then_some(state.node);
        let lot = self.ev.lot;
        push_leaf(&mut self.leaves, || {
            Leaf::new(
                Symbol(state.symbol),
                state.scope,
                geometry,
                paint,
                node,
                lot,
                extras,
            )
        });
    }

    /// Applies an operation: the family module of the operation does the work. Returns whether
    /// it made new shapes (splits), which ends the current shape's chance of becoming a leaf.
    fn op(
        &mut self,
        op: &'p Op,
        span: Span,
        state: &mut State,
        anchor: &Scope,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<bool> {
        match op {
            Op::Extrude { world_up, distance } => {
                self.extrude(state, *world_up, distance, span, args)?
            }
            Op::Translate(v) => self.translate(state, v, args)?,
            Op::Rotate {
                about_center,
                degrees,
            } => self.rotate(state, *about_center, degrees, args)?,
            Op::Size(v) => self.size(state, v, args)?,
            Op::Center(axes) => center(state, anchor, *axes),
            Op::Mirror(flags) => self.mirror(state, flags, args)?,
            Op::AlignScopeToAxes(axis) => align_to_axes(state, *axis),
            Op::AlignScopeToGeometry { z_up, face, edge } => {
                self.align_to_geometry(state, *z_up, face, edge, span, args)?
            }
            Op::AlignScopeToGeometryBBox { first, second } => align_to_bbox(state, *first, *second),
            Op::RotateScope(v) => self.rotate_scope(state, v, args)?,
            Op::MirrorScope(flags) => self.mirror_scope(state, flags, args)?,
            Op::SetPivot { up, corner } => self.set_pivot(state, *up, corner, args)?,
            Op::ResetGeometry => self.reset_geometry(state, span)?,
            Op::Insert(path, placement) => self.insert(state, path, *placement, args)?,
            Op::Primitive(kind, params) => self.primitive(state, *kind, params, span, args)?,
            Op::Scatter(spec) => {
                self.scatter(state, spec, span, args, out)?;
                return Ok(true);
            }
            Op::UvSplit {
                coordinate,
                metres,
                set,
                block,
            } => {
                let how = (*coordinate, *metres);
                self.uv_split(state, how, set, block, span, args, out)?;
                return Ok(true);
            }
            Op::Split {
                axis,
                by_area,
                adjust,
                snap,
                joints,
                block,
            } => {
                let how = (*adjust, *joints);
                if *by_area {
                    self.split_area(state, *axis, *adjust, block, span, args, out)?;
                } else {
                    self.split(state, *axis, how, snap.as_ref(), block, span, args, out)?;
                }
                return Ok(true);
            }
            Op::Snap { axes, tag } => self.snap(state, *axes, tag.as_ref(), args)?,
            Op::Label(name) => self.label(state, name, args)?,
            Op::Tag { name, target } => self.tag(state, name, *target, args)?,
            Op::DeleteTags { query, target } => {
                self.delete_tags(state, query.as_ref(), *target, args)?;
            }
            Op::Comp { kind, entries } => {
                self.comp(state, *kind, entries, span, args, out)?;
                return Ok(true);
            }
            Op::InnerRectangle {
                edge,
                shape,
                remainder,
                split,
            } => {
                let outputs = SetbackOutputs {
                    entries: &[],
                    shape: shape.as_ref(),
                    remainder: remainder.as_ref(),
                };
                self.inner_rectangle(state, *edge, outputs, *split, span, args, out)?;
                return Ok(*split);
            }
            Op::PerimeterSplit(spec) => {
                self.perimeter_split(state, spec, span, args, out)?;
                return Ok(true);
            }
            Op::Setback {
                depths,
                entries,
                shape,
                remainder,
            } => {
                let outputs = SetbackOutputs {
                    entries,
                    shape: shape.as_ref(),
                    remainder: remainder.as_ref(),
                };
                self.setback(state, depths, outputs, span, args, out)?;
                return Ok(true);
            }
            Op::Color(params) => {
                state.color = self.color(state, params, args)?;
                state.painted = true;
            }
            Op::ColorLiteral(color) => {
                state.color = *color;
                state.painted = true;
            }
            Op::Set(target, value) => self.set(state, target, value, args)?,
            Op::Reimport { attrs, overrides } => {
                let values = overrides
                    .iter()
                    .map(|(i, e)| Ok((*i, self.ev.eval(e, state, args)?)))
                    .collect::<Fallible<Vec<_>>>()?;
                self.ev.reset_attrs(state, attrs, &values)?;
            }
            Op::Report(key, value) => self.report(state, key, value, args)?,
            Op::Print(value) => self.print(state, value, args)?,
            Op::ReverseNormals => reverse_normals(state, span)?,
            Op::Trim => trim(state),
            Op::Envelope { world_up, params } => {
                self.envelope(state, *world_up, params, span, args)?
            }
            Op::Cleanup { what, tolerance } => self.cleanup(state, *what, tolerance, span, args)?,
            Op::Footprint => footprint(state, span)?,
            Op::Pyramid(height) => self.pyramid(state, height, span, args)?,
            Op::Transform {
                rotate,
                absolute,
                system,
                values,
            } => match rotate {
                true => self.rotate_in(state, *absolute, *system, values, args)?,
                false => self.translate_in(state, *absolute, *system, values, args)?,
            },
            Op::Convexify(max) => self.convexify(state, max.as_ref(), span, args)?,
            Op::Offset { distance, keep } => self.offset(state, distance, *keep, span, args)?,
            Op::Roof {
                kind,
                by_height,
                params,
            } => self.roof(state, *kind, *by_height, params, span, args)?,
            Op::Implicit(kind) => implicit(state, *kind, span)?,
            Op::ImplicitFile(path) => self.implicit_file(state, path, span, args)?,
            Op::Csg {
                kind,
                group,
                amount,
            } => self.csg(state, *kind, group, amount.as_ref(), span, args)?,
            Op::Boolean { kind, operands } => self.boolean(state, *kind, operands, span, args)?,
            Op::Inline { mode, body } => self.inline(state, *mode, body, span, args)?,
            Op::Joint(at) => self.place_joint(state, at, args)?,
            Op::JointLimits {
                rotation,
                axis,
                min,
                max,
            } => self.limit_joint(state, *rotation, *axis, (min, max), span, args)?,
            Op::JointPose { rotation, values } => {
                self.pose_joint(state, *rotation, values, span, args)?
            }
            Op::Deform { kind, axis, amount } => {
                self.deform(state, *kind, *axis, amount, span, args)?
            }
            Op::Sync(sync) => self.synchronize(state, *sync),
            Op::SetupProjection(setup) => self.setup_projection(state, setup, args)?,
            Op::ProjectUv(set) => self.project_uv(state, set, args)?,
            Op::Texture(path) => self.texture(state, COLORMAP, true, path, args)?,
            Op::EditUv(edit, params) => self.edit_uv(state, *edit, params, args)?,
            Op::Ignored => {}
        }
        Ok(false)
    }

    /// Evaluates operation arguments that must all be numbers.
    pub(super) fn numbers(
        &mut self,
        params: &[CExpr],
        state: &mut State,
        args: &[Value],
    ) -> Fallible<Vec<f64>> {
        params
            .iter()
            .map(|p| self.ev.number(p, state, args))
            .collect()
    }
}
