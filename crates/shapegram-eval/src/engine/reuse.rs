//! Deriving again after rules changed (§4.4 of the "Procedural Skeletons" paper): only the
//! subtrees of shapes whose rules changed are derived again, and every other subtree is taken
//! from the previous derivation's [`Trace`], its skeleton edits replayed onto the new skeleton.
//!
//! The engine walks the new derivation depth first as always, in step with the previous one's
//! rule applications. At each shape waiting for its rule it compares what the subtree depends
//! on: the rule (its fingerprint), the shape (the same as before, as long as every rule on the
//! way to it is unchanged), the constants evaluated so far, and what the subtree reads of the
//! skeleton outside itself (its section's joint, limits, pose and children, and the parent's
//! joint: Theorem 4.4 says it reads nothing else). A subtree whose dependencies are unchanged
//! and that holds no changed rule is copied, its sections and tree nodes renumbered; one that
//! holds a changed rule further down is applied and walked into; one whose own rule or
//! dependencies changed is derived afresh. The result is the full derivation of the new
//! grammar, byte for byte.

use rustc_hash::FxHashMap;
use shapegram_kinematics::{SectionId, Skeleton};

use super::derive::run;
use super::machine::{Engine, Task};
use super::trace::{Key, LotTrace, Marks, SectionInputs, Trace, changed_rules};
use super::{Derivation, DeriveOptions, InitialShape, Leaf, Paint, Symbol, TreeNode};
use crate::error::DeriveError;
use crate::expr::ConstEvent;
use crate::program::Program;
use crate::shape::Geometry;
use crate::value::Value;

/// The result of [`derive_again`].
#[derive(Debug)]
pub struct Rederivation {
    /// The derivation: the same as [`crate::derive`] of the new program would make.
    pub derivation: Derivation,
    /// Rule applications taken from the previous derivation.
    pub reused: usize,
    /// Rule applications run.
    pub applied: usize,
    /// Why nothing could be reused, when that was so (the derivation was then made afresh).
    pub fallback: Option<&'static str>,
}

/// Derives `program` on `lots` again, reusing what `previous` derived with rules that did not
/// change. `previous` must have been derived with [`DeriveOptions::trace`] set; the new
/// derivation keeps a trace when `options` say so, to be derived again in turn.
///
/// Only the rules' bodies may differ from the previous program: when its attributes,
/// constants, functions or list of rules, the lots, the seed, the attribute values or the
/// options differ, or the grammar asks about other shapes (occlusion, snapping), is a goal
/// grammar or derives in generations, everything is derived afresh and [`Rederivation::fallback`] says why. Asset
/// files are assumed unchanged.
pub fn derive_again(
    previous: &Derivation,
    program: &Program,
    lots: &[InitialShape],
    options: &DeriveOptions,
) -> Result<Rederivation, DeriveError> {
    let key = Key::new(program, lots, options);
    let refusal = if options.generations.is_some() {
        Some("derivations in generations are always made afresh")
    } else if program.goals.is_some() {
        Some("goal grammars are always derived afresh")
    } else if program.derives_now {
        Some("grammars with union, subtract, intersect or inline are always derived afresh")
    } else if program.context_rules.contains(&true) {
        Some("grammars that ask about other shapes (occlusion, snapping) are always derived afresh")
    } else {
        match &previous.trace {
            None => Some("the previous derivation kept no trace (DeriveOptions::trace)"),
            Some(trace) => trace.key.refuses(&key),
        }
    };
    let old = match (refusal, &previous.trace) {
        (None, Some(trace)) => Old::new(trace, previous, program),
        _ => {
            let derivation = run(program, lots, options, None)?.0;
            return Ok(Rederivation {
                applied: derivation.stats.rules.iter().map(|(_, n)| n).sum(),
                derivation,
                reused: 0,
                fallback: refusal,
            });
        }
    };
    let (derivation, reused) = run(program, lots, options, Some(&old))?;
    let all: usize = derivation.stats.rules.iter().map(|(_, n)| n).sum();
    Ok(Rederivation {
        applied: all - reused,
        derivation,
        reused,
        fallback: None,
    })
}

/// The previous derivation, ready to be reused lot by lot.
pub(super) struct Old<'a> {
    trace: &'a Trace,
    derivation: &'a Derivation,
    changed: Vec<bool>,
    moved: bool,
    /// By symbol of the previous derivation: the new program's symbol of that name (a changed
    /// rule body can number symbols otherwise), `None` when it has none.
    symbols: Vec<Option<Symbol>>,
    /// Where each lot's leaves, tree nodes, reports and prints start in the derivation.
    starts: Vec<Marks>,
}

impl<'a> Old<'a> {
    fn new(trace: &'a Trace, derivation: &'a Derivation, program: &Program) -> Self {
        let mut starts = Vec::with_capacity(trace.lots.len());
        let mut at = Marks::default();
        for lot in &trace.lots {
            starts.push(at);
            let totals = lot.totals();
            at.leaves += totals.leaves;
            at.nodes += totals.nodes;
            at.reports += totals.reports;
            at.prints += totals.prints;
        }
        let (old, new) = (&trace.key.fingerprints, &program.fingerprints);
        let by_name: FxHashMap<&str, Symbol> = (program.symbols.iter())
            .enumerate()
            .map(|(i, name)| (name.as_str(), Symbol(i as u32)))
            .collect();
        let symbols = (derivation.names.iter())
            .map(|name| by_name.get(&**name).copied())
            .collect();
        Self {
            trace,
            derivation,
            changed: changed_rules(old, new),
            moved: old.starts != new.starts,
            symbols,
            starts,
        }
    }

    /// What lot `lot` derived before, for its engine.
    pub(super) fn previous(&'a self, lot: usize) -> Option<Previous<'a>> {
        let trace = self.trace.lots.get(lot)?;
        let start = self.starts[lot];
        let totals = trace.totals();
        let d = self.derivation;
        let applications = &trace.applications;
        // How many changed rules each subtree holds, from counts up to each application.
        let mut before = Vec::with_capacity(applications.len() + 1);
        before.push(0u32);
        for a in applications {
            let last = *before.last().expect("starts with 0");
            before.push(last + u32::from(self.changed[a.rule as usize]));
        }
        let dirty = (0..applications.len())
            .map(|i| before[applications[i].end] > before[i])
            .collect();
        let skeleton = d
            .skeletons
            .iter()
            .find(|(l, _)| *l as usize == lot)
            .map(|(_, s)| s);
        Some(Previous {
            trace,
            skeleton,
            leaves: d.leaves.get(start.leaves..start.leaves + totals.leaves)?,
            paints: &d.paints,
            tree: d.tree.get(start.nodes..start.nodes + totals.nodes)?,
            nodes_base: start.nodes,
            reports: d
                .reports
                .get(start.reports..start.reports + totals.reports)?,
            report_nodes: d
                .report_nodes
                .get(start.reports..start.reports + totals.reports)
                .unwrap_or_default(),
            prints: d.prints.get(start.prints..start.prints + totals.prints)?,
            changed: &self.changed,
            moved: self.moved,
            symbols: &self.symbols,
            dirty,
            cursor: 0,
            fresh: None,
            consts_checked: 0,
            consts_agree: true,
            reused: 0,
        })
    }
}

/// One lot of the previous derivation, as the engine deriving it again walks through it.
pub(super) struct Previous<'a> {
    trace: &'a LotTrace,
    /// The lot's skeleton, which holds the joints and names of the sections its edits made.
    skeleton: Option<&'a Skeleton>,
    leaves: &'a [Leaf],
    /// The previous derivation's paints, which its leaves number.
    paints: &'a [Paint],
    tree: &'a [TreeNode],
    /// The previous derivation's number of the lot's first tree node.
    nodes_base: usize,
    reports: &'a [(String, Value)],
    /// The tree nodes of `reports`, when the previous derivation kept its tree.
    report_nodes: &'a [u32],
    prints: &'a [String],
    changed: &'a [bool],
    /// The new program's symbols of the previous derivation's ([`Old::symbols`]).
    symbols: &'a [Option<Symbol>],
    /// Whether rules moved in the file: implicit solids keep the spans of their operations, so
    /// subtrees that made them are not copied but walked into.
    moved: bool,
    /// By application: whether its subtree holds an application of a changed rule.
    dirty: Vec<bool>,
    /// The next previous application the walk expects.
    cursor: usize,
    /// While a subtree is derived afresh: the depth of the work stack below it.
    fresh: Option<usize>,
    /// How many of the previous lot's constant evaluations the new ones were found equal to.
    consts_checked: usize,
    consts_agree: bool,
    /// Rule applications reused.
    pub reused: usize,
}

impl Previous<'_> {
    /// What the lot made before.
    pub(super) fn totals(&self) -> Marks {
        self.trace.totals()
    }

    /// How many rule applications and skeleton edits the lot recorded before.
    pub(super) fn recorded(&self) -> (usize, usize) {
        (self.trace.applications.len(), self.trace.edits.len())
    }

    /// Whether the constants evaluated so far, `log`, are the `count` the previous derivation
    /// had evaluated at this point, with the same values and random stream.
    fn consts_agree(&mut self, log: &[ConstEvent], count: usize) -> bool {
        if log.len() != count {
            return false;
        }
        while self.consts_agree && self.consts_checked < count {
            let i = self.consts_checked;
            self.consts_agree = log[i] == self.trace.consts[i];
            self.consts_checked += 1;
        }
        self.consts_agree
    }
}

/// The error for a walk that no longer matches the previous derivation: a defect, since only
/// subtrees with unchanged dependencies are followed.
fn lost(what: &str) -> DeriveError {
    DeriveError::general(format!(
        "deriving again lost its place in the previous derivation ({what}); derive afresh"
    ))
}

impl Engine<'_> {
    /// Ends the fresh derivation of a subtree when the work stack is back at `depth`.
    pub(super) fn leave_fresh(&mut self, depth: usize) {
        if let Some(previous) = &mut self.previous
            && previous.fresh.is_some_and(|d| d >= depth)
        {
            previous.fresh = None;
        }
    }

    /// Takes the subtree of `task` from the previous derivation when nothing it depends on
    /// changed, and says whether it did; otherwise decides how the walk goes on (into the
    /// subtree, or afresh through it). The work stack is `depth` deep below the task.
    pub(super) fn reuse(&mut self, task: &Task, depth: usize) -> Result<bool, DeriveError> {
        let Some(previous) = &self.previous else {
            return Ok(false);
        };
        if previous.fresh.is_some() {
            return Ok(false);
        }
        let i = previous.cursor;
        let trace = previous.trace;
        let Some(application) = trace.applications.get(i) else {
            return Err(lost("more rule applications than before"));
        };
        if application.rule != task.rule {
            return Err(lost("a different rule"));
        }
        let section = SectionId(task.state.section);
        let same_skeleton = match (&self.skeleton, &application.inputs) {
            (Some(skeleton), Some(inputs)) => SectionInputs::of(skeleton, section) == **inputs,
            (None, None) => true,
            _ => false,
        };
        let log = self.ev.const_log.as_deref().unwrap_or_default();
        let previous = self.previous.as_mut().expect("checked above");
        let same_consts = previous.consts_agree(log, application.start.consts);
        let made_solids = || {
            previous.leaves[application.start.leaves..application.finish.leaves]
                .iter()
                .any(|l| matches!(l.geometry, Geometry::Implicit(_)))
        };
        if previous.changed[task.rule as usize] || !same_skeleton || !same_consts {
            previous.cursor = application.end;
            previous.fresh = Some(depth);
            return Ok(false);
        }
        if previous.dirty[i] || previous.moved && made_solids() {
            previous.cursor = i + 1;
            return Ok(false);
        }
        previous.cursor = application.end;
        previous.reused += application.end - i;
        // The shape's own node was made by its parent's application, not copied.
        self.note_rule(task);
        self.splice(i, task)?;
        Ok(true)
    }

    /// Copies the subtree of previous application `i` into the derivation as the subtree of
    /// `task`: its skeleton edits, tree nodes, leaves, output, constants and counts, with its
    /// sections and tree nodes renumbered, and its record into the new trace.
    fn splice(&mut self, i: usize, task: &Task) -> Result<(), DeriveError> {
        let previous = self
            .previous
            .as_ref()
            .expect("splicing a previous derivation");
        let Previous {
            trace,
            leaves,
            paints,
            tree,
            reports,
            report_nodes,
            prints,
            nodes_base,
            symbols,
            ..
        } = *previous;
        let application = &trace.applications[i];
        let (start, finish) = (application.start, application.finish);
        let now = self.marks();
        // The subtree's sections are its shape's and those it made; so are its tree nodes.
        let section = |old: u32| -> Result<u32, DeriveError> {
            let old_usize = old as usize;
            if old == application.section {
                Ok(task.state.section)
            } else if (start.sections..finish.sections).contains(&old_usize) {
                Ok((old_usize - start.sections + now.sections) as u32)
            } else {
                Err(lost("a section outside the subtree"))
            }
        };
        let task_node = self.lot_node(task.state.node);
        let node = |old: usize| -> Result<usize, DeriveError> {
            if old == application.node {
                Ok(task_node)
            } else if (start.nodes..finish.nodes).contains(&old) {
                Ok(old - start.nodes + now.nodes)
            } else {
                Err(lost("a tree node outside the subtree"))
            }
        };
        // Tree nodes are numbered in the batch: the lot's first is `first_node`.
        let first_node = self.batch_node(0) as usize;
        let batch_node = |old: u32| -> Result<u32, DeriveError> {
            Ok((first_node + node(old as usize - nodes_base)?) as u32)
        };

        if let Some(recorded) = previous.skeleton {
            let skeleton = self.skeleton.as_mut().ok_or_else(|| lost("no skeleton"))?;
            let map = |s: u32| section(s).map_err(|e| e.message);
            for edit in &trace.edits[start.edits..finish.edits] {
                let edit = edit.replay(recorded, skeleton, map).map_err(|e| lost(&e))?;
                if let Some(recorder) = &mut self.recorder {
                    recorder.trace.edits.push(edit);
                }
            }
        }
        if let Some(new) = &mut self.tree {
            new.reserve(finish.nodes - start.nodes);
            for n in &tree[start.nodes..finish.nodes] {
                new.push(TreeNode {
                    parent: n.parent.map(batch_node).transpose()?,
                    section: section(n.section)?,
                    ..n.clone()
                });
            }
        }
        self.leaves.reserve(finish.leaves - start.leaves);
        for leaf in &leaves[start.leaves..finish.leaves] {
            let moved = section(leaf.section())?;
            let name = symbols.get(leaf.name.0 as usize).copied().flatten();
            // Paints are numbered anew: in the order this derivation's leaves use them.
            let paint = paints.get(leaf.paint.0 as usize).copied();
            let leaf = Leaf {
                name: name.ok_or_else(|| lost("a symbol the new grammar lacks"))?,
                paint: self
                    .palette
                    .id(paint.ok_or_else(|| lost("a paint outside the palette"))?),
                ..leaf.clone()
            };
            let node = leaf.node().map(batch_node).transpose()?;
            self.leaves.push(leaf.with_node(node).with_section(moved));
        }
        self.ev
            .reports
            .extend_from_slice(&reports[start.reports..finish.reports]);
        if self.tree.is_some() {
            let made_on = report_nodes.get(start.reports..finish.reports);
            for &old in made_on.ok_or_else(|| lost("reports without tree nodes"))? {
                self.report_nodes.push(batch_node(old)?);
            }
        }
        for text in &prints[start.prints..finish.prints] {
            self.ev.print(text.clone());
        }
        self.ev
            .replay_consts(&trace.consts[start.consts..finish.consts]);
        if let Some(previous) = &mut self.previous {
            previous.consts_checked = finish.consts;
        }
        let applications = &trace.applications[i..application.end];
        for a in applications {
            self.counts[a.rule as usize] += 1;
        }
        self.applications += applications.len();
        self.shapes += finish.shapes - start.shapes;
        if self.shapes > self.options.max_shapes {
            return Err(DeriveError::general(format!(
                "the derivation made more than {} shapes",
                self.options.max_shapes
            ))
            .with_hint("a rule that keeps making successors needs a condition that ends it"));
        }
        let keeps_tree = self.tree.is_some();
        if let Some(recorder) = &mut self.recorder {
            let first = recorder.trace.applications.len();
            recorder.trace.applications.reserve(applications.len());
            for a in applications {
                let mut a = a.clone();
                a.end = a.end - i + first;
                a.node = if keeps_tree { node(a.node)? } else { 0 };
                a.section = section(a.section)?;
                a.start = a.start.shifted(start, now);
                a.finish = a.finish.shifted(start, now);
                recorder.trace.applications.push(a);
            }
        }
        Ok(())
    }
}
