//! CGA `envelope(normal | world.up, maxHeight, …)`: the largest volume over each face of a flat
//! shape under a height limit and under planes rising inward from its edges.

use shapegram_geom::{DVec3, FaceClass, Mesh, Scope, envelope::envelope};
use shapegram_syntax::Span;

use super::Fallible;
use super::auto_tags::{self, Facing};
use super::footprint::{face_tags, flat_faces, grown_axes};
use super::machine::Engine;
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::selectors::SelectorFrame;
use crate::shape::{Geometry, State};
use crate::value::Value;

/// The base heights and angles of an envelope's edges.
enum EdgeRules {
    /// By the class of each edge's direction in the street frame (there being no streets, the
    /// initial shape's): front, back, right and left, each `(base, angle)`.
    ByClass([(f64, f64); 4]),
    /// Per face edge, face after face; missing ones are upright walls (base 0, 90°).
    PerEdge(Vec<(f64, f64)>),
}

/// An upright wall all the way up: an edge that cuts nothing.
const UPRIGHT: (f64, f64) = (0.0, 90.0);

impl Engine<'_> {
    /// The envelope over every face of a flat shape, extruded along the face's normal or world
    /// up; the result is a closed solid whose scope keeps x and has y along the extrusion.
    pub(super) fn envelope(
        &mut self,
        state: &mut State,
        world_up: bool,
        params: &[CExpr],
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let max_height = self.ev.number(&params[0], state, args)?;
        let rules = self.envelope_rules(state, &params[1..], args)?;
        let world = flat_faces(state, "envelope", span)?;
        let frames = self.ev.frames(&state.scope);
        let mut solid = Mesh::new();
        let mut tags = Vec::new();
        let mut direction = DVec3::ZERO;
        let mut first_edge = 0;
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let normal = world.face_normal(f);
            let up = if world_up { DVec3::Y } else { normal };
            let edges: Vec<(f64, f64)> = (0..points.len())
                .map(|i| {
                    let outward = (points[(i + 1) % points.len()] - points[i]).cross(normal);
                    match &rules {
                        EdgeRules::PerEdge(list) => {
                            list.get(first_edge + i).copied().unwrap_or(UPRIGHT)
                        }
                        EdgeRules::ByClass(by) => {
                            match frames.class(outward, SelectorFrame::Street) {
                                FaceClass::Back => by[1],
                                FaceClass::Right => by[2],
                                FaceClass::Left => by[3],
                                _ => by[0],
                            }
                        }
                    }
                })
                .collect();
            first_edge += points.len();
            let Some(built) = envelope(&points, up, max_height, &edges) else {
                return Err(DeriveError::at(
                    format!(
                        "cannot build this envelope: the height must be more than 0 (it is \
                         {max_height}), base heights 0 or more, angles more than 0, the direction \
                         on the face's front side, and some volume left"
                    ),
                    span,
                ));
            };
            if direction == DVec3::ZERO {
                direction = up;
            }
            if self.program.tagged {
                let source = face_tags(state, f);
                tags.extend(auto_tags::by_facing(
                    &built,
                    &source,
                    up,
                    "envelope",
                    |facing| match facing {
                        Facing::Down => "envelope.bottom",
                        Facing::Upright => "envelope.side.base",
                        Facing::Slope => "envelope.side.slope",
                        Facing::Level => "envelope.top",
                    },
                ));
            }
            solid.append(&built);
        }
        let fitted = Scope::fit(
            grown_axes(&state.scope, direction),
            solid.positions().iter().copied(),
        );
        solid.transform(&fitted.world_to_local());
        state.scope = fitted;
        state.geometry = Geometry::tagged_mesh(solid, tags);
        Ok(())
    }

    /// The base heights and angles after `maxHeight`: two arrays, or pairs for front, back, the
    /// sides (or right and left), the missing ones upright.
    fn envelope_rules(
        &mut self,
        state: &mut State,
        params: &[CExpr],
        args: &[Value],
    ) -> Fallible<EdgeRules> {
        let values = params
            .iter()
            .map(|e| self.ev.eval(e, state, args))
            .collect::<Fallible<Vec<_>>>()?;
        let number = |i: usize| match &values[i] {
            Value::Number(n) => Ok(*n),
            other => Err(DeriveError::at(
                format!(
                    "envelope: expected a number, or two arrays of base heights and angles, found {}",
                    other.type_name()
                ),
                params[i].span,
            )),
        };
        if let [Value::Array(bases), Value::Array(angles)] = values.as_slice() {
            let numbers = |list: &[Value], i: usize| -> Fallible<Vec<f64>> {
                list.iter()
                    .map(|v| match v {
                        Value::Number(n) => Ok(*n),
                        other => Err(DeriveError::at(
                            format!("envelope: expected numbers in the array, found {other}"),
                            params[i].span,
                        )),
                    })
                    .collect()
            };
            let (bases, angles) = (numbers(bases, 0)?, numbers(angles, 1)?);
            let count = bases.len().max(angles.len());
            return Ok(EdgeRules::PerEdge(
                (0..count)
                    .map(|k| {
                        (
                            bases.get(k).copied().unwrap_or(UPRIGHT.0),
                            angles.get(k).copied().unwrap_or(UPRIGHT.1),
                        )
                    })
                    .collect(),
            ));
        }
        let pair = |k: usize| -> Fallible<Option<(f64, f64)>> {
            if 2 * k + 1 < values.len() {
                Ok(Some((number(2 * k)?, number(2 * k + 1)?)))
            } else {
                Ok(None)
            }
        };
        let front = pair(0)?.unwrap_or(UPRIGHT);
        let back = pair(1)?.unwrap_or(UPRIGHT);
        let (right, left) = match (pair(2)?, pair(3)?) {
            (Some(right), Some(left)) => (right, left),
            (Some(side), None) => (side, side),
            _ => (UPRIGHT, UPRIGHT),
        };
        Ok(EdgeRules::ByClass([front, back, right, left]))
    }
}
