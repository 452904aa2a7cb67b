//! What the operations do to the kinematic skeleton (Ilčík, Fiedler, Purgathofer and Wimmer,
//! "Procedural Skeletons", §4.1): a split makes a chain or a fork of sections, components hang
//! from the shape's section, and the kinematic operations place the shape's joint, limit it and
//! pose it. Every other operation keeps the shape's section. Only a grammar that uses a
//! kinematic operation builds a skeleton; without one the split and component hooks return at
//! once.

use std::sync::Arc;

use shapegram_geom::{DMat3, DQuat, DVec3, Scope};
use shapegram_kinematics::{Frame, KinematicError, Parts, Range, SectionId, Skeleton, Tagged};
use shapegram_syntax::Span;

use super::Fallible;
use super::machine::{Engine, Phase};
use super::trace::Edit;
use crate::error::DeriveError;
use crate::ops::SplitJoints;
use crate::program::{CExpr, CStmt, Sym};
use crate::rng::mix;
use crate::shape::State;
use crate::value::Value;

/// A split is sequential when its axis is within this angle of the shape's bone (the line from
/// its parent's joint to its own); the paper leaves the threshold open.
const ALONG_BONE_DEGREES: f64 = 30.0;

impl Engine<'_> {
    /// The sections of a split's parts, given as (start, size) along `axis` and the body that
    /// derives them (which names them); `None` when the grammar builds no skeleton.
    pub(super) fn split_sections<'b>(
        &mut self,
        state: &State,
        axis: usize,
        parts: impl ExactSizeIterator<Item = (f64, f64, &'b [CStmt])>,
        joints: SplitJoints,
        span: Span,
    ) -> Fallible<Option<Parts>> {
        let Some(skeleton) = &mut self.skeleton else {
            return Ok(None);
        };
        let section = SectionId(state.section);
        let rest = skeleton.section(section).rest();
        let direction = state.scope.axes.col(axis);
        // Joints lie on the line through the shape's joint along the split direction.
        let on_line = |t: f64| {
            let p = state.scope.origin + direction * t;
            Frame {
                rotation: rest.rotation,
                translation: rest.translation + direction * (p - rest.translation).dot(direction),
            }
        };
        let names = self.names;
        let named = |i: usize, body: &[CStmt], frame: Frame| {
            let symbol = first_successor(body).unwrap_or(state.symbol);
            (
                frame,
                section_name(&names[symbol as usize], state.seed, i as u64),
            )
        };
        let kind = match joints {
            SplitJoints::Auto => automatic(skeleton, section, direction),
            kind => kind,
        };
        let parallel = kind == SplitJoints::Parallel;
        let ids = if parallel {
            let frames = parts
                .enumerate()
                .map(|(i, (start, size, body))| named(i, body, on_line(start + size / 2.0)));
            skeleton
                .parallel(section, frames)
                .map_err(|e| kinematic_error(e, span))?
        } else {
            let frames = parts
                .enumerate()
                .skip(1)
                .map(|(i, (start, _, body))| named(i, body, on_line(start)));
            skeleton.sequential(section, frames)
        };
        self.record_split(section, ids, parallel);
        self.follow_new_sections();
        Ok(Some(ids))
    }

    /// A component split's component hangs from the shape's section by a joint at its centre
    /// with z along its normal (the component scope's z); `made` counts the components so far,
    /// for their names.
    pub(super) fn hang_component(
        &mut self,
        state: &State,
        child: &mut State,
        body: &[CStmt],
        made: &mut u64,
    ) {
        let Some(skeleton) = &mut self.skeleton else {
            return;
        };
        let section = SectionId(state.section);
        let rest = skeleton.section(section).rest();
        let frame = self
            .last_rotation
            .frame(&child.scope, child.scope.center(), rest);
        let symbol = first_successor(body).unwrap_or(state.symbol);
        let name = section_name(&self.names[symbol as usize], state.seed, !*made);
        *made += 1;
        child.section = skeleton.add_child(section, frame, name).0;
        self.record_edit(|| Edit::Component {
            parent: section.0,
            section: child.section,
        });
        self.follow_new_sections();
    }

    /// In phase 2 of a grammar with context rules, occlusion queries place a shape by the pose
    /// phase 1 left (see `Evaluator::motions`): a section made since moves with its parent,
    /// as it does at rest.
    fn follow_new_sections(&mut self) {
        let Some(skeleton) = &self.skeleton else {
            return;
        };
        let motions = &mut self.ev.motions;
        if self.phase != Phase::Answer || motions.is_empty() {
            return;
        }
        for id in motions.len()..skeleton.len() {
            let parent = skeleton.section(SectionId(id as u32)).parent();
            let motion = parent
                .and_then(|p| motions.get(p.index()).copied())
                .unwrap_or(Frame::IDENTITY);
            motions.push(motion);
        }
    }

    /// `joint(x, y, z)`: the joint placement rule. The joint moves to the point of the scope,
    /// its axes along the scope's; nothing else moves.
    pub(super) fn place_joint(
        &mut self,
        state: &mut State,
        at: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let local = self.vector(at, state, args)?;
        let section = SectionId(state.section);
        let rest = self.skeleton_mut().section(section).rest();
        let rest = self
            .last_rotation
            .frame(&state.scope, state.scope.to_world(local), rest);
        self.skeleton_mut().place_joint(section, rest);
        self.record_edit(|| Edit::Joint {
            section: section.0,
            rest: Box::new(rest),
        });
        Ok(())
    }

    /// `rotationLimits(axis, min, max)` and `translationLimits(axis, min, max)`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn limit_joint(
        &mut self,
        state: &mut State,
        rotation: bool,
        axis: usize,
        (min, max): (&CExpr, &CExpr),
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let range = Range::new(
            self.ev.number(min, state, args)?,
            self.ev.number(max, state, args)?,
        );
        let skeleton = self.skeleton_mut();
        let section = SectionId(state.section);
        let mut limits = skeleton.section(section).limits();
        if rotation {
            limits.rotation[axis] = range;
        } else {
            limits.translation[axis] = range;
        }
        // A joint at rest outside its limits starts at the nearest limit; a pose the grammar
        // set is never changed behind its back.
        let pose = skeleton.section(section).pose();
        if !pose.is_rest() {
            limits.validate().map_err(|e| kinematic_error(e, span))?;
            limits.admit(&pose).map_err(|e| {
                DeriveError::at(format!("the joint's pose leaves the new limits: {e}"), span)
                    .with_hint("set the limits before the pose (rotateJoint, translateJoint)")
            })?;
        }
        skeleton
            .set_limits(section, limits)
            .map_err(|e| kinematic_error(e, span))?;
        self.record_edit(|| Edit::Limits {
            section: section.0,
            limits: Box::new(limits),
        });
        Ok(())
    }

    /// `rotateJoint(x, y, z)` and `translateJoint(x, y, z)`: the current pose. A pose outside
    /// the joint's limits is an error, not clamped: a grammar's pose is meant as written.
    pub(super) fn pose_joint(
        &mut self,
        state: &mut State,
        rotation: bool,
        values: &[CExpr; 3],
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let mut v = DVec3::ZERO;
        for (i, e) in values.iter().enumerate() {
            v[i] = self.ev.number(e, state, args)?;
        }
        let skeleton = self.skeleton_mut();
        let section = SectionId(state.section);
        let mut pose = skeleton.section(section).pose();
        if rotation {
            pose.rotation = v;
        } else {
            pose.translation = v;
        }
        let posed = skeleton.pose_within(section, pose);
        if posed.is_ok() {
            self.record_edit(|| Edit::Pose {
                section: section.0,
                pose: Box::new(pose),
            });
        }
        posed.map_err(|e| {
            let hint = match &e {
                KinematicError::OutsideLimits { clamped, .. } => Some(format!(
                    "free the axis first: `{}({}, min, max)`",
                    if clamped.rotation {
                        "rotationLimits"
                    } else {
                        "translationLimits"
                    },
                    clamped.axis.name()
                )),
                _ => None,
            };
            let error = kinematic_error(e, span);
            match hint {
                Some(hint) => error.with_hint(hint),
                None => error,
            }
        })
    }

    /// The skeleton of a grammar with kinematic operations (there always is one then).
    fn skeleton_mut(&mut self) -> &mut Skeleton {
        self.skeleton
            .as_mut()
            .expect("a grammar with kinematic operations builds a skeleton")
    }
}

/// The split kind the paper picks for plain CGA splits: sequential along the bone, else
/// parallel where the shape allows a fork, else sequential. A shape whose joint may move is
/// split sequentially too, so that its parts move with it.
fn automatic(skeleton: &Skeleton, section: SectionId, direction: DVec3) -> SplitJoints {
    let s = skeleton.section(section);
    let Some(parent) = s.parent() else {
        return SplitJoints::Sequential;
    };
    // A fork would hang the parts from the parent, past a joint the grammar freed or posed:
    // they would not move with it.
    if s.has_children() || s.is_free() {
        return SplitJoints::Sequential;
    }
    // Along the bone: |bone · direction| ≥ cos θ |bone| (the direction is a unit vector),
    // squared to spare a square root per split.
    let bone = s.rest().translation - skeleton.section(parent).rest().translation;
    let cos = ALONG_BONE_DEGREES.to_radians().cos();
    let along = bone.dot(direction).powi(2) >= cos * cos * bone.length_squared()
        && bone.length_squared() > 0.0;
    if along {
        SplitJoints::Sequential
    } else {
        SplitJoints::Parallel
    }
}

/// The rotation of the last scope axes a joint took, since the shapes of one facade or floor
/// share their axes and turning axes into a rotation takes two square roots.
#[derive(Clone, Copy, Default)]
pub(super) struct LastRotation(Option<(DMat3, DQuat)>);

impl LastRotation {
    /// A joint frame at `at` with the scope's axes, or with `fallback`'s orientation when the
    /// scope's axes are not a rotation (a mirrored or degenerate scope).
    fn frame(&mut self, scope: &Scope, at: DVec3, fallback: Frame) -> Frame {
        let axes: DMat3 = scope.axes;
        let rotation = match self.0 {
            Some((last, rotation)) if last == axes => rotation,
            // Scope axes are orthonormal; a mirror makes them left-handed.
            _ if axes.determinant() > 0.5 => {
                let rotation = Frame::from_axes(at, axes).rotation;
                self.0 = Some((axes, rotation));
                rotation
            }
            _ => fallback.rotation,
        };
        Frame {
            rotation,
            translation: at,
        }
    }
}

/// A short name that stays the same when the grammar is derived again: the rule of the part
/// and a hash of the shape's place in the derivation and the part's index.
fn section_name(symbol: &Arc<str>, seed: u64, part: u64) -> Tagged<'_> {
    let hash = mix(seed ^ part.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    Tagged {
        rule: symbol,
        tag: hash as u32,
    }
}

/// The symbol of the first successor of a body: the rule a part or component becomes, which
/// names its section.
fn first_successor(body: &[CStmt]) -> Option<Sym> {
    body.iter().find_map(|s| match s {
        CStmt::Successor { symbol, .. } => Some(*symbol),
        _ => None,
    })
}

fn kinematic_error(error: KinematicError, span: Span) -> DeriveError {
    DeriveError::at(error.to_string(), span)
}
