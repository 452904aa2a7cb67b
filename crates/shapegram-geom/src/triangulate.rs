//! Triangulation of planar polygons, convex or not.

use earcut::Earcut;

use crate::{DVec2, DVec3, Mesh, mesh::newell};

/// Reusable triangulator: keeps its buffers between calls.
#[derive(Default)]
pub struct Triangulator {
    earcut: Earcut<f64>,
    flat: Vec<[f64; 2]>,
    out: Vec<u32>,
}

impl Triangulator {
    /// A triangulator with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Triangulates a planar loop with optional holes, given as 3D points. The outer loop is
    /// `points[..hole_starts[0]]` (or all points), hole `k` starts at `hole_starts[k]`.
    /// Returned triangles index into `points` and wind like the outer loop.
    pub fn triangulate(&mut self, points: &[DVec3], hole_starts: &[usize]) -> Vec<[u32; 3]> {
        let outer_len = hole_starts.first().copied().unwrap_or(points.len());
        let n = points.len();
        if outer_len < 3 {
            return Vec::new();
        }
        if n == 3 && hole_starts.is_empty() {
            return vec![[0, 1, 2]];
        }
        if hole_starts.is_empty() && is_convex(points) {
            // Collinear corners would give slivers of zero area; the other fan triangles cover.
            // The test is on the sine of the angle at the hub, so the thin but real triangles of
            // a finely divided circle are kept.
            return (1..n as u32 - 1)
                .map(|i| [0, i, i + 1])
                .filter(|t| {
                    let [a, b, c] = t.map(|i| points[i as usize]);
                    let (ab, ac) = (b - a, c - a);
                    ab.cross(ac).length() > 1e-12 * ab.length() * ac.length()
                })
                .collect();
        }
        let normal = newell(points[..outer_len].iter().copied()).normalize_or_zero();
        if normal == DVec3::ZERO {
            return Vec::new();
        }
        let (u, v) = plane_basis(normal);
        let origin = points[0];
        self.flat.clear();
        self.flat.extend(points.iter().map(|&p| {
            let d = p - origin;
            [d.dot(u), d.dot(v)]
        }));
        let holes: Vec<u32> = hole_starts.iter().map(|&h| h as u32).collect();
        self.earcut.earcut_slice(&self.flat, &holes, &mut self.out);
        // Earcut may wind either way; make every triangle agree with the outer loop.
        self.out
            .chunks_exact(3)
            .map(|t| {
                let tri = [t[0], t[1], t[2]];
                let [a, b, c] = tri.map(|i| {
                    let f = self.flat[i as usize];
                    DVec2::new(f[0], f[1])
                });
                if (b - a).perp_dot(c - a) < 0.0 {
                    [tri[0], tri[2], tri[1]]
                } else {
                    tri
                }
            })
            .collect()
    }
}

/// Two unit vectors spanning the plane with the given unit normal, so that `(u, v, normal)` is
/// right-handed.
pub fn plane_basis(normal: DVec3) -> (DVec3, DVec3) {
    let u = normal.any_orthonormal_vector();
    (u, normal.cross(u))
}

/// Whether a planar loop is convex (no reflex corner; collinear corners allowed).
pub fn is_convex(points: &[DVec3]) -> bool {
    let normal = newell(points.iter().copied());
    let n = points.len();
    (0..n).all(|i| {
        let a = points[i];
        let b = points[(i + 1) % n];
        let c = points[(i + 2) % n];
        (b - a).cross(c - b).dot(normal) >= -1e-12 * normal.length() * (c - a).length()
    })
}

impl Mesh {
    /// Triangles covering every face, indexing this mesh's vertices, in face order.
    pub fn triangulate(&self) -> Vec<[u32; 3]> {
        let mut triangulator = Triangulator::new();
        let mut points = Vec::new();
        let mut triangles = Vec::with_capacity(self.face_count() * 2);
        for face in self.faces() {
            points.clear();
            points.extend(face.iter().map(|&v| self.position(v)));
            triangles.extend(
                triangulator
                    .triangulate(&points, &[])
                    .into_iter()
                    .map(|t| t.map(|i| face[i as usize])),
            );
        }
        triangles
    }

    /// Number of triangles of [`Mesh::triangulate`] whose area is below `min_area`.
    pub fn degenerate_triangle_count(&self, min_area: f64) -> usize {
        self.triangulate()
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| self.position(i));
                0.5 * (b - a).cross(c - a).length() < min_area
            })
            .count()
    }
}
