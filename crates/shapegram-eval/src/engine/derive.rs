//! Deriving lots: the entry point [`derive()`], lots derived in batches (in parallel when there
//! are threads to spare), and the two phases of grammars with context rules.

use std::rc::Rc;
use std::sync::Arc;

use rayon::prelude::*;
use rustc_hash::FxHashMap;
use shapegram_geom::{DMat3, DVec3, Mesh, Scope, mesh::newell};
use shapegram_kinematics::{Frame, Name, Skeleton};

use super::machine::{Engine, Phase, Task, Work};
use super::palette::{self, Palette};
use super::reuse::{Old, Previous};
use super::trace::{LotTrace, finish_trace};
use super::{Derivation, DeriveOptions, GoalQuery, InitialShape, Leaf, TreeNode};
use crate::context::{Context, Occluder, SnapPlane, Waiting};
use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::program::{Program, RuleId};
use crate::rng::child_seed;
use crate::shape::{Geometry, NO_OCCLUDER, State, fills_box};
use crate::value::Value;

/// Derives a model from each initial shape, in parallel, and returns the results in order.
pub fn derive(
    program: &Program,
    lots: &[InitialShape],
    options: &DeriveOptions,
) -> Result<Derivation, DeriveError> {
    Ok(run(program, lots, options, None)?.0)
}

/// Derives, reusing what `old` derived with unchanged rules; returns the derivation and the
/// number of rule applications reused.
pub(super) fn run(
    program: &Program,
    lots: &[InitialShape],
    options: &DeriveOptions,
    old: Option<&Old>,
) -> Result<(Derivation, usize), DeriveError> {
    if let Some(goals) = &program.goals {
        return Ok((super::goals::run_goals(program, goals, lots, options)?, 0));
    }
    let start = start_rule(program, options)?;
    if let Some(cell) = options.implicit_cell
        && !(cell.is_finite() && cell > 0.0)
    {
        return Err(DeriveError::general(format!(
            "implicit cell size {cell}: expected a finite number above 0"
        )));
    }
    let overrides = overrides(program, options)?;
    let names = program.symbol_names();
    let phase = if program.context_rules.contains(&true) {
        Phase::Gather
    } else {
        Phase::Only
    };
    let lot_number = |i: usize| lots[i].index.unwrap_or(i as u64);
    let lot_seed = |i: usize| child_seed(options.seed, lot_number(i));
    // Only a depth-first derivation in one phase is recorded, or derived again.
    let traced = phase == Phase::Only && options.generations.is_none();
    let batches = in_batches(program, lots.len(), None, |batch, i| {
        let how = Lot {
            start,
            index: i as u32,
            number: lot_number(i),
            seed: lot_seed(i),
            overrides: &overrides,
            names: &names,
            phase,
            trace: options.trace && traced,
            previous: old.filter(|_| traced).and_then(|old| old.previous(i)),
        };
        derive_lot(program, &lots[i], how, options, batch)
    });
    let mut all = Derivation {
        names: names.clone(),
        ..Derivation::default()
    };
    // One batch (one thread) hands its leaves over as they are: room for them all would be a
    // second vector as large, allocated for nothing.
    if batches.len() > 1 {
        all.leaves
            .reserve_exact(batches.iter().map(|b| b.leaves.len()).sum());
    }
    let mut counts = vec![0usize; program.rules.len()];
    let mut gathered = Gathered::default();
    let mut traces = Vec::new();
    let mut reused = 0;
    for mut batch in batches {
        traces.append(&mut batch.traces);
        reused += batch.reused;
        all.absorb(batch, &mut counts, &mut gathered, false)?;
    }
    if options.trace && traced {
        all.trace = Some(finish_trace(traces, program, lots, options));
    }
    if !gathered.waiting.is_empty() {
        let motions = if program.kinematic {
            pose_context(&all.skeletons, &mut gathered)
        } else {
            Vec::new()
        };
        let context = Context::new(gathered.occluders, gathered.snaps, &names);
        // Each lot's waiting shapes are taken by the one batch that resumes that lot.
        let waiting: Vec<_> = gathered
            .waiting
            .into_iter()
            .map(|w| std::sync::Mutex::new(Some(w)))
            .collect();
        let resume = |batch: &mut Batch, i: usize| {
            let taken = waiting[i]
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .take();
            let Some(waiting) = taken else {
                return Ok(());
            };
            let lot = waiting.lot as usize;
            let numbered = (lot_number(lot), lot_seed(lot));
            let motions = motions.get(i).cloned().unwrap_or_default();
            resume_lot(
                program, waiting, motions, numbered, &names, options, &context, batch,
            )
        };
        // With a tree, phase 2 numbers its nodes after those of phase 1: one batch, in order.
        let tree = options.keep_tree.then(|| std::mem::take(&mut all.tree));
        for batch in in_batches(program, waiting.len(), tree, resume) {
            all.absorb(
                batch,
                &mut counts,
                &mut Gathered::default(),
                options.keep_tree,
            )?;
        }
        // Lots that waited for phase 2 hand in their skeletons after the others.
        all.skeletons.sort_by_key(|(lot, _)| *lot);
    }
    if all.stats.shapes > options.max_shapes {
        return Err(DeriveError::general(format!(
            "the derivation made more than {} shapes",
            options.max_shapes
        ))
        .with_hint("raise the limit (--max-shapes) or derive fewer initial shapes"));
    }
    all.stats.leaves = all.leaves.len();
    all.stats.rules = rule_counts(program, &counts);
    if program.solids {
        all.solids = crate::solids::mesh_solids(&all, options.implicit_cell, options.time_budget)?;
    }
    Ok((all, reused))
}

/// Runs `work` on the items `0..n` in batches of consecutive items, in parallel when there is
/// more than one thread and no `tree` to extend (then in one batch that starts with it); a batch
/// keeps the error of its first failing item and skips the items after it. Batches come back in
/// item order.
pub(super) fn in_batches(
    program: &Program,
    n: usize,
    tree: Option<Vec<TreeNode>>,
    work: impl Fn(&mut Batch, usize) -> Result<(), DeriveError> + Sync,
) -> Vec<Batch> {
    let step = |batch: &mut Batch, i: usize| {
        if batch.error.is_none()
            && let Err(e) = work(batch, i)
        {
            batch.error = Some(e);
        }
    };
    // Items derive into batches of consecutive items, so that leaves are not copied from one
    // vector per item into the result: on one thread there is a single batch.
    if n <= 1 || rayon::current_num_threads() == 1 || tree.is_some() {
        let mut batch = Batch::new(program);
        batch.tree = tree.unwrap_or_default();
        for i in 0..n {
            step(&mut batch, i);
            // Room for the items to come, estimated from those so far (only memory depends on
            // it).
            let done = i + 1;
            let estimate = batch.leaves.len() / done * (n - done);
            batch.leaves.reserve(estimate);
        }
        return vec![batch];
    }
    (0..n)
        .into_par_iter()
        .fold(
            || Batch::new(program),
            |mut batch, i| {
                step(&mut batch, i);
                batch
            },
        )
        .collect()
}

/// What phase 1 leaves for phase 2, numbered across all batches.
#[derive(Default)]
struct Gathered {
    waiting: Vec<Waiting>,
    occluders: Vec<Occluder>,
    snaps: Vec<SnapPlane>,
}

impl Derivation {
    /// Appends the results of a batch of lots derived in one phase.
    pub(super) fn absorb_batch(
        &mut self,
        batch: Batch,
        counts: &mut [usize],
    ) -> Result<(), DeriveError> {
        self.absorb(batch, counts, &mut Gathered::default(), false)
    }

    /// Appends a batch's results. Node numbers of the batch start after those already here,
    /// unless the batch `continues` the tree (it was handed the tree to extend).
    fn absorb(
        &mut self,
        mut batch: Batch,
        counts: &mut [usize],
        gathered: &mut Gathered,
        continues: bool,
    ) -> Result<(), DeriveError> {
        if let Some(e) = batch.error {
            return Err(e);
        }
        self.skeletons.append(&mut batch.skeletons);
        self.queries.append(&mut batch.queries);
        self.unmatched.append(&mut batch.unmatched);
        if let Some(map) = palette::merge(&mut self.paints, batch.palette.paints()) {
            for leaf in &mut batch.leaves {
                leaf.paint = map[leaf.paint.0 as usize];
            }
        }
        let base = if continues { 0 } else { self.tree.len() as u32 };
        if continues || self.leaves.is_empty() && self.tree.is_empty() {
            // No renumbering needed: append the leaves as they are, take the tree.
            if self.leaves.is_empty() {
                self.leaves = std::mem::take(&mut batch.leaves);
            } else {
                self.leaves.append(&mut batch.leaves);
            }
            self.tree = batch.tree;
        } else {
            self.tree.extend(batch.tree.into_iter().map(|mut n| {
                n.parent = n.parent.map(|p| p + base);
                n
            }));
            self.leaves.extend(batch.leaves.into_iter().map(|l| {
                let node = l.node().map(|n| n + base);
                l.with_node(node)
            }));
        }
        let occluder_base = gathered.occluders.len() as u32;
        gathered
            .occluders
            .extend(batch.occluders.into_iter().map(|mut o| {
                if o.parent != NO_OCCLUDER {
                    o.parent += occluder_base;
                }
                o
            }));
        for mut lot in batch.waiting {
            for shape in &mut lot.shapes {
                shape.state.rebase(base, occluder_base);
            }
            gathered.waiting.push(lot);
        }
        gathered.snaps.append(&mut batch.snaps);
        self.reports.extend(batch.reports);
        self.report_nodes
            .extend(batch.report_nodes.into_iter().map(|n| n + base));
        self.prints.extend(batch.prints);
        self.print_lots.extend(batch.print_lots);
        self.stats.shapes += batch.shapes;
        for (c, n) in counts.iter_mut().zip(&batch.counts) {
            *c += n;
        }
        Ok(())
    }
}

/// What consecutive lots derived so far: their leaves, tree, output and counts, what they leave
/// for phase 2, or the error of the first lot that failed.
pub(super) struct Batch {
    pub(super) leaves: Vec<Leaf>,
    /// The paints of `leaves`.
    pub(super) palette: Palette,
    pub(super) tree: Vec<TreeNode>,
    pub(super) reports: Vec<(String, Value)>,
    /// The batch's number of the tree node each report was made on (with a tree only).
    pub(super) report_nodes: Vec<u32>,
    pub(super) prints: Vec<String>,
    pub(super) print_lots: Vec<u32>,
    pub(super) shapes: usize,
    pub(super) counts: Vec<usize>,
    waiting: Vec<Waiting>,
    pub(super) occluders: Vec<Occluder>,
    pub(super) snaps: Vec<SnapPlane>,
    /// Each lot's skeleton, by lot, when the grammar builds them.
    pub(super) skeletons: Vec<(u32, Skeleton)>,
    /// Each lot's trace, when the derivation keeps one.
    pub(super) traces: Vec<LotTrace>,
    /// Rule applications taken from a previous derivation.
    pub(super) reused: usize,
    /// The most sections a skeleton of the batch has: lots of one grammar grow skeletons of
    /// similar sizes, so the next one starts with room for that many.
    pub(super) skeleton_room: usize,
    /// Goal grammars: what shapes of the batch sought rules for.
    pub(super) queries: Vec<GoalQuery>,
    /// Goal grammars: what shapes of the batch that no rule applied to sought.
    pub(super) unmatched: Vec<GoalQuery>,
    error: Option<DeriveError>,
}

impl Batch {
    fn new(program: &Program) -> Self {
        Self {
            leaves: Vec::new(),
            palette: Palette::default(),
            tree: Vec::new(),
            reports: Vec::new(),
            report_nodes: Vec::new(),
            prints: Vec::new(),
            print_lots: Vec::new(),
            shapes: 0,
            counts: vec![0; program.rules.len()],
            waiting: Vec::new(),
            skeletons: Vec::new(),
            traces: Vec::new(),
            reused: 0,
            skeleton_room: 1,
            occluders: Vec::new(),
            snaps: Vec::new(),
            queries: Vec::new(),
            unmatched: Vec::new(),
            error: None,
        }
    }
}

pub(super) fn rule_counts(program: &Program, counts: &[usize]) -> Vec<(String, usize)> {
    program
        .rules
        .iter()
        .zip(counts)
        .map(|(r, &n)| (program.symbol_name(r.symbol).to_owned(), n))
        .collect()
}

/// The attribute overrides of `options` as attribute indices; a name the program does not
/// declare is an error (with the closest name as a hint).
pub(super) fn overrides(
    program: &Program,
    options: &DeriveOptions,
) -> Result<Vec<(u32, Value)>, DeriveError> {
    options
        .attrs
        .iter()
        .map(|(name, value)| {
            program
                .attr(name)
                .map(|i| (i, value.clone()))
                .ok_or_else(|| {
                    let mut e =
                        DeriveError::general(format!("the grammar has no attribute `{name}`"));
                    if let Some(close) = shapegram_syntax::suggest(name, program.attr_names()) {
                        e = e.with_hint(format!("did you mean `{close}`?"));
                    }
                    e
                })
        })
        .collect()
}

fn start_rule(program: &Program, options: &DeriveOptions) -> Result<RuleId, DeriveError> {
    let id = match &options.start_rule {
        Some(name) => program.rule(name, 0).ok_or_else(|| {
            let mut e = DeriveError::general(format!(
                "the grammar has no rule `{name}` without parameters"
            ));
            if let Some(close) = shapegram_syntax::suggest(name, program.rule_names()) {
                e = e.with_hint(format!("did you mean `{close}`?"));
            }
            e
        })?,
        None => program
            .start_rule
            .ok_or_else(|| DeriveError::general("the grammar has no rules"))?,
    };
    let rule = &program.rules[id as usize];
    if rule.params > 0 {
        let count = match rule.params {
            1 => "1 parameter".to_owned(),
            n => format!("{n} parameters"),
        };
        return Err(DeriveError::general(format!(
            "the start rule `{}` takes {count}, but a lot has no values for them",
            program.symbol_name(rule.symbol),
        ))
        .with_hint(
            "start from a rule without parameters: mark it @StartRule, or name it with --start",
        ));
    }
    Ok(id)
}

/// The scope and geometry of an initial shape: x along the first edge, y along the normal, the
/// box fitted around the polygon (CGA's initial scope).
pub(super) fn initial_shape(footprint: &[DVec3]) -> Result<(Scope, Geometry), DeriveError> {
    let normal = newell(footprint.iter().copied()).normalize_or_zero();
    let finite = footprint.iter().all(|p| p.is_finite());
    let x = footprint
        .iter()
        .zip(footprint.iter().cycle().skip(1))
        .find_map(|(a, b)| (*b - *a).reject_from(normal).try_normalize());
    let (Some(x), true) = (x, finite && normal != DVec3::ZERO) else {
        return Err(DeriveError::general(
            "an initial shape has no area (fewer than three distinct corners, or all in a line)",
        ));
    };
    let axes = DMat3::from_cols(x, normal, x.cross(normal));
    let scope = Scope::fit(axes, footprint.iter().copied());
    let local: Vec<DVec3> = footprint.iter().map(|&p| scope.to_local(p)).collect();
    let geometry = if fills_box(&local, scope.size) {
        Geometry::Box
    } else {
        Geometry::mesh(Mesh::from_polygon(&local))
    };
    Ok((scope, geometry))
}

/// How to derive one lot: its start rule, number and seed, the attribute values, the symbols'
/// names, the phase, whether to record a trace, and its previous derivation if any.
struct Lot<'a> {
    start: RuleId,
    index: u32,
    number: u64,
    seed: u64,
    overrides: &'a [(u32, Value)],
    names: &'a [Arc<str>],
    phase: Phase,
    trace: bool,
    previous: Option<Previous<'a>>,
}

/// Derives one lot into `batch` (in phase 1 of a derivation with context rules, what waits for
/// phase 2 goes to the batch too).
fn derive_lot<'a>(
    program: &'a Program,
    lot: &InitialShape,
    how: Lot<'a>,
    options: &'a DeriveOptions,
    batch: &mut Batch,
) -> Result<(), DeriveError> {
    let Lot {
        start,
        index,
        number,
        seed,
        overrides,
        names,
        phase,
        ..
    } = how;
    let (scope, geometry) = initial_shape(&lot.footprint)?;
    let symbol = program.rules[start as usize].symbol;
    let initial = (scope, geometry.clone());
    let mut state = State::initial(symbol, scope, geometry, seed);
    let mut ev = Evaluator::new(program, seed, scope.origin);
    ev.object_axes = scope.axes;
    ev.assets = options.assets.as_deref();
    ev.lot = index;
    ev.lot_number = number;
    ev.start = Some(start);
    state.attrs = Rc::new(ev.initial_attrs(&mut state, overrides)?);
    // A lot derived again grows to about its previous size.
    let previous = how
        .previous
        .as_ref()
        .map(Previous::totals)
        .unwrap_or_default();
    let room = batch.skeleton_room.max(previous.sections);
    let mut engine = Engine::new(program, ev, names, options, phase, batch);
    engine.initial = Some(initial.clone());
    engine.leaves.reserve(previous.leaves);
    if let Some(tree) = &mut engine.tree {
        tree.reserve(previous.nodes);
    }
    if how.trace {
        engine.start_recording();
        engine.reserve_trace(how.previous.as_ref());
    }
    engine.previous = how.previous;
    if program.kinematic {
        // The model's pivot: the centre of the lot's scope on the ground, with its axes.
        let pivot = scope.to_world(scope.size * DVec3::new(0.5, 0.0, 0.5));
        let root = Frame::from_axes(pivot, scope.axes);
        let name = Name::new(names[symbol as usize].clone());
        engine.skeleton = Some(Skeleton::with_capacity(root, name, room));
    }
    if engine.tree.is_some() {
        let attrs = engine.node_attrs(&state.attrs);
        let tree = engine.tree.as_mut().expect("checked above");
        state.node = tree.len() as u32;
        tree.push(TreeNode {
            name: names[symbol as usize].clone(),
            parent: None,
            scope,
            lot: index,
            section: 0,
            attrs,
            rule: None,
        });
    }
    engine.shapes = 1;
    let task = Work::Rewrite(Task {
        state: Box::new(state),
        rule: start,
        args: Vec::new(),
    });
    match options.generations {
        Some(n) => engine.run_generations(task, n)?,
        None => engine.run_depth_first(task)?,
    }
    if !engine.parked.is_empty() {
        batch.waiting.push(Waiting {
            lot: index,
            origin: scope.origin,
            object_axes: scope.axes,
            initial,
            consts: engine.ev.memo(),
            shapes: std::mem::take(&mut engine.parked),
            skeleton: engine.skeleton.take(),
        });
    }
    engine.finish(batch);
    Ok(())
}

/// Places the occluders and snap planes of phase 1 where the skeletons' poses put them, and
/// returns, for each lot waiting for phase 2 in order, the rigid motions of its sections from
/// the rest pose: the queries of phase 2 see the model posed as phase 1 left it.
fn pose_context(done: &[(u32, Skeleton)], gathered: &mut Gathered) -> Vec<Vec<Frame>> {
    let waiting: Vec<Vec<Frame>> = gathered
        .waiting
        .iter()
        .map(|w| {
            w.skeleton
                .as_ref()
                .map(Skeleton::skinning)
                .unwrap_or_default()
        })
        .collect();
    let finished: Vec<(u32, Vec<Frame>)> = done
        .iter()
        .map(|(lot, skeleton)| (*lot, skeleton.skinning()))
        .collect();
    let by_lot: FxHashMap<u32, &[Frame]> = finished
        .iter()
        .map(|(lot, motions)| (*lot, motions.as_slice()))
        .chain(
            gathered
                .waiting
                .iter()
                .zip(&waiting)
                .map(|(w, motions)| (w.lot, motions.as_slice())),
        )
        .collect();
    for occluder in &mut gathered.occluders {
        if let Some(motions) = by_lot.get(&occluder.lot()) {
            occluder.pose(motions);
        }
    }
    for plane in &mut gathered.snaps {
        if let Some(motions) = by_lot.get(&plane.lot) {
            plane.pose(motions);
        }
    }
    waiting
}

/// Derives the shapes of one lot that waited for phase 2, in order, into `batch`; `motions`
/// place its shapes for occlusion queries; `(number, seed)` are the lot's number in the input
/// and its seed.
#[allow(clippy::too_many_arguments)]
fn resume_lot(
    program: &Program,
    waiting: Waiting,
    motions: Vec<Frame>,
    (number, seed): (u64, u64),
    names: &[Arc<str>],
    options: &DeriveOptions,
    context: &Context,
    batch: &mut Batch,
) -> Result<(), DeriveError> {
    let mut ev = Evaluator::new(program, seed, waiting.origin);
    ev.object_axes = waiting.object_axes;
    ev.assets = options.assets.as_deref();
    ev.start = start_rule(program, options).ok();
    ev.restore(waiting.consts);
    ev.lot = waiting.lot;
    ev.lot_number = number;
    ev.context = Some(context);
    ev.motions = motions;
    let mut engine = Engine::new(program, ev, names, options, Phase::Answer, batch);
    engine.skeleton = waiting.skeleton;
    engine.initial = Some(waiting.initial);
    for p in waiting.shapes {
        let task = Work::Rewrite(Task {
            state: Box::new(p.state.thaw()),
            rule: p.rule,
            args: p.args,
        });
        match options.generations {
            Some(n) => engine.run_generations(task, n.saturating_sub(p.generation))?,
            None => engine.run_depth_first(task)?,
        }
    }
    engine.finish(batch);
    Ok(())
}
