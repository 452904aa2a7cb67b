//! What CGA's `geometry.*` functions ask of a shape's mesh: whether its faces are rectangles,
//! planar or convex, how many edges it has and how long its boundary is. Meshes are welded
//! first (faces of a box share no vertices), so that edges are counted once.

use crate::{DVec3, Mesh};

/// Welding tolerance relative to the mesh's size.
const WELD: f64 = 1e-9;

/// A mesh with coincident vertices merged.
fn welded(mesh: &Mesh) -> Mesh {
    let size = mesh
        .bounds()
        .map_or(1.0, |b| b.size().max_element().max(1.0));
    mesh.welded(WELD * size)
}

/// The corners of face `f` that are not degenerate, as (previous, corner, next) points.
fn corners(mesh: &Mesh, f: usize) -> Vec<(DVec3, DVec3, DVec3)> {
    let points: Vec<DVec3> = mesh.face_points(f).collect();
    let n = points.len();
    (0..n)
        .map(|i| (points[(i + n - 1) % n], points[i], points[(i + 1) % n]))
        .filter(|(a, b, c)| (*a - *b).length_squared() > 0.0 && (*c - *b).length_squared() > 0.0)
        .collect()
}

/// At least one face, and every face has four corners, each within `tolerance` degrees of a
/// right angle (`geometry.isRectangular`).
pub fn is_rectangular(mesh: &Mesh, tolerance: f64) -> bool {
    mesh.face_count() > 0
        && (0..mesh.face_count()).all(|f| {
            let corners = corners(mesh, f);
            corners.len() == 4
                && corners.iter().all(|(a, b, c)| {
                    let angle = (*a - *b).angle_between(*c - *b).to_degrees();
                    (angle - 90.0).abs() <= tolerance
                })
        })
}

/// Some face turns the other way at a corner (`geometry.isConcave`); collinear corners count
/// as convex.
pub fn is_concave(mesh: &Mesh) -> bool {
    (0..mesh.face_count()).any(|f| {
        let normal = mesh.face_normal(f);
        let corners = corners(mesh, f);
        let scale = corners
            .iter()
            .map(|(a, b, _)| (*a - *b).length_squared())
            .fold(0.0, f64::max);
        corners
            .iter()
            .any(|(a, b, c)| (*b - *a).cross(*c - *b).dot(normal) < -1e-12 * scale)
    })
}

/// At least one face, and at every corner the plane of its two edges is within `tolerance`
/// degrees of the face's plane (`geometry.isPlanar`).
pub fn is_planar(mesh: &Mesh, tolerance: f64) -> bool {
    mesh.face_count() > 0
        && (0..mesh.face_count()).all(|f| {
            let normal = mesh.face_normal(f);
            corners(mesh, f).iter().all(|(a, b, c)| {
                let corner = (*b - *a).cross(*c - *b);
                // Collinear corners have no plane of their own.
                corner.length_squared() == 0.0
                    || corner
                        .angle_between(normal)
                        .to_degrees()
                        .min(180.0 - corner.angle_between(normal).to_degrees())
                        <= tolerance
            })
        })
}

/// At least one face, and every edge shared by exactly two faces (`geometry.isClosedSurface`).
pub fn is_closed_surface(mesh: &Mesh) -> bool {
    let welded = welded(mesh);
    welded.face_count() > 0
        && welded
            .edges()
            .iter()
            .all(|e| e.forward.len() + e.backward.len() == 2)
}

/// The number of distinct edges (`geometry.nEdges`).
pub fn edge_count(mesh: &Mesh) -> usize {
    welded(mesh).edges().len()
}

/// The total length of the edges that bound the surface: those of one face only
/// (`geometry.boundaryLength`).
pub fn boundary_length(mesh: &Mesh) -> f64 {
    let welded = welded(mesh);
    welded
        .edges()
        .iter()
        .filter(|e| e.forward.len() + e.backward.len() == 1)
        .map(|e| (welded.position(e.a) - welded.position(e.b)).length())
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    fn quad(points: [[f64; 2]; 4]) -> Mesh {
        Mesh::from_polygon(&points.map(|[x, z]| DVec3::new(x, 0.0, z)))
    }

    #[test]
    fn boxes_are_rectangular_planar_convex_and_closed() {
        let cube = primitives::cuboid(DVec3::new(2.0, 3.0, 4.0));
        assert!(is_rectangular(&cube, 0.0));
        assert!(is_planar(&cube, 0.0));
        assert!(!is_concave(&cube));
        assert!(is_closed_surface(&cube));
        assert_eq!(edge_count(&cube), 12);
        assert_eq!(boundary_length(&cube), 0.0);
    }

    #[test]
    fn rectangles_rhombi_and_notched_faces() {
        let rectangle = quad([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]);
        assert!(is_rectangular(&rectangle, 0.0));
        assert!(!is_closed_surface(&rectangle));
        assert_eq!(edge_count(&rectangle), 4);
        assert_eq!(boundary_length(&rectangle), 14.0);
        // A parallelogram with corners of 80° and 100°: rectangular within 10°, not within 5°.
        let slant = 3.0 * 10f64.to_radians().tan();
        let rhombus = quad([[0.0, 0.0], [4.0, 0.0], [4.0 + slant, 3.0], [slant, 3.0]]);
        assert!(is_rectangular(&rhombus, 10.0 + 1e-9) && !is_rectangular(&rhombus, 5.0));
        let notched = Mesh::from_polygon(
            &[[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [2.0, 1.0], [0.0, 3.0]]
                .map(|[x, z]| DVec3::new(x, 0.0, z)),
        );
        assert!(is_concave(&notched) && !is_rectangular(&notched, 45.0));
        assert!(!is_concave(&rectangle));
        assert!(!is_rectangular(&Mesh::new(), 90.0));
    }
}
