//! Cleaning meshes up (CGA's `cleanupGeometry`): merging vertices that (nearly) coincide,
//! dropping corners on (nearly) straight lines and faces with (nearly) no area.
//!
//! One tolerance in `0..=1` sets every limit, as CityEngine's does: at 0 only exact duplicates,
//! exactly straight corners and faces without area go; at 1 vertices within 1 m merge, corners
//! within 10° of straight go and faces under 1 m² are dropped; in between the limits scale
//! linearly.

use crate::{DVec3, Mesh};

/// What [`cleanup`] cleans.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cleanup {
    /// Merge close vertices and drop straight corners.
    pub vertices: bool,
    /// Drop faces with little area.
    pub faces: bool,
}

/// Relative size below which lengths and areas count as zero at tolerance 0.
const ZERO: f64 = 1e-12;

/// A cleaned copy of `mesh` (see the module docs); faces left with fewer than three corners are
/// dropped, and unused vertices removed. A tolerance outside `0..=1` is clamped to it.
pub fn cleanup(mesh: &Mesh, what: Cleanup, tolerance: f64) -> Mesh {
    let t = if tolerance.is_nan() {
        0.0
    } else {
        tolerance.clamp(0.0, 1.0)
    };
    let scale = mesh.bounds().map_or(1.0, |b| b.diagonal().max(1e-300));
    let mut faces: Vec<Vec<u32>> = mesh.faces().map(<[u32]>::to_vec).collect();
    if what.vertices {
        let remap = merged(mesh.positions(), t * 1.0);
        for face in &mut faces {
            for v in face.iter_mut() {
                *v = remap[*v as usize];
            }
        }
        drop_repeats(&mut faces);
        drop_straight_corners(mesh.positions(), &mut faces, (t * 10.0).to_radians());
    }
    drop_repeats(&mut faces);
    if what.faces {
        let least = (t * 1.0).max(ZERO * scale * scale);
        faces.retain(|face| {
            let points: Vec<DVec3> = face.iter().map(|&v| mesh.position(v)).collect();
            crate::mesh::newell(points.iter().copied()).length() * 0.5 > least
        });
    }
    Mesh::from_faces(mesh.positions().to_vec(), faces).compacted()
}

/// For each vertex, the vertex it merges into: the first (by index) of those chained to it by
/// distances of at most `within` (exactly equal positions at 0).
fn merged(positions: &[DVec3], within: f64) -> Vec<u32> {
    let n = positions.len();
    let mut root: Vec<u32> = (0..n as u32).collect();
    fn find(root: &mut [u32], mut v: u32) -> u32 {
        while root[v as usize] != v {
            root[v as usize] = root[root[v as usize] as usize];
            v = root[v as usize];
        }
        v
    }
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by(|&a, &b| positions[a as usize].x.total_cmp(&positions[b as usize].x));
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            let (p, q) = (positions[a as usize], positions[b as usize]);
            if q.x - p.x > within {
                break;
            }
            if p.distance(q) <= within {
                let (ra, rb) = (find(&mut root, a), find(&mut root, b));
                let (keep, gone) = (ra.min(rb), ra.max(rb));
                root[gone as usize] = keep;
            }
        }
    }
    (0..n as u32).map(|v| find(&mut root, v)).collect()
}

/// Removes consecutive repeated corners (also last to first) and faces left with fewer than
/// three.
fn drop_repeats(faces: &mut Vec<Vec<u32>>) {
    for face in faces.iter_mut() {
        face.dedup();
        while face.len() > 1 && face.first() == face.last() {
            face.pop();
        }
    }
    faces.retain(|f| f.len() >= 3);
}

/// Removes corners that turn by at most `angle` (radians; exactly straight at 0) in every face
/// that uses them, so that no face keeps a corner its neighbour lost.
fn drop_straight_corners(positions: &[DVec3], faces: &mut [Vec<u32>], angle: f64) {
    let turn = |face: &[u32], k: usize| {
        let m = face.len();
        let at = |i: usize| positions[face[i] as usize];
        let (a, b, c) = (at((k + m - 1) % m), at(k), at((k + 1) % m));
        let (d1, d2) = ((b - a).normalize_or_zero(), (c - b).normalize_or_zero());
        d1.dot(d2).clamp(-1.0, 1.0).acos()
    };
    let straight = |face: &[u32], k: usize| {
        let t = turn(face, k);
        if angle == 0.0 { t <= 1e-9 } else { t <= angle }
    };
    let mut keep = vec![false; positions.len()];
    let mut seen = vec![false; positions.len()];
    for face in faces.iter() {
        for k in 0..face.len() {
            let v = face[k] as usize;
            seen[v] = true;
            keep[v] |= !straight(face, k);
        }
    }
    for face in faces.iter_mut() {
        if face.iter().filter(|&&v| keep[v as usize]).count() >= 3 {
            face.retain(|&v| keep[v as usize] || !seen[v as usize]);
        }
    }
}
