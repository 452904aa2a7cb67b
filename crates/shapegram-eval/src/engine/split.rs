//! `split(x | y | z) { … }`: the shape cut into parts along an axis of its scope, sized and
//! repeated as [`Layout`] works out; each part is a new shape with its slab of the geometry (a
//! mesh cut into slabs, a solid intersected with one, a box by its scope alone).

mod layout;
mod uv;

use std::sync::Arc;

use shapegram_geom::{DAffine3, DVec3, Scope, split::split_slabs};
use shapegram_syntax::Span;

use super::footprint::flat_faces;
use super::machine::{Engine, Phase, Work};
use super::palette::Paint;
use super::scope::refit;
use super::{Fallible, Leaf, LeafExtras, Symbol, push_leaf};
use crate::context::Occluder;
use crate::ops::{SplitBlock, SplitJoints};
use crate::program::{CExpr, CStmt};
use crate::shape::{Geometry, State};
use crate::tags;
use crate::value::Value;

pub(super) use layout::{Layout, Layouts};

/// Bisection steps that place a boundary of `splitArea`: enough for the last bits of an f64.
const AREA_STEPS: usize = 100;

impl<'p> Engine<'p> {
    /// CGA `split(axis [, adjust | noAdjust] [, snap [, "tag"]]) { … }`: the parts laid out
    /// along `axis` (their boundaries moved onto snap planes with `snap`), then derived one by
    /// one.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn split(
        &mut self,
        state: &mut State,
        axis: usize,
        (adjust, joints): (bool, SplitJoints),
        snap: Option<&Option<CExpr>>,
        block: &'p SplitBlock,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let snaps = match snap {
            Some(tag) => Some(self.snap_positions(state, axis, tag.as_ref(), args)?),
            None => None,
        };
        let length = state.scope.size[axis];
        let mut layout = self.layouts.take_for(block, length);
        let laid = layout.lay_out(block, length, span, &mut self.ev, state, args);
        if let Err(e) = laid {
            self.layouts.put(layout);
            return Err(e);
        }
        if let Some(positions) = snaps {
            layout.snap(&positions);
        }
        let result = self.split_parts(state, axis, (adjust, joints), &layout, span, args, out);
        self.layouts.put(layout);
        result
    }

    /// CGA `splitArea(axis [, adjust | noAdjust]) { … }`: a split of a flat shape whose sizes
    /// are the areas of the parts (`'` of the geometry's area, `~` floating, `*` repeating, as
    /// in [`Layout`]); each boundary goes where the geometry before it has the area the layout
    /// puts before it, found by bisection.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn split_area(
        &mut self,
        state: &mut State,
        axis: usize,
        adjust: bool,
        block: &'p SplitBlock,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        flat_faces(state, "splitArea", span)?;
        let Some(mesh) = state.geometry.local_mesh(state.scope.size) else {
            return Ok(());
        };
        let length = state.scope.size[axis];
        let total = mesh.area();
        let mut layout = self.layouts.take();
        let laid = layout.lay_out(block, total, span, &mut self.ev, state, args);
        if let Err(e) = laid {
            self.layouts.put(layout);
            return Err(e);
        }
        layout.forget();
        // The area before a position along the axis, and the position before which lies an
        // area.
        let before = |x: f64| split_slabs(&mesh, DVec3::AXES[axis], &[x])[0].area();
        let position = |area: f64| {
            if area <= 0.0 {
                return 0.0;
            }
            if area >= total {
                return length;
            }
            let (mut lo, mut hi) = (0.0, length);
            for _ in 0..AREA_STEPS {
                let mid = 0.5 * (lo + hi);
                if before(mid) < area {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        };
        for part in &mut layout.parts {
            let (start, end) = (position(part.start), position(part.start + part.size));
            part.start = start;
            part.size = end - start;
        }
        let how = (adjust, SplitJoints::Auto);
        let result = self.split_parts(state, axis, how, &layout, span, args, out);
        self.layouts.put(layout);
        result
    }

    /// Derives the parts of a split, each with its slab of the geometry.
    #[allow(clippy::too_many_arguments)]
    fn split_parts(
        &mut self,
        state: &mut State,
        axis: usize,
        (adjust, joints): (bool, SplitJoints),
        layout: &Layout<'p>,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let parts = &layout.parts;
        let total = parts.len() as u32;
        let extents = parts.iter().map(|p| (p.start, p.size, p.body));
        let sections = self.split_sections(state, axis, extents, joints, span)?;
        let slabs = match &state.geometry {
            Geometry::Mesh(mesh, _) => {
                let mut cuts: Vec<f64> = parts
                    .iter()
                    .flat_map(|p| [p.start, p.start + p.size])
                    .collect();
                cuts.dedup();
                let pieces = split_slabs(mesh, DVec3::AXES[axis], &cuts);
                Some((cuts, pieces))
            }
            _ => None,
        };
        let solid = match &state.geometry {
            Geometry::Implicit(implicit) => Some(implicit.solid.clone()),
            _ => None,
        };
        for (i, part) in parts.iter().enumerate() {
            // The part's scope, worked out from the parent's.
            let mut scope = state.scope;
            scope.translate(DVec3::AXES[axis] * part.start);
            scope.size[axis] = part.size;
            let section = sections.map_or(state.section, |s| s.get(i).0);
            if slabs.is_none()
                && solid.is_none()
                && self.leaf_part(state, part.body, (&scope, section), span, out)?
            {
                continue;
            }
            let mut child = state.spawn();
            child.section = section;
            child.split = (i as u32, total);
            child.scope = scope;
            if let Some(solid) = &solid {
                let Some(slab) = slab_of(solid, axis, part.start, part.size) else {
                    continue;
                };
                child.geometry = state.geometry.with_solid(slab);
                if adjust {
                    let axes = child.scope.axes;
                    refit(&mut child, axes);
                }
            }
            if let Some((cuts, pieces)) = &slabs {
                let at = cuts.iter().position(|&c| c == part.start).unwrap_or(0);
                let mut piece = pieces[at + 1].clone();
                if piece.is_empty() {
                    continue;
                }
                // Pieces keep the tags of the faces they were cut from; caps have none.
                let tags = match &state.geometry {
                    Geometry::Mesh(mesh, Some(tags)) => tags::carry(mesh, tags, &piece),
                    _ => None,
                };
                piece.transform(&DAffine3::from_translation(-DVec3::AXES[axis] * part.start));
                child.geometry = Geometry::Mesh(Arc::new(piece), tags);
                if adjust {
                    let axes = child.scope.axes;
                    refit(&mut child, axes);
                }
            }
            self.admit(&mut child, span)?;
            self.run_stmts(part.body, &mut child, args, out)?;
        }
        Ok(())
    }

    /// The common part of a box split that is at once a leaf (`{ 1 : Wall. }`), made without
    /// making the part's shape and its successor: only their counts and the leaf are left of
    /// them, and the parent's count of children. Returns whether the part was such a part.
    fn leaf_part(
        &mut self,
        state: &mut State,
        body: &[CStmt],
        (scope, section): (&Scope, u32),
        span: Span,
        out: &[Work],
    ) -> Fallible<bool> {
        let [
            CStmt::Successor {
                symbol,
                rule,
                args,
                terminal,
                span: successor_span,
            },
        ] = body
        else {
            return Ok(false);
        };
        if !args.is_empty()
            || (rule.is_some() && !terminal)
            || self.tree.is_some()
            || out.len() != self.base
        {
            return Ok(false);
        }
        // The part, as `State::spawn` would have made it, and its successor's place among
        // the rule's (`getTreeKey`).
        state.children += 1;
        self.successors += 1;
        self.count(state.depth + 1, state.symbol, span)?;
        // Its successor, as `State::make_child` would have made it.
        self.count(state.depth + 2, *symbol, *successor_span)?;
        if self.phase == Phase::Gather {
            let (lot, parent) = (self.ev.lot, state.occluder);
            let leaf = Occluder::new(scope, &state.geometry, None, *symbol, None, lot, parent);
            let leaf = self.posable(leaf, section, scope, &state.geometry);
            self.occluders.extend(leaf);
        }
        if !matches!(state.geometry, Geometry::Empty) {
            let extras = LeafExtras::of(
                state.material.clone(),
                state.texturing.clone(),
                section,
                None,
            );
            let paint = self.palette.id(Paint {
                color: state.color,
                painted: state.painted,
            });
            let geometry = state.geometry.clone();
            let lot = self.ev.lot;
            push_leaf(&mut self.leaves, || {
                Leaf::new(Symbol(*symbol), *scope, geometry, paint, None, lot, extras)
            });
        }
        Ok(true)
    }
}

/// The part of `solid` between `start` and `start + size` along `axis`, in the frame of a part
/// starting there (`None` when nothing of the solid lies there).
fn slab_of(
    solid: &shapegram_implicit::Solid,
    axis: usize,
    start: f64,
    size: f64,
) -> Option<shapegram_implicit::Solid> {
    let shifted = solid.translate(-DVec3::AXES[axis] * start).ok()?;
    let bounds = shifted.bounds()?;
    // The slab spans the solid's bounds (with a margin) across the split axis.
    let mut lo = bounds.min - DVec3::ONE;
    let mut hi = bounds.max + DVec3::ONE;
    lo[axis] = 0.0;
    hi[axis] = size;
    if lo[axis] >= bounds.max[axis] || hi[axis] <= bounds.min[axis] || size <= 0.0 {
        return None;
    }
    let slab = shapegram_implicit::Solid::cuboid(hi - lo)
        .and_then(|b| b.translate((lo + hi) / 2.0))
        .ok()?;
    Some(shifted.intersection(&slab))
}
