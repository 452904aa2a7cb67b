//! CityEngine's roof edge selectors for `comp(e)`: `eave`, `hip`, `valley` and `ridge`.
//!
//! Shapegram's roofs are closed, so their bottom is a face, not a border. An edge is an
//! **eave** when it is level (across the scope's y axis) and on the border of the geometry or
//! along a face that looks down; the other edges between two faces, none of them looking down,
//! are inner edges. An inner edge whose faces meet in a concavity is a **valley**; one that
//! touches an eave's end is a **hip**; any other is a **ridge**. Eaves run anticlockwise
//! around the roof seen from above; hips, valleys and ridges run upward.

use rustc_hash::FxHashSet;
use shapegram_geom::{DVec3, Mesh, component};

use crate::selectors::RoofEdge;

/// The roof edge kind of every edge component of a mesh.
pub(super) struct RoofEdges {
    kinds: Vec<Option<RoofEdge>>,
    up: DVec3,
    centre: DVec3,
}

impl RoofEdges {
    /// The kinds of the edge components `edges` of `mesh` (world space), `up` being the
    /// scope's y axis.
    pub fn new(mesh: &Mesh, edges: &[component::Component], up: DVec3) -> Self {
        let topology = mesh.edges();
        let size = mesh
            .bounds()
            .map_or(1.0, |b| b.size().max_element())
            .max(f64::MIN_POSITIVE);
        let eps = 1e-9 * size;
        let down = |f: usize| mesh.face_normal(f).dot(up) < -0.999;
        let faces_of = |e: &component::Component| {
            let t = &topology[e.source];
            t.forward
                .iter()
                .chain(&t.backward)
                .copied()
                .collect::<Vec<_>>()
        };
        let level = |e: &component::Component| {
            (e.points[1] - e.points[0])
                .normalize_or_zero()
                .dot(up)
                .abs()
                < 1e-9
        };
        let mut kinds: Vec<Option<RoofEdge>> = edges
            .iter()
            .map(|e| {
                let faces = faces_of(e);
                let eave = level(e) && (faces.len() == 1 || faces.iter().any(|&f| down(f)));
                eave.then_some(RoofEdge::Eave)
            })
            .collect();
        let key = |p: DVec3| p.to_array().map(|x| (x + 0.0).to_bits());
        let eave_ends: FxHashSet<[u64; 3]> = edges
            .iter()
            .zip(&kinds)
            .filter(|(_, k)| k.is_some())
            .flat_map(|(e, _)| e.points.iter().map(|&p| key(p)))
            .collect();
        for (e, kind) in edges.iter().zip(kinds.iter_mut()) {
            let faces = faces_of(e);
            if kind.is_some() || faces.len() != 2 || faces.iter().any(|&f| down(f)) {
                continue;
            }
            let concave = mesh
                .face_points(faces[1])
                .any(|p| (p - e.points[0]).dot(mesh.face_normal(faces[0])) > eps);
            *kind = Some(if concave {
                RoofEdge::Valley
            } else if e.points.iter().any(|&p| eave_ends.contains(&key(p))) {
                RoofEdge::Hip
            } else {
                RoofEdge::Ridge
            });
        }
        let count = mesh.vertex_count().max(1) as f64;
        Self {
            kinds,
            up,
            centre: mesh.positions().iter().sum::<DVec3>() / count,
        }
    }

    /// The kind of edge component `c`, if it is a roof edge.
    pub fn kind(&self, c: usize) -> Option<RoofEdge> {
        self.kinds.get(c).copied().flatten()
    }

    /// Edge component `c` turned the way its kind runs: an eave anticlockwise seen from above,
    /// the others upward.
    pub fn oriented(&self, edge: &component::Component, c: usize) -> component::Component {
        let along = edge.points[1] - edge.points[0];
        let forward = match self.kind(c) {
            Some(RoofEdge::Eave) => {
                let middle = 0.5 * (edge.points[0] + edge.points[1]);
                along.dot(self.up.cross(middle - self.centre)) >= 0.0
            }
            Some(_) => along.dot(self.up) >= 0.0,
            None => true,
        };
        if forward {
            edge.clone()
        } else {
            component::reversed_edge(edge)
        }
    }
}
