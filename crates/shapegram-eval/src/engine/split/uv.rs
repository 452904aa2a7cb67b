//! `split(u | v, uvSpace | unitSpace, uvSet) { … }`: the shape cut across a texture coordinate.
//! A uv set is an affine function of world position (see [`crate::texturing`]), so the lines of
//! equal u are the traces of parallel planes, and the cut is a split along their normal.

use shapegram_geom::{DVec3, Scope, split::split_slabs};
use shapegram_syntax::Span;

use super::super::Fallible;
use super::super::machine::{Engine, Work};
use crate::error::DeriveError;
use crate::ops::SplitBlock;
use crate::program::CExpr;
use crate::shape::{Geometry, State};
use crate::texturing::UV_SETS;
use crate::value::Value;

impl<'p> Engine<'p> {
    /// The parts laid out between the least and greatest value of the coordinate over the
    /// geometry, in uv units or (`unitSpace`) in metres along the surface's stretch; each part
    /// gets the slab of the geometry between its planes, with the shape's axes fitted around
    /// it.
    #[allow(clippy::too_many_arguments)]
    pub(in crate::engine) fn uv_split(
        &mut self,
        state: &mut State,
        (coordinate, metres): (usize, bool),
        set: &CExpr,
        block: &'p SplitBlock,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let number = self.ev.number(set, state, args)?;
        if !(0.0..UV_SETS as f64).contains(&number) || number.fract() != 0.0 {
            return Err(DeriveError::at(
                format!("a uv set is a whole number from 0 to 9, not {number}"),
                set.span,
            ));
        }
        let index = number as usize;
        let map = state
            .texturing
            .as_ref()
            .and_then(|t| t.uvs[index])
            .ok_or_else(|| {
                DeriveError::at(format!("the shape has no uv set {index} to split along"), span)
                    .with_hint(format!(
                        "project one first: `setupProjection({index}, scope.xy, 1, 1) projectUV({index})`"
                    ))
            })?;
        let Some(world) = state.geometry.world_mesh(&state.scope) else {
            return Ok(());
        };
        let row = if coordinate == 0 { map.u } else { map.v };
        let gradient = DVec3::new(row[0], row[1], row[2]);
        let stretch = gradient.length();
        let Some(normal) = gradient.try_normalize() else {
            return Err(DeriveError::at(
                format!("uv set {index} does not change across the shape: nothing to split along"),
                span,
            ));
        };
        let at = |p: DVec3| gradient.dot(p) + row[3];
        let (least, most) = world
            .positions()
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(at(p)), hi.max(at(p)))
            });
        // Lengths along the layout, and uv units per unit of them.
        let per = if metres { stretch } else { 1.0 };
        let length = (most - least) / per;
        let mut layout = self.layouts.take();
        let laid = layout.lay_out(block, length, span, &mut self.ev, state, args);
        if let Err(e) = laid {
            self.layouts.put(layout);
            return Err(e);
        }
        // Plane offsets along `normal` where the coordinate takes a value.
        let offset = |value: f64| (value - row[3]) / stretch;
        let mut cuts: Vec<f64> = Vec::with_capacity(2 * layout.parts.len());
        for part in &layout.parts {
            cuts.push(offset(least + part.start * per));
            cuts.push(offset(least + (part.start + part.size) * per));
        }
        let mut sorted = cuts.clone();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup();
        let slabs = split_slabs(&world, normal, &sorted);
        let total = layout.parts.len() as u32;
        let mut result = Ok(());
        for (i, part) in layout.parts.iter().enumerate() {
            let start = cuts[2 * i];
            let at = sorted.iter().position(|&c| c == start).unwrap_or(0);
            let mut piece = slabs[at + 1].clone();
            if piece.is_empty() {
                continue;
            }
            let mut child = state.spawn();
            child.split = (i as u32, total);
            child.scope = Scope::fit(state.scope.axes, piece.positions().iter().copied());
            piece.transform(&child.scope.world_to_local());
            child.geometry = Geometry::mesh(piece);
            result = self
                .admit(&mut child, span)
                .and_then(|()| self.run_stmts(part.body, &mut child, args, out));
            if result.is_err() {
                break;
            }
        }
        self.layouts.put(layout);
        result
    }
}
