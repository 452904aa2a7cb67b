//! CGA's roofs, `roofGable`, `roofHip`, `roofPyramid` and `roofShed`, on the faces of a flat
//! shape.

use shapegram_geom::{DVec3, Mesh, Scope};
use shapegram_syntax::Span;

use super::Fallible;
use super::footprint::{flat_faces, grown_axes};
use super::machine::Engine;
use crate::error::DeriveError;
use crate::ops::RoofKind;
use crate::program::CExpr;
use crate::shape::{Geometry, State};
use crate::value::Value;

impl Engine<'_> {
    /// CGA's roofs on every face of a flat shape; the result is a closed solid whose scope keeps x
    /// and has y along the faces' normal.
    pub(super) fn roof(
        &mut self,
        state: &mut State,
        kind: RoofKind,
        params: &[CExpr],
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let params = self.numbers(params, state, args)?;
        let world = flat_faces(state, "roof", span)?;
        let angle = params[0];
        let extra = params.get(1).copied();
        let mut solid = Mesh::new();
        let mut up = DVec3::ZERO;
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let built = match kind {
                RoofKind::Gable => {
                    shapegram_geom::roof::roof_gable(&points, angle, extra.unwrap_or(0.0))
                }
                RoofKind::Hip => {
                    shapegram_geom::roof::roof_hip(&points, angle, extra.unwrap_or(0.0))
                }
                RoofKind::Pyramid => shapegram_geom::roof::roof_pyramid(&points, angle),
                RoofKind::Shed => {
                    let edge = extra.unwrap_or(0.0);
                    if edge < 0.0 || edge.fract() != 0.0 {
                        return Err(DeriveError::at(
                            format!("roofShed's edge index must be a whole number ≥ 0, not {edge}"),
                            span,
                        ));
                    }
                    shapegram_geom::roof::roof_shed(&points, angle, edge as usize)
                }
            };
            let Some(built) = built else {
                return Err(DeriveError::at(
                    format!(
                        "cannot build this roof: the angle must be between 0 and 90 degrees (it is \
                         {angle}), any overhang not negative, and the face a simple polygon"
                    ),
                    span,
                ));
            };
            if up == DVec3::ZERO {
                up = world.face_normal(f);
            }
            solid.append(&built);
        }
        let fitted = Scope::fit(
            grown_axes(&state.scope, up),
            solid.positions().iter().copied(),
        );
        solid.transform(&fitted.world_to_local());
        state.scope = fitted;
        state.geometry = Geometry::mesh(solid);
        Ok(())
    }
}
