//! CGA's uv queries: `geometry.hasUVs([uvSet])`, `geometry.uMin/uMax/vMin/vMax([uvSet])` and
//! `geometry.du/dv(uvSet, uvSpace | unitSpace)`, read from the shape's uv sets (see
//! [`crate::texturing`]) at the vertices of its geometry. Without the argument, the sets are
//! read from set 0, which is the uvs an inserted asset brought until `projectUV(0)` replaces
//! them; without uvs (or geometry), the bounds and extents are 0.

use shapegram_geom::DVec2;

use crate::asset_look::WornAsset;
use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::program::{CExpr, CKind};
use crate::shape::{Geometry, State};
use crate::texturing::{UV_SETS, UvMap};
use crate::value::Value;

/// A uv query.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UvQuery {
    HasUvs,
    UMin,
    UMax,
    VMin,
    VMax,
    Du,
    Dv,
}

/// Each query with its name, fewest and most arguments, and signature.
const TABLE: &[(UvQuery, &str, usize, usize, &str)] = &[
    (
        UvQuery::HasUvs,
        "geometry.hasUVs",
        0,
        1,
        "geometry.hasUVs([uvSet])",
    ),
    (
        UvQuery::UMin,
        "geometry.uMin",
        0,
        1,
        "geometry.uMin([uvSet])",
    ),
    (
        UvQuery::UMax,
        "geometry.uMax",
        0,
        1,
        "geometry.uMax([uvSet])",
    ),
    (
        UvQuery::VMin,
        "geometry.vMin",
        0,
        1,
        "geometry.vMin([uvSet])",
    ),
    (
        UvQuery::VMax,
        "geometry.vMax",
        0,
        1,
        "geometry.vMax([uvSet])",
    ),
    (
        UvQuery::Du,
        "geometry.du",
        2,
        2,
        "geometry.du(uvSet, uvSpace | unitSpace)",
    ),
    (
        UvQuery::Dv,
        "geometry.dv",
        2,
        2,
        "geometry.dv(uvSet, uvSpace | unitSpace)",
    ),
];

impl UvQuery {
    /// The query called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        TABLE.iter().find(|t| t.1 == name).map(|t| t.0)
    }

    /// Every query's name.
    pub fn names() -> impl Iterator<Item = &'static str> {
        TABLE.iter().map(|t| t.1)
    }

    fn entry(self) -> &'static (UvQuery, &'static str, usize, usize, &'static str) {
        TABLE
            .iter()
            .find(|t| t.0 == self)
            .expect("every query is in the table")
    }

    /// Fewest and most arguments.
    pub fn arity(self) -> (usize, usize) {
        let e = self.entry();
        (e.2, e.3)
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        self.entry().4
    }
}

impl Evaluator<'_> {
    /// The value of a uv query for the shape.
    pub(crate) fn uv_query(
        &mut self,
        query: UvQuery,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value, DeriveError> {
        let set = match params.first() {
            Some(p) => {
                let n = self.number(p, shape, args)?;
                if n.fract() != 0.0 || !(0.0..UV_SETS as f64).contains(&n) {
                    return Err(DeriveError::at(
                        format!("uv set {n}: expected a whole number from 0 to 9"),
                        p.span,
                    ));
                }
                n as usize
            }
            None => 0,
        };
        let in_metres = match params.get(1) {
            None => false,
            Some(p) => match &p.kind {
                CKind::Selector(w) if w == "uvSpace" => false,
                CKind::Selector(w) if w == "unitSpace" => true,
                _ => {
                    return Err(DeriveError::at("expected `uvSpace` or `unitSpace`", p.span));
                }
            },
        };
        let texturing = shape.texturing.as_ref();
        let extent = match texturing.and_then(|t| t.uvs[set]) {
            Some(map) => uv_bounds(shape, &map).map(|bounds| (bounds, map.rates())),
            // Until `projectUV(0)` replaces them, set 0 is the uvs an inserted asset brought.
            None => texturing
                .and_then(|t| t.asset.as_ref())
                .filter(|_| set == 0)
                .and_then(|worn| asset_uv_extent(shape, worn)),
        };
        if query == UvQuery::HasUvs {
            return Ok(Value::Bool(extent.is_some()));
        }
        let Some(((low, high), rates)) = extent else {
            return Ok(Value::Number(0.0));
        };
        let extent = |i: usize| {
            let uv = high[i] - low[i];
            let rate = rates[i];
            match (in_metres, rate > 0.0) {
                (false, _) => uv,
                (true, true) => uv / rate,
                (true, false) => 0.0,
            }
        };
        Ok(Value::Number(match query {
            UvQuery::UMin => low.x,
            UvQuery::UMax => high.x,
            UvQuery::VMin => low.y,
            UvQuery::VMax => high.y,
            UvQuery::Du => extent(0),
            UvQuery::Dv => extent(1),
            UvQuery::HasUvs => unreachable!("answered above"),
        }))
    }
}

/// The smallest and largest uv over the shape's vertices; `None` without geometry.
fn uv_bounds(shape: &State, map: &UvMap) -> Option<(DVec2, DVec2)> {
    let mesh = shape.geometry.world_mesh(&shape.scope)?;
    let uvs = mesh.positions().iter().map(|&p| map.at(p));
    let (low, high) = uvs.fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(low, high), uv| (low.min(uv), high.max(uv)),
    );
    low.is_finite().then_some((low, high))
}

/// The bounds of uv set 0 that the asset `worn` brought, over the shape's geometry, and how
/// fast u and v grow per metre on its surface; `None` without geometry or uvs.
pub(crate) fn asset_uv_extent(shape: &State, worn: &WornAsset) -> Option<((DVec2, DVec2), DVec2)> {
    let mesh = shape.geometry.world_mesh(&shape.scope)?;
    let local = match &shape.geometry {
        Geometry::Mesh(local, _) => Some(&**local),
        _ => None,
    };
    worn.uv_extent(mesh, local)
}
