//! Questions about the shape itself: its scope, split and comp position, its geometry's
//! measures, a goal grammar's attributes and a value per face edge.

use std::sync::Arc;

use shapegram_geom::DVec3;
use shapegram_syntax::Span;
use shapegram_syntax::ast::AttributeKind;

use super::{Evaluator, Result};
use crate::builtins::{Builtin, Query};
use crate::error::DeriveError;
use crate::goals::AttrId;
use crate::ops::CompSelector;
use crate::program::CExpr;
use crate::shape::{Geometry, State};
use crate::value::Value;

impl Evaluator<'_> {
    /// `geometry.isOriented(selector)`: whether some face of the shape faces as the selector
    /// says; `geometry.area(selector)`: the area of those faces.
    pub(super) fn oriented(
        &mut self,
        b: Builtin,
        which: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let areas = self.faces_facing(which, shape, args)?;
        Ok(match b {
            Builtin::IsOriented => Value::Bool(!areas.is_empty()),
            _ => Value::Number(areas.iter().sum()),
        })
    }

    /// The areas of the shape's faces that face as a face selector of `comp(f)` says
    /// (`front`, `world.north`, `street.side`, …; `surface` is `all`), as `comp(f)` would
    /// select them.
    fn faces_facing(
        &mut self,
        which: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Vec<f64>> {
        let word = self.word(which, shape, args)?;
        let named = match &*word {
            "surface" => Some(CompSelector::All),
            other => crate::selectors::named(other),
        };
        let selector = named
            .filter(|s| !matches!(s, CompSelector::Inside | CompSelector::Border))
            .ok_or_else(|| {
                DeriveError::at(
                    format!(
                        "`{word}` is no orientation: expected a face selector such as `front`, `side`, `object.top`, `world.north` or `street.front`"
                    ),
                    which.span,
                )
            })?;
        let Some(mesh) = shape.geometry.world_mesh(&shape.scope) else {
            return Ok(Vec::new());
        };
        let frames = self.frames(&shape.scope);
        Ok((0..mesh.face_count())
            .filter(|&f| {
                selector
                    .takes_direction(mesh.face_normal(f), f, &frames)
                    .unwrap_or(false)
            })
            .map(|f| mesh.face_area(f))
            .collect())
    }

    pub(super) fn query(&self, q: Query, shape: &State) -> f64 {
        let scope = &shape.scope;
        match q {
            Query::ScopeSize(i) => scope.size[i],
            Query::ScopeOrigin(i) => scope.origin[i],
            Query::Elevation => scope.origin.y,
            Query::ScopeRotation(i) => euler_degrees(&scope.axes)[i],
            Query::SplitIndex => f64::from(shape.split.0),
            Query::SplitTotal => f64::from(shape.split.1),
            Query::CompIndex => f64::from(shape.comp.0),
            Query::CompTotal => f64::from(shape.comp.1),
            Query::GeometryArea => match &shape.geometry {
                Geometry::Empty => 0.0,
                g => g.local_mesh(scope.size).map_or(0.0, |m| m.area()),
            },
            Query::GeometryVolume => shape
                .geometry
                .local_mesh(scope.size)
                .map_or(0.0, |m| m.signed_volume().abs()),
            Query::GeometryVertices => shape
                .geometry
                .local_mesh(scope.size)
                .map_or(0.0, |m| m.vertex_count() as f64),
            Query::GeometryFaces => shape
                .geometry
                .local_mesh(scope.size)
                .map_or(0.0, |m| m.face_count() as f64),
            Query::GeometryHoles => 0.0,
            Query::InitialOrigin(i) => self.initial_origin[i],
            // A number in [0, 1) stable for the shape: CGA's `seedian`.
            Query::Seed => (crate::rng::mix(shape.seed) >> 11) as f64 / (1u64 << 53) as f64,
            Query::Depth => f64::from(shape.depth),
            Query::InitialRotation(i) => euler_degrees(&self.object_axes)[i],
            Query::CompSel | Query::StartRule | Query::InitialName | Query::TreeKey => {
                unreachable!("string queries are evaluated in `eval`")
            }
        }
    }

    /// `geometry.isRectangular(tolerance)` and the other questions about the shape's mesh
    /// (see `shapegram_geom::shape_metrics`); a shape without geometry has no faces.
    pub(super) fn measure(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        use shapegram_geom::shape_metrics as m;
        let tolerance = match params.first() {
            Some(p) => self.number(p, shape, args)?,
            None => 0.0,
        };
        let scope = shape.scope;
        if b == Builtin::Height {
            let height = shape
                .geometry
                .world_mesh(&scope)
                .and_then(|mesh| mesh.bounds())
                .map_or(0.0, |b| b.size().y);
            return Ok(Value::Number(height));
        }
        let mesh = shape.geometry.local_mesh(scope.size).unwrap_or_default();
        Ok(match b {
            Builtin::IsRectangular => Value::Bool(m::is_rectangular(&mesh, tolerance)),
            Builtin::IsConcave => Value::Bool(m::is_concave(&mesh)),
            Builtin::IsPlanar => Value::Bool(m::is_planar(&mesh, tolerance)),
            Builtin::IsClosedSurface => Value::Bool(m::is_closed_surface(&mesh)),
            Builtin::EdgeCount => Value::Number(m::edge_count(&mesh) as f64),
            _ => Value::Number(m::boundary_length(&mesh)),
        })
    }

    /// A named attribute of a goal grammar's shape, checked against the getter's type.
    pub(super) fn goal_attribute(
        &self,
        attr: AttrId,
        kind: AttributeKind,
        shape: &State,
        span: Span,
    ) -> Result<Value> {
        let name = || {
            self.program
                .goals
                .as_ref()
                .map_or("?", |g| &g.attributes[attr as usize])
                .to_owned()
        };
        let Some(value) = shape.semantics.as_ref().and_then(|s| s.get(attr)) else {
            return Err(DeriveError::at(
                format!("the shape has no attribute `{}`", name()),
                span,
            )
            .with_hint("only rules read attributes (they apply to shapes that have them); set it with `set(@name, value)`"));
        };
        let wanted = match (kind, value) {
            (AttributeKind::Number, Value::Number(_))
            | (AttributeKind::String, Value::Str(_))
            | (AttributeKind::Any, _) => return Ok(value.clone()),
            (AttributeKind::Number, _) => "a number (`@Double`)",
            (AttributeKind::String, _) => "a string (`@String`)",
        };
        Err(DeriveError::at(
            format!(
                "attribute `{}` is a {}, not {wanted}",
                name(),
                value.type_name()
            ),
            span,
        ))
    }

    /// `comp(fe) { selector : value | … }`: a value per edge of the shape's faces, face after
    /// face, each the value of the first entry whose selector takes it (evaluated once for the
    /// shape), else 0.
    pub(super) fn edge_values(
        &mut self,
        entries: &[(crate::ops::CompSelector, CExpr)],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let values = entries
            .iter()
            .map(|(_, e)| self.eval(e, shape, args))
            .collect::<Result<Vec<_>>>()?;
        let Some(world) = shape.geometry.world_mesh(&shape.scope) else {
            return Ok(Value::Array(Arc::from([])));
        };
        let mut out = Vec::new();
        for f in 0..world.face_count() {
            let normal = world.face_normal(f);
            let points: Vec<DVec3> = world.face_points(f).collect();
            for (i, &a) in points.iter().enumerate() {
                let b = points[(i + 1) % points.len()];
                let outward = (b - a).cross(normal);
                let value = entries
                    .iter()
                    .position(|(s, _)| s.takes_edge(outward, i, &self.frames(&shape.scope)))
                    .map_or(Value::Number(0.0), |k| values[k].clone());
                out.push(value);
            }
        }
        Ok(Value::Array(out.into()))
    }
}
/// `geometry.angle(…)`: of the shape's steepest face, its slope against the ground (degrees,
/// 0 flat, 90 upright), the compass direction it faces (degrees clockwise from north, −z; 0 for
/// a flat face), or 90 − the slope; 0 for a shape without faces.
pub(super) fn slope_angle(which: &str, shape: &State) -> std::result::Result<Value, String> {
    let steepest = shape.geometry.world_mesh(&shape.scope).and_then(|mesh| {
        (0..mesh.face_count())
            .map(|i| mesh.face_normal(i))
            .filter(|n| *n != DVec3::ZERO)
            .min_by(|a, b| a.y.abs().total_cmp(&b.y.abs()))
    });
    let slope = steepest.map_or(0.0, |n| n.y.abs().min(1.0).acos().to_degrees());
    Ok(Value::Number(match which {
        "maxSlope" => slope,
        "zenith" => 90.0 - slope,
        "azimuth" => steepest.map_or(0.0, |n| {
            if n.x.hypot(n.z) < 1e-12 {
                0.0
            } else {
                n.x.atan2(-n.z).to_degrees().rem_euclid(360.0)
            }
        }),
        other => {
            return Err(format!(
                "expected `maxSlope`, `azimuth` or `zenith`, found `{other}`"
            ));
        }
    }))
}

/// The Euler angles of a frame in degrees: intrinsic x, y, z, as `r(…)` turns.
fn euler_degrees(axes: &shapegram_geom::DMat3) -> [f64; 3] {
    let (x, y, z) = shapegram_geom::DQuat::from_mat3(axes).to_euler(glam::EulerRot::XYZ);
    [x, y, z].map(f64::to_degrees)
}
