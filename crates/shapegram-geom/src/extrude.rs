//! Extrusion of polygons and of mesh faces.

use crate::{DVec3, Mesh, mesh::newell};

/// Extrudes a planar polygon (counter-clockwise about its normal) by `distance` along its normal
/// into a closed prism: the polygon itself, reversed, is the bottom. A negative distance extrudes
/// backwards, so the polygon becomes the top. Returns `None` for a polygon without area or a
/// distance of zero (or not finite).
pub fn extrude_polygon(points: &[DVec3], distance: f64) -> Option<Mesh> {
    let normal = newell(points.iter().copied()).normalize_or_zero();
    extrude_along(points, normal * distance)
}

/// A copy of `mesh` where face `face` is pushed out along its normal by `distance` and joined to
/// its old outline by side walls, so a closed mesh stays closed. Vertices of the face are not
/// shared with the moved copy; faces around the face keep their vertices.
pub fn extrude_face(mesh: &Mesh, face: usize, distance: f64) -> Mesh {
    let normal = mesh.face_normal(face);
    let outline = mesh.face(face).to_vec();
    let mut out = Mesh::from_faces(
        mesh.positions().to_vec(),
        mesh.faces()
            .enumerate()
            .filter(|&(f, _)| f != face)
            .map(|(_, l)| l),
    );
    let moved: Vec<u32> = outline
        .iter()
        .map(|&v| out.add_vertex(mesh.position(v) + normal * distance))
        .collect();
    out.add_face(&moved);
    let n = outline.len();
    for i in 0..n {
        let j = (i + 1) % n;
        // The wall takes over the face's edge i → j, whichever way the face moved.
        out.add_face(&[outline[i], outline[j], moved[j], moved[i]]);
    }
    out
}

/// Sweeps a planar polygon along `offset` (any direction not in its plane) into a closed
/// prism, e.g. straight up for CGA's `extrude(world.up, h)` on a sloped face. Returns `None` for
/// a polygon without area or an offset parallel to its plane.
pub fn extrude_along(points: &[DVec3], offset: DVec3) -> Option<Mesh> {
    let normal = newell(points.iter().copied()).normalize_or_zero();
    let rise = normal.dot(offset);
    if normal == DVec3::ZERO || !rise.is_finite() || rise.abs() <= 1e-12 * offset.length() {
        return None;
    }
    // Sweeping against the normal turns the prism inside out: start from the far end instead.
    let (base, lift) = if rise > 0.0 {
        (DVec3::ZERO, offset)
    } else {
        (offset, -offset)
    };
    let n = points.len() as u32;
    let mut positions: Vec<DVec3> = points.iter().map(|&p| p + base).collect();
    positions.extend(points.iter().map(|&p| p + base + lift));
    let mut mesh = Mesh::from_faces(positions, [(0..n).rev().collect::<Vec<_>>()]);
    mesh.add_face(&(n..2 * n).collect::<Vec<_>>());
    for i in 0..n {
        let j = (i + 1) % n;
        mesh.add_face(&[i, j, n + j, n + i]);
    }
    Some(mesh)
}
