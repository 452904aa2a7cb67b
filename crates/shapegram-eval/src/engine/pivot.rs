//! Operations that give the shape another scope frame and leave its geometry where it is in
//! the world (`mirrorScope`, `setPivot`), and `resetGeometry`, which takes the shape back to
//! the initial shape's geometry and scope.

use shapegram_geom::{DMat3, DVec3, Scope};
use shapegram_syntax::Span;

use super::Fallible;
use super::machine::Engine;
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::{Geometry, State, flat_axis};
use crate::trim::Trim;
use crate::value::Value;

/// The corners of a scope by CityEngine's numbering, as steps along x, y and z: 0 to 3 around
/// the bottom from the origin (along x first), 4 to 7 above them.
const CORNERS: [[bool; 3]; 8] = [
    [false, false, false],
    [true, false, false],
    [true, false, true],
    [false, false, true],
    [false, true, false],
    [true, true, false],
    [true, true, true],
    [false, true, true],
];

impl Engine<'_> {
    /// CGA `mirrorScope(x, y, z)`: each flagged scope axis turned round, the scope's origin
    /// moved to that axis's far end, so the scope covers the same box (now mirrored).
    pub(super) fn mirror_scope(
        &mut self,
        state: &mut State,
        flags: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let mut scope = state.scope;
        for (i, e) in flags.iter().enumerate() {
            let flip = match self.ev.eval(e, state, args)? {
                Value::Bool(b) => b,
                other => {
                    return Err(DeriveError::at(
                        format!("mirrorScope takes true or false per axis, not {other}"),
                        e.span,
                    ));
                }
            };
            if flip {
                scope.origin += scope.axes.col(i) * scope.size[i];
                let mut turn = DVec3::ONE;
                turn[i] = -1.0;
                scope.axes *= DMat3::from_diagonal(turn);
            }
        }
        reframe(state, scope);
        Ok(())
    }

    /// CGA `setPivot(xyz | yzx | zxy, corner)`: the scope's origin moved to one of its eight
    /// corners, its axes turned to point into the box: the new y along the old axis `up` (y
    /// for `xyz`, x for `yzx`, z for `zxy`), the new x along whichever of the other two leaves
    /// the new z pointing in too.
    pub(super) fn set_pivot(
        &mut self,
        state: &mut State,
        up: usize,
        corner: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        let index = self.ev.number(corner, state, args)?;
        let Some(steps) =
            (index.fract() == 0.0 && (0.0..8.0).contains(&index)).then(|| CORNERS[index as usize])
        else {
            return Err(DeriveError::at(
                format!("setPivot's corner is a whole number from 0 to 7, not {index}"),
                corner.span,
            ));
        };
        let inward = |i: usize| {
            let mut d = DVec3::ZERO;
            d[i] = if steps[i] { -1.0 } else { 1.0 };
            d
        };
        // At corner 0 the new x runs along the axis after `up` in z, x, y order wrapped
        // (x for xyz, z for yzx, y for zxy), the new z along the remaining one.
        let (first, other) = ((up + 2) % 3, (up + 1) % 3);
        let y = inward(up);
        let (x, from) = if inward(first).cross(y).dot(inward(other)) > 0.0 {
            (inward(first), [first, up, other])
        } else {
            (inward(other), [other, up, first])
        };
        let local = DMat3::from_cols(x, y, x.cross(y));
        let size = state.scope.size;
        let corner = DVec3::new(
            f64::from(u8::from(steps[0])) * size.x,
            f64::from(u8::from(steps[1])) * size.y,
            f64::from(u8::from(steps[2])) * size.z,
        );
        let scope = Scope::new(
            state.scope.to_world(corner),
            state.scope.axes * local,
            DVec3::new(size[from[0]], size[from[1]], size[from[2]]),
        );
        reframe(state, scope);
        Ok(())
    }

    /// CGA `resetGeometry()`: the initial shape's geometry and scope back, without trim
    /// planes; attributes, material and projections stay.
    pub(super) fn reset_geometry(&mut self, state: &mut State, span: Span) -> Fallible<()> {
        let Some((scope, geometry)) = &self.initial else {
            return Err(DeriveError::at(
                "resetGeometry needs an initial shape, and this derivation started without one",
                span,
            ));
        };
        state.scope = *scope;
        state.geometry = geometry.clone();
        state.trim = Trim::default();
        Ok(())
    }
}

/// Gives the shape a scope that covers the same place, its geometry staying where it is in the
/// world. A solid box stays a box; anything else is carried over as a mesh, since a flat box's
/// face follows its scope's axes.
fn reframe(state: &mut State, scope: Scope) {
    if state.geometry == Geometry::Box && flat_axis(state.scope.size).is_none() {
        state.scope = scope;
    } else {
        state.rescope(scope);
    }
}
