//! CGA's roofs, `roofGable`, `roofHip`, `roofPyramid`, `roofShed` and `roofRidge`, on the
//! faces of a flat shape, by angle or (`byHeight`) by height.

use shapegram_geom::{
    DVec3, Mesh, Scope,
    roof::{
        Gable, RoofShape, pyramid, roof_gable_with, roof_hip, roof_pyramid, roof_ridge, roof_run,
        roof_shed,
    },
};
use shapegram_syntax::Span;

use super::Fallible;
use super::auto_tags::{self, Facing};
use super::footprint::{face_tags, flat_faces, grown_axes};
use super::machine::Engine;
use crate::error::DeriveError;
use crate::ops::RoofKind;
use crate::program::CExpr;
use crate::shape::{Geometry, State};
use crate::tags::FaceTags;
use crate::value::Value;

/// A roof's options evaluated.
struct RoofOptions {
    /// The angle in degrees, or the height with `byHeight`.
    value: f64,
    by_height: bool,
    overhang_x: f64,
    overhang_y: f64,
    /// The edge of a shed roof, or the ridge's edge of a gable roof; negative counts from the
    /// end.
    edge: Option<i64>,
}

impl Engine<'_> {
    /// CGA's roofs on every face of a flat shape; the result is a closed solid whose scope keeps x
    /// and has y along the faces' normal.
    pub(super) fn roof(
        &mut self,
        state: &mut State,
        kind: RoofKind,
        by_height: bool,
        params: &[CExpr],
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let options = self.roof_options(state, kind, by_height, params, args)?;
        let world = flat_faces(state, "roof", span)?;
        let mut solid = Mesh::new();
        let mut tags = Vec::new();
        let mut up = DVec3::ZERO;
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let edge = options
                .edge
                .map(|i| i.rem_euclid(points.len() as i64) as usize);
            let ridge = state.scope.x_axis();
            let angle = angle_of(kind, &options, (edge, ridge), &points, span)?;
            let built = match kind {
                RoofKind::Gable => roof_gable_with(
                    &points,
                    angle,
                    &Gable {
                        overhang_x: options.overhang_x,
                        overhang_y: options.overhang_y,
                        ridge_edge: edge,
                    },
                ),
                RoofKind::Hip => roof_hip(&points, angle, options.overhang_x),
                RoofKind::Pyramid => roof_pyramid(&points, angle),
                RoofKind::Shed => roof_shed(&points, angle, edge.unwrap_or(0)),
                RoofKind::Ridge => roof_ridge(&points, angle, ridge),
            };
            let Some(built) = built else {
                return Err(DeriveError::at(
                    format!(
                        "cannot build this roof: the angle must be between 0 and 90 degrees (it is \
                         {angle}), any overhang not negative (a gable's overhangY may be, if \
                         some roof is left), and the face a simple polygon"
                    ),
                    span,
                ));
            };
            if up == DVec3::ZERO {
                up = world.face_normal(f);
            }
            if self.program.tagged {
                let walls = match kind {
                    RoofKind::Gable => "roof.side",
                    _ => "roof.side.outer",
                };
                let source = face_tags(state, f);
                let normal = world.face_normal(f);
                tags.extend(auto_tags::by_facing(
                    &built,
                    &source,
                    normal,
                    "roof",
                    |facing| match facing {
                        Facing::Down => "roof.bottom",
                        Facing::Upright => walls,
                        Facing::Level | Facing::Slope => "roof.top",
                    },
                ));
            }
            solid.append(&built);
        }
        let fitted = Scope::fit(
            grown_axes(&state.scope, up),
            solid.positions().iter().copied(),
        );
        solid.transform(&fitted.world_to_local());
        state.scope = fitted;
        state.geometry = Geometry::tagged_mesh(solid, tags);
        Ok(())
    }

    /// CGA `taper(height)`: a pyramid over the first face of a flat shape, its apex `height`
    /// along the face's normal over its centroid; the scope keeps x and has y along the normal.
    pub(super) fn pyramid(
        &mut self,
        state: &mut State,
        height: &CExpr,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let h = self.ev.number(height, state, args)?;
        let world = flat_faces(state, "taper", span)?;
        let points: Vec<DVec3> = world.face_points(0).collect();
        let Some(mut solid) = pyramid(&points, h) else {
            return Err(DeriveError::at(
                format!(
                    "cannot build a pyramid {h} high: the height must not be 0 and the face must be a simple polygon"
                ),
                span,
            ));
        };
        let fitted = Scope::fit(
            grown_axes(&state.scope, world.face_normal(0)),
            solid.positions().iter().copied(),
        );
        // Face 0 is the base; the others rise from its edges.
        let tags = if self.program.tagged {
            let source = face_tags(state, 0);
            (0..solid.face_count())
                .map(|f| {
                    let tag = if f == 0 { "taper.bottom" } else { "taper.side" };
                    FaceTags::with_names(auto_tags::renamed(&source.names, "taper", tag))
                })
                .collect()
        } else {
            Vec::new()
        };
        solid.transform(&fitted.world_to_local());
        state.scope = fitted;
        state.geometry = Geometry::tagged_mesh(solid, tags);
        Ok(())
    }

    /// The value and options of a roof, by position: overhangX, overhangY (overhangX when not
    /// given: Shapegram's two-argument gable has always overhung all round), even (no effect),
    /// index for a gable roof; overhang and even for a hip roof; the edge for a shed roof.
    fn roof_options(
        &mut self,
        state: &mut State,
        kind: RoofKind,
        by_height: bool,
        params: &[CExpr],
        args: &[Value],
    ) -> Fallible<RoofOptions> {
        let mut number = |i: usize, state: &mut State| -> Fallible<Option<f64>> {
            params
                .get(i)
                .map(|e| self.ev.number(e, state, args))
                .transpose()
        };
        let value = number(0, state)?.unwrap_or(0.0);
        let (overhang_x, overhang_y, edge_at) = match kind {
            RoofKind::Gable => (number(1, state)?, number(2, state)?, Some(4)),
            RoofKind::Hip => (number(1, state)?, None, None),
            RoofKind::Pyramid | RoofKind::Ridge => (None, None, None),
            RoofKind::Shed => (None, None, Some(1)),
        };
        let edge = match edge_at.and_then(|i| params.get(i)) {
            Some(e) => {
                let index = self.ev.number(e, state, args)?;
                if index.fract() != 0.0 {
                    return Err(DeriveError::at(
                        format!("a roof's edge index must be a whole number, not {index}"),
                        e.span,
                    ));
                }
                Some(index as i64)
            }
            None => None,
        };
        Ok(RoofOptions {
            value,
            by_height,
            overhang_x: overhang_x.unwrap_or(0.0),
            overhang_y: overhang_y.or(overhang_x).unwrap_or(0.0),
            edge,
        })
    }
}

/// The angle of a roof over `points`: the value, or with `byHeight` the angle at which the roof
/// reaches that height over this face.
fn angle_of(
    kind: RoofKind,
    options: &RoofOptions,
    (edge, ridge): (Option<usize>, DVec3),
    points: &[DVec3],
    span: Span,
) -> Fallible<f64> {
    if !options.by_height {
        return Ok(options.value);
    }
    let shape = match kind {
        RoofKind::Gable => RoofShape::Gable(edge),
        RoofKind::Hip => RoofShape::Hip,
        RoofKind::Pyramid => RoofShape::Pyramid,
        RoofKind::Shed => RoofShape::Shed(edge.unwrap_or(0)),
        RoofKind::Ridge => RoofShape::Ridge(ridge),
    };
    let height = options.value;
    let run = roof_run(points, shape).filter(|_| height > 0.0 && height.is_finite());
    let Some(run) = run else {
        return Err(DeriveError::at(
            format!(
                "cannot build this roof {height} high: the height must be more than 0 and the \
                 face a simple polygon"
            ),
            span,
        ));
    };
    Ok((height / run).atan().to_degrees())
}
