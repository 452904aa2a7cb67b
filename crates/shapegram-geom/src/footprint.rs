//! The footprint of a mesh (CGA's `footprint()`): what it covers, seen along an up direction.

use crate::{DVec3, Mesh};

/// The footprint of a mesh (CGA's `footprint()`): its faces that look down (`-up`) projected
/// onto the plane through the origin across `up` (unit length), turned to look up; for a mesh
/// with no face looking down (a lot, a wall seen from above), the faces that look up. Faces
/// standing upright project to nothing and are left out; overlapping projections stay
/// separate faces.
pub fn footprint(mesh: &Mesh, up: DVec3) -> Mesh {
    let facing = |f: usize| mesh.face_normal(f).dot(up);
    let tilt = 1e-9;
    let down: Vec<usize> = (0..mesh.face_count())
        .filter(|&f| facing(f) < -tilt)
        .collect();
    let (faces, flip) = if down.is_empty() {
        (
            (0..mesh.face_count())
                .filter(|&f| facing(f) > tilt)
                .collect(),
            false,
        )
    } else {
        (down, true)
    };
    let mut out = Mesh::new();
    for f in faces {
        let mut points: Vec<DVec3> = mesh.face_points(f).map(|p| p - up * p.dot(up)).collect();
        if flip {
            points.reverse();
        }
        out.append(&Mesh::from_polygon(&points));
    }
    out
}
