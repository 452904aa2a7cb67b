//! CGA `innerRectangle(scope | edge) { shape : … | remainder : … }` and the deprecated
//! `innerRect`: the largest rectangle inside each face of a flat shape.

use std::sync::Arc;

use shapegram_geom::{
    DVec3, Mesh, Scope,
    inner_rectangle::{around_rectangle, inner_rectangle},
};
use shapegram_syntax::Span;

use super::Fallible;
use super::footprint::{Piece, SetbackOutputs, flat_faces};
use super::machine::{Engine, Work};
use crate::shape::{Geometry, State};
use crate::value::Value;

impl<'p> Engine<'p> {
    /// The largest rectangle in every face of a flat shape, its sides along the scope's axes
    /// (the two the face's normal is least along) or, with `edge`, along one of the face's edges
    /// at least a quarter as long as its longest. With `split`, the rectangles go to `shape` and
    /// the rest of the faces to `remainder`, each with the shape's axes; without (`innerRect`),
    /// the rectangles become the shape's geometry.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn inner_rectangle(
        &mut self,
        state: &mut State,
        edge: bool,
        outputs: SetbackOutputs<'p>,
        split: bool,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let name = if split { "innerRectangle" } else { "innerRect" };
        let world = flat_faces(state, name, span)?;
        let scope = state.scope;
        let mut rectangles: Vec<Vec<DVec3>> = Vec::new();
        let mut rest: Vec<Vec<DVec3>> = Vec::new();
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let found = if edge {
                along_an_edge(&points)
            } else {
                inner_rectangle(&points, across(&scope, world.face_normal(f)))
            };
            match found {
                Some(rectangle) => {
                    rest.extend(around_rectangle(&points, &rectangle));
                    rectangles.push(rectangle.to_vec());
                }
                None => rest.push(points),
            }
        }
        if !split {
            let mut mesh = Mesh::new();
            for rectangle in &rectangles {
                mesh.append(&Mesh::from_polygon(rectangle));
            }
            if mesh.is_empty() {
                return Ok(());
            }
            let fitted = Scope::fit(scope.axes, mesh.positions().iter().copied());
            mesh.transform(&fitted.world_to_local());
            state.scope = fitted;
            state.geometry = Geometry::Mesh(Arc::new(mesh), None);
            return Ok(());
        }
        for (entry, polygons) in [(outputs.shape, &rectangles), (outputs.remainder, &rest)] {
            let Some((merge, body)) = entry else {
                continue;
            };
            let pieces: Vec<Piece> = polygons
                .iter()
                .map(|p| (scope.axes, vec![p.as_slice()]))
                .collect();
            self.flat_children(state, pieces, *merge, 0, body, span, args, out)?;
        }
        Ok(())
    }
}

/// The direction of a rectangle's sides in `innerRectangle(scope)`: the scope axis after the
/// one the face's normal is most along (the other side is then the third axis, for a face
/// across that axis).
fn across(scope: &Scope, normal: DVec3) -> DVec3 {
    let local = scope.direction_to_local(normal).abs();
    let most = if local.y >= local.x && local.y >= local.z {
        1
    } else if local.z >= local.x {
        2
    } else {
        0
    };
    scope.axes.col((most + 1) % 3)
}

/// The largest rectangle with a side along one of the polygon's edges at least a quarter as
/// long as its longest (the first edge's on a tie).
fn along_an_edge(points: &[DVec3]) -> Option<[DVec3; 4]> {
    let n = points.len();
    let edges: Vec<DVec3> = (0..n).map(|i| points[(i + 1) % n] - points[i]).collect();
    let longest = edges.iter().map(|e| e.length()).fold(0.0, f64::max);
    let area = |r: &[DVec3; 4]| r[0].distance(r[1]) * r[0].distance(r[3]);
    edges
        .iter()
        .filter(|e| e.length() >= 0.25 * longest && e.length() > 0.0)
        .filter_map(|&e| inner_rectangle(points, e))
        .fold(None, |best: Option<[DVec3; 4]>, r| match best {
            Some(b) if area(&b) >= area(&r) => Some(b),
            _ => Some(r),
        })
}
