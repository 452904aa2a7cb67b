//! Random points on and in meshes (CGA's `scatter`), from random numbers the caller draws, so
//! that the caller's random stream keeps derivations deterministic.

use crate::{DVec3, Mesh};

/// Uniform points on the surface of a mesh, and tests for points inside it.
pub struct Sampler {
    triangles: Vec<[DVec3; 3]>,
    /// Running totals of the triangles' areas.
    totals: Vec<f64>,
    closed: bool,
}

impl Sampler {
    /// A sampler over the faces of `mesh`.
    pub fn new(mesh: &Mesh) -> Self {
        let triangles: Vec<[DVec3; 3]> = mesh
            .triangulate()
            .into_iter()
            .map(|t| t.map(|i| mesh.position(i)))
            .collect();
        let mut total = 0.0;
        let totals = triangles
            .iter()
            .map(|[a, b, c]| {
                total += 0.5 * (*b - *a).cross(*c - *a).length();
                total
            })
            .collect();
        Self {
            triangles,
            totals,
            closed: mesh.is_watertight(),
        }
    }

    /// The mesh's area.
    pub fn area(&self) -> f64 {
        self.totals.last().copied().unwrap_or(0.0)
    }

    /// Whether the mesh is a closed surface, so that it has an inside.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// The point of the surface for three numbers in `[0, 1)`: the first picks a triangle by
    /// area, the others a point in it, uniformly. Returns the point and the triangle's unit
    /// normal; `None` for a mesh without area.
    pub fn on_surface(&self, r: [f64; 3]) -> Option<(DVec3, DVec3)> {
        let area = self.area();
        if area <= 0.0 {
            return None;
        }
        let target = r[0] * area;
        let k = self
            .totals
            .partition_point(|&t| t <= target)
            .min(self.triangles.len() - 1);
        let [a, b, c] = self.triangles[k];
        let (mut s, mut t) = (r[1], r[2]);
        if s + t > 1.0 {
            (s, t) = (1.0 - s, 1.0 - t);
        }
        let normal = (b - a).cross(c - a).normalize_or_zero();
        Some((a + (b - a) * s + (c - a) * t, normal))
    }

    /// Whether a point lies inside the closed mesh: a ray from it crosses the surface an odd
    /// number of times. The ray leans off the axes so that it meets no edge exactly on
    /// ordinary building geometry.
    pub fn contains(&self, p: DVec3) -> bool {
        let dir = DVec3::new(0.577_215_664_9, 0.321_928_094_9, 0.750_173_611_2).normalize();
        let mut inside = false;
        for [a, b, c] in &self.triangles {
            // Möller–Trumbore.
            let (e1, e2) = (*b - *a, *c - *a);
            let h = dir.cross(e2);
            let det = e1.dot(h);
            if det.abs() < 1e-300 {
                continue;
            }
            let f = 1.0 / det;
            let s = p - *a;
            let u = f * s.dot(h);
            let q = s.cross(e1);
            let v = f * dir.dot(q);
            if (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && f * e2.dot(q) > 0.0 {
                inside = !inside;
            }
        }
        inside
    }
}
