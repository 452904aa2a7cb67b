//! What a derivation records so that it can be derived again after a rule changes (§4.4 of the
//! "Procedural Skeletons" paper): every rule application in depth-first order with the extent
//! of what its subtree made, what the subtree read of the skeleton outside itself, the
//! skeleton edits and the constants' first evaluations. See [`super::reuse`] for the use.

use std::sync::Arc;

use shapegram_kinematics::{Frame, Limits, Parts, Pose, SectionId, Skeleton};

use super::machine::{Engine, Task};
use super::reuse::Previous;
use super::{DeriveOptions, InitialShape};
use crate::expr::ConstEvent;
use crate::fingerprint::Fingerprints;
use crate::program::{Program, RuleId};
use crate::value::Value;

/// What a derivation recorded for [`crate::derive_again`]; kept in [`crate::Derivation::trace`]
/// when [`DeriveOptions::trace`] is set.
#[derive(Debug)]
pub struct Trace {
    pub(super) lots: Vec<LotTrace>,
    pub(super) key: Key,
}

impl Trace {
    /// Rule applications recorded, over all lots.
    pub fn applications(&self) -> usize {
        self.lots.iter().map(|l| l.applications.len()).sum()
    }
}

/// Everything a derivation depends on besides its program's rules: the grammar's frame (see
/// [`Fingerprints`]), the options and the lots.
#[derive(Debug)]
pub(super) struct Key {
    pub fingerprints: Fingerprints,
    kinematic: bool,
    tagged: bool,
    tree_keys: bool,
    seed: u64,
    attrs: Vec<(String, Value)>,
    start_rule: Option<String>,
    max_shapes: usize,
    max_depth: u32,
    keep_tree: bool,
    implicit_cell: Option<f64>,
    lots: Vec<InitialShape>,
}

impl Key {
    pub(super) fn new(program: &Program, lots: &[InitialShape], options: &DeriveOptions) -> Self {
        Self {
            fingerprints: program.fingerprints.clone(),
            kinematic: program.kinematic,
            tagged: program.tagged,
            tree_keys: program.tree_keys,
            seed: options.seed,
            attrs: options.attrs.clone(),
            start_rule: options.start_rule.clone(),
            max_shapes: options.max_shapes,
            max_depth: options.max_depth,
            keep_tree: options.keep_tree,
            implicit_cell: options.implicit_cell,
            lots: lots.to_vec(),
        }
    }

    /// Why a derivation with key `new` can reuse nothing of one with this key, if it cannot.
    pub(super) fn refuses(&self, new: &Key) -> Option<&'static str> {
        let (old, now) = (&self.fingerprints, &new.fingerprints);
        if old.frame != now.frame || old.rules.len() != now.rules.len() {
            Some("the grammar's attributes, constants, functions or list of rules changed")
        } else if self.kinematic != new.kinematic {
            Some("the grammar started or stopped using kinematic operations")
        } else if self.tagged != new.tagged {
            Some("the grammar started or stopped using component tags")
        } else if self.tree_keys != new.tree_keys {
            Some("the grammar started or stopped asking for getTreeKey")
        } else if self.lots != new.lots {
            Some("the lots changed")
        } else if (
            self.seed,
            &self.attrs,
            &self.start_rule,
            self.max_shapes,
            self.max_depth,
            self.keep_tree,
            self.implicit_cell,
        ) != (
            new.seed,
            &new.attrs,
            &new.start_rule,
            new.max_shapes,
            new.max_depth,
            new.keep_tree,
            new.implicit_cell,
        ) {
            Some("the seed, the attribute values or the options changed")
        } else {
            None
        }
    }
}

/// How far each list a lot's derivation fills had come, counted from the lot's start.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Marks {
    pub leaves: usize,
    pub nodes: usize,
    pub sections: usize,
    pub reports: usize,
    pub prints: usize,
    pub shapes: usize,
    pub consts: usize,
    pub edits: usize,
}

impl Marks {
    /// `self` moved by the distance from `from` to `to`, list by list.
    pub fn shifted(self, from: Marks, to: Marks) -> Marks {
        let f = |v: usize, a: usize, b: usize| v + b - a;
        Marks {
            leaves: f(self.leaves, from.leaves, to.leaves),
            nodes: f(self.nodes, from.nodes, to.nodes),
            sections: f(self.sections, from.sections, to.sections),
            reports: f(self.reports, from.reports, to.reports),
            prints: f(self.prints, from.prints, to.prints),
            shapes: f(self.shapes, from.shapes, to.shapes),
            consts: f(self.consts, from.consts, to.consts),
            edits: f(self.edits, from.edits, to.edits),
        }
    }
}

/// One rule application and the subtree it roots.
#[derive(Clone, Debug)]
pub(super) struct Application {
    pub rule: RuleId,
    /// The index of the first application after its subtree.
    pub end: usize,
    /// The shape's tree node, counted from the lot's first (0 without a tree).
    pub node: usize,
    /// The shape's section.
    pub section: u32,
    pub start: Marks,
    pub finish: Marks,
    /// What the subtree reads of the skeleton outside itself, as it was at its start (only
    /// with a skeleton).
    pub inputs: Option<Box<SectionInputs>>,
}

/// What a subtree's operations read of sections it did not make: its shape's section (the
/// joint, limits and pose, and whether it has children) and that section's parent's joint.
/// Nothing else outside the subtree is read (Theorem 4.4: a subtree connects to the rest of the
/// skeleton only through its root's section).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct SectionInputs {
    rest: Frame,
    limits: Limits,
    pose: Pose,
    has_children: bool,
    parent_rest: Option<Frame>,
}

impl SectionInputs {
    pub(super) fn of(skeleton: &Skeleton, section: SectionId) -> Self {
        let s = skeleton.section(section);
        Self {
            rest: s.rest(),
            limits: s.limits(),
            pose: s.pose(),
            has_children: s.has_children(),
            parent_rest: s.parent().map(|p| skeleton.section(p).rest()),
        }
    }
}

/// A change the derivation made to the skeleton, in the terms of the skeleton's own operations,
/// so that replaying it does what the operation did. New sections are named by their ids: the
/// derivation's skeleton holds their joints and names, which nothing changes after the subtree
/// that made them (only its shapes hang from them, and joints are placed on a shape's own
/// section), so a replay reads them there.
#[derive(Clone, Debug)]
pub(super) enum Edit {
    /// `section` was made as a child of `parent` (a component).
    Component {
        parent: u32,
        section: u32,
    },
    /// `section` was split in a chain of the new sections `first..first + len`.
    Sequential {
        section: u32,
        first: u32,
        len: u32,
    },
    /// `section` was split in a fork of the new sections `first..first + len`.
    Parallel {
        section: u32,
        first: u32,
        len: u32,
    },
    // The values of the rarer edits are boxed, so that an edit takes 16 bytes.
    Joint {
        section: u32,
        rest: Box<Frame>,
    },
    Limits {
        section: u32,
        limits: Box<Limits>,
    },
    Pose {
        section: u32,
        pose: Box<Pose>,
    },
}

impl Edit {
    /// Does to `skeleton` what the recorded operation did to `recorded`, the skeleton it was
    /// recorded in, with sections renamed by `map` (which names the sections about to be made
    /// too); returns the edit in the new names. The operations that can refuse (a fork at the
    /// root, a pose outside the limits) did not refuse when recorded, on a skeleton that read
    /// the same, so they do not refuse now: a refusal is returned as text.
    pub(super) fn replay(
        &self,
        recorded: &Skeleton,
        skeleton: &mut Skeleton,
        map: impl Fn(u32) -> Result<u32, String>,
    ) -> Result<Edit, String> {
        let made = |first: u32, len: u32| {
            (first..first + len).map(|id| {
                let s = recorded.section(SectionId(id));
                (s.rest(), s)
            })
        };
        let next = skeleton.len() as u32;
        Ok(match self {
            Edit::Component { parent, section } => {
                let parent = map(*parent)?;
                let s = recorded.section(SectionId(*section));
                let made = skeleton.add_child(SectionId(parent), s.rest(), s);
                Edit::Component {
                    parent,
                    section: made.0,
                }
            }
            Edit::Sequential {
                section,
                first,
                len,
            } => {
                let section = map(*section)?;
                skeleton.sequential(SectionId(section), made(*first, *len));
                Edit::Sequential {
                    section,
                    first: next,
                    len: *len,
                }
            }
            Edit::Parallel {
                section,
                first,
                len,
            } => {
                let section = map(*section)?;
                skeleton
                    .parallel(SectionId(section), made(*first, *len))
                    .map_err(|e| e.to_string())?;
                Edit::Parallel {
                    section,
                    first: next,
                    len: *len,
                }
            }
            Edit::Joint { section, rest } => {
                let section = map(*section)?;
                skeleton.place_joint(SectionId(section), **rest);
                Edit::Joint {
                    section,
                    rest: rest.clone(),
                }
            }
            Edit::Limits { section, limits } => {
                let section = map(*section)?;
                skeleton
                    .set_limits(SectionId(section), **limits)
                    .map_err(|e| e.to_string())?;
                Edit::Limits {
                    section,
                    limits: limits.clone(),
                }
            }
            Edit::Pose { section, pose } => {
                let section = map(*section)?;
                skeleton
                    .pose_within(SectionId(section), **pose)
                    .map_err(|e| e.to_string())?;
                Edit::Pose {
                    section,
                    pose: pose.clone(),
                }
            }
        })
    }
}

/// What one lot's derivation recorded.
#[derive(Debug, Default)]
pub(super) struct LotTrace {
    pub applications: Vec<Application>,
    pub edits: Vec<Edit>,
    pub consts: Vec<ConstEvent>,
}

impl LotTrace {
    /// What the whole lot made.
    pub fn totals(&self) -> Marks {
        self.applications
            .first()
            .map_or_else(Marks::default, |a| a.finish)
    }
}

/// The engine's recording of one lot.
pub(super) struct Recorder {
    pub trace: LotTrace,
    /// Open applications: the depth of the work stack below each, and its index.
    open: Vec<(usize, usize)>,
    /// Where the lot's leaves and tree nodes start in the batch's lists.
    leaves_base: usize,
    nodes_base: usize,
}

impl Engine<'_> {
    /// Starts recording a lot whose leaves and tree nodes will follow those there now.
    pub(super) fn start_recording(&mut self) {
        self.recorder = Some(Recorder {
            trace: LotTrace::default(),
            open: Vec::new(),
            leaves_base: self.leaves.len(),
            nodes_base: self.tree.as_ref().map_or(0, Vec::len),
        });
        self.ev.const_log = Some(Vec::new());
    }

    /// Makes room in the trace for as much as `previous` recorded.
    pub(super) fn reserve_trace(&mut self, previous: Option<&Previous>) {
        if let (Some(recorder), Some(previous)) = (&mut self.recorder, previous) {
            let (applications, edits) = previous.recorded();
            recorder.trace.applications.reserve(applications);
            recorder.trace.edits.reserve(edits);
        }
    }

    /// How far the lot has come.
    pub(super) fn marks(&self) -> Marks {
        let (leaves_base, nodes_base, edits) = self.recorder.as_ref().map_or((0, 0, 0), |r| {
            (r.leaves_base, r.nodes_base, r.trace.edits.len())
        });
        Marks {
            leaves: self.leaves.len() - leaves_base,
            nodes: self.tree.as_ref().map_or(0, |t| t.len() - nodes_base),
            sections: self.skeleton.as_ref().map_or(0, Skeleton::len),
            reports: self.ev.reports.len(),
            prints: self.ev.prints.len(),
            shapes: self.shapes,
            consts: self.ev.const_log.as_ref().map_or(0, Vec::len),
            edits,
        }
    }

    /// The lot-relative number of a tree node of the batch.
    pub(super) fn lot_node(&self, node: u32) -> usize {
        let base = self.recorder.as_ref().map_or(0, |r| r.nodes_base);
        (node as usize).saturating_sub(base)
    }

    /// The batch's number of a lot-relative tree node.
    pub(super) fn batch_node(&self, node: usize) -> u32 {
        let base = self.recorder.as_ref().map_or(0, |r| r.nodes_base);
        (base + node) as u32
    }

    /// Records the start of a rule application, applied with the work stack `depth` deep below
    /// it.
    pub(super) fn open_application(&mut self, task: &Task, depth: usize) {
        let start = self.marks();
        let node = if self.tree.is_some() {
            self.lot_node(task.state.node)
        } else {
            0
        };
        let inputs = self
            .skeleton
            .as_ref()
            .map(|s| Box::new(SectionInputs::of(s, SectionId(task.state.section))));
        let Some(recorder) = &mut self.recorder else {
            return;
        };
        let index = recorder.trace.applications.len();
        recorder.trace.applications.push(Application {
            rule: task.rule,
            end: index + 1,
            node,
            section: task.state.section,
            start,
            finish: start,
            inputs,
        });
        recorder.open.push((depth, index));
    }

    /// Records the end of the applications whose subtrees are done: those applied with the
    /// work stack at least `depth` deep below them, now that it is `depth` deep.
    pub(super) fn close_applications(&mut self, depth: usize) {
        let closing = self
            .recorder
            .as_ref()
            .is_some_and(|r| r.open.last().is_some_and(|&(d, _)| d >= depth));
        if !closing {
            return;
        }
        let marks = self.marks();
        let recorder = self.recorder.as_mut().expect("checked above");
        let count = recorder.trace.applications.len();
        while let Some(&(d, index)) = recorder.open.last() {
            if d < depth {
                break;
            }
            recorder.open.pop();
            let application = &mut recorder.trace.applications[index];
            application.end = count;
            application.finish = marks;
        }
    }

    /// Records a skeleton edit.
    pub(super) fn record_edit(&mut self, edit: impl FnOnce() -> Edit) {
        if let Some(recorder) = &mut self.recorder {
            recorder.trace.edits.push(edit());
        }
    }

    /// Records a split's new sections.
    pub(super) fn record_split(&mut self, section: SectionId, parts: Parts, parallel: bool) {
        // A chain keeps the split section as its first part.
        let new = parts.len() as u32 - u32::from(!parallel);
        let first = parts.iter().find(|&id| id != section).map_or(0, |id| id.0);
        self.record_edit(|| {
            if parallel {
                Edit::Parallel {
                    section: section.0,
                    first,
                    len: new,
                }
            } else {
                Edit::Sequential {
                    section: section.0,
                    first,
                    len: new,
                }
            }
        });
    }
}

/// The recorded lots with what their derivation depended on.
pub(super) fn finish_trace(
    lots: Vec<LotTrace>,
    program: &Program,
    initial: &[InitialShape],
    options: &DeriveOptions,
) -> Arc<Trace> {
    Arc::new(Trace {
        lots,
        key: Key::new(program, initial, options),
    })
}

/// Which rules of the new grammar differ from the old one's, by rule.
pub(super) fn changed_rules(old: &Fingerprints, new: &Fingerprints) -> Vec<bool> {
    old.rules
        .iter()
        .zip(&new.rules)
        .map(|(a, b)| a != b)
        .collect()
}
