//! Cleaning meshes up (CGA's `cleanupGeometry`): merging vertices that (nearly) coincide,
//! dropping corners on (nearly) straight lines and faces with (nearly) no area, and merging
//! (nearly) coplanar faces that share edges into one polygon.
//!
//! One tolerance in `0..=1` sets every limit, as CityEngine's does: at 0 only exact duplicates,
//! exactly straight corners, faces without area and edges between coplanar faces go; at 1
//! vertices within 1 m merge, corners within 10° of straight go, faces under 1 m² are dropped
//! and faces whose normals are within 10° of each other merge; in between the limits scale
//! linearly.

use std::collections::BTreeMap;

use crate::{DVec3, Mesh};

/// What [`cleanup`] cleans.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cleanup {
    /// Merge close vertices and drop straight corners.
    pub vertices: bool,
    /// Drop faces with little area.
    pub faces: bool,
    /// Merge close vertices and the faces on either side of edges between coplanar faces.
    pub edges: bool,
}

/// Relative size below which lengths and areas count as zero at tolerance 0.
const ZERO: f64 = 1e-12;

/// A cleaned copy of `mesh` (see the module docs); faces left with fewer than three corners are
/// dropped, and unused vertices removed. A tolerance outside `0..=1` is clamped to it.
pub fn cleanup(mesh: &Mesh, what: Cleanup, tolerance: f64) -> Mesh {
    cleanup_classes(mesh, what, tolerance, &[]).0
}

/// [`cleanup`] of a mesh whose faces belong to classes (a face without an entry in `classes`
/// is in class 0): faces of different classes never merge. Returns the cleaned mesh and, for
/// each of its faces, the face of `mesh` it came from (a merged face: the first of its group).
pub fn cleanup_classes(
    mesh: &Mesh,
    what: Cleanup,
    tolerance: f64,
    classes: &[u32],
) -> (Mesh, Vec<usize>) {
    let t = if tolerance.is_nan() {
        0.0
    } else {
        tolerance.clamp(0.0, 1.0)
    };
    let scale = mesh.bounds().map_or(1.0, |b| b.diagonal().max(1e-300));
    let mut faces: Vec<(usize, Vec<u32>)> = mesh.faces().map(<[u32]>::to_vec).enumerate().collect();
    if what.vertices || what.edges {
        let remap = merged(mesh.positions(), t * 1.0);
        for (_, face) in &mut faces {
            for v in face.iter_mut() {
                *v = remap[*v as usize];
            }
        }
        drop_repeats(&mut faces);
    }
    if what.edges {
        let class = |f: usize| classes.get(f).copied().unwrap_or(0);
        faces = merged_faces(mesh.positions(), faces, (t * 10.0).to_radians(), class);
    }
    if what.vertices {
        drop_straight_corners(mesh.positions(), &mut faces, (t * 10.0).to_radians());
    }
    drop_repeats(&mut faces);
    if what.faces {
        let least = (t * 1.0).max(ZERO * scale * scale);
        faces.retain(|(_, face)| {
            let points: Vec<DVec3> = face.iter().map(|&v| mesh.position(v)).collect();
            crate::mesh::newell(points.iter().copied()).length() * 0.5 > least
        });
    }
    let sources = faces.iter().map(|(f, _)| *f).collect();
    let loops = faces.into_iter().map(|(_, face)| face);
    (
        Mesh::from_faces(mesh.positions().to_vec(), loops).compacted(),
        sources,
    )
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
fn drop_repeats(faces: &mut Vec<(usize, Vec<u32>)>) {
    for (_, face) in faces.iter_mut() {
        face.dedup();
        while face.len() > 1 && face.first() == face.last() {
            face.pop();
        }
    }
    faces.retain(|(_, f)| f.len() >= 3);
}

/// Removes corners that turn by at most `angle` (radians; exactly straight at 0) in every face
/// that uses them, so that no face keeps a corner its neighbour lost.
fn drop_straight_corners(positions: &[DVec3], faces: &mut [(usize, Vec<u32>)], angle: f64) {
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
    for (_, face) in faces.iter() {
        for k in 0..face.len() {
            let v = face[k] as usize;
            seen[v] = true;
            keep[v] |= !straight(face, k);
        }
    }
    for (_, face) in faces.iter_mut() {
        if face.iter().filter(|&&v| keep[v as usize]).count() >= 3 {
            face.retain(|&v| keep[v as usize] || !seen[v as usize]);
        }
    }
}

/// Faces (each with the face it came from) merged across the edges they share with faces
/// (nearly) coplanar with them and of the same class: each group grows from its first face (in
/// order) over shared edges to faces whose normals turn by at most `angle` from that face's
/// (exactly parallel at 0), and becomes the one polygon around it, in the place of its first
/// face. A group whose outline is not one simple loop (a hole, or faces touching at a corner)
/// stays as it was.
fn merged_faces(
    positions: &[DVec3],
    faces: Vec<(usize, Vec<u32>)>,
    angle: f64,
    class: impl Fn(usize) -> u32,
) -> Vec<(usize, Vec<u32>)> {
    let (sources, faces): (Vec<usize>, Vec<Vec<u32>>) = faces.into_iter().unzip();
    let normals: Vec<DVec3> = faces
        .iter()
        .map(|f| crate::mesh::newell(f.iter().map(|&v| positions[v as usize])).normalize_or_zero())
        .collect();
    let within = |a: DVec3, b: DVec3| {
        let turn = a.dot(b).clamp(-1.0, 1.0).acos();
        a != DVec3::ZERO
            && if angle == 0.0 {
                turn <= 1e-9
            } else {
                turn <= angle
            }
    };
    // The face on the other side of each directed edge.
    let mut by_edge: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for (f, face) in faces.iter().enumerate() {
        for (k, &a) in face.iter().enumerate() {
            by_edge.insert((a, face[(k + 1) % face.len()]), f);
        }
    }
    let mut group = vec![usize::MAX; faces.len()];
    let mut out = Vec::with_capacity(faces.len());
    for seed in 0..faces.len() {
        if group[seed] != usize::MAX {
            continue;
        }
        group[seed] = seed;
        let mut members = vec![seed];
        let mut k = 0;
        while k < members.len() {
            let face = &faces[members[k]];
            for (i, &a) in face.iter().enumerate() {
                let b = face[(i + 1) % face.len()];
                if let Some(&g) = by_edge.get(&(b, a))
                    && group[g] == usize::MAX
                    && class(sources[g]) == class(sources[seed])
                    && within(normals[seed], normals[g])
                {
                    group[g] = seed;
                    members.push(g);
                }
            }
            k += 1;
        }
        match outline(&faces, &members) {
            Some(merged) if members.len() > 1 => out.push((sources[seed], merged)),
            _ => out.extend(members.iter().map(|&m| (sources[m], faces[m].clone()))),
        }
    }
    out
}

/// The one loop around a group of faces: their edges less those shared within the group, in
/// order from the first face's first remaining edge; `None` unless that is every edge left,
/// each corner met once.
fn outline(faces: &[Vec<u32>], members: &[usize]) -> Option<Vec<u32>> {
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for &m in members {
        let face = &faces[m];
        for (i, &a) in face.iter().enumerate() {
            edges.push((a, face[(i + 1) % face.len()]));
        }
    }
    let inner: std::collections::BTreeSet<(u32, u32)> = edges.iter().copied().collect();
    let boundary: Vec<(u32, u32)> = edges
        .into_iter()
        .filter(|&(a, b)| !inner.contains(&(b, a)))
        .collect();
    let mut next: BTreeMap<u32, u32> = BTreeMap::new();
    for &(a, b) in &boundary {
        if next.insert(a, b).is_some() {
            return None;
        }
    }
    let start = boundary.first()?.0;
    let mut loop_ = vec![start];
    let mut at = next[&start];
    while at != start {
        if loop_.len() > boundary.len() {
            return None;
        }
        loop_.push(at);
        at = *next.get(&at)?;
    }
    (loop_.len() == boundary.len()).then_some(loop_)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EDGES: Cleanup = Cleanup {
        vertices: false,
        faces: false,
        edges: true,
    };

    /// A 20 × 10 rectangle in two squares, and a third square folded up along its right edge
    /// by `fold` degrees (10 m apart, corners stay apart even at tolerance 1).
    fn strip(fold: f64) -> Mesh {
        let (s, c) = fold.to_radians().sin_cos();
        let positions: Vec<DVec3> = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(2.0 + c, 0.0, s),
            DVec3::new(2.0 + c, 1.0, s),
        ]
        .into_iter()
        .map(|p| p * 10.0)
        .collect();
        Mesh::from_faces(
            positions,
            vec![vec![0, 1, 4, 5], vec![1, 2, 3, 4], vec![2, 6, 7, 3]],
        )
    }

    #[test]
    fn coplanar_neighbours_merge_and_a_fold_beyond_the_angle_stays() {
        let merged = cleanup(&strip(30.0), EDGES, 0.0);
        assert_eq!(merged.face_count(), 2);
        // The rectangle keeps the corners on its long sides (its neighbours' share them).
        let first: Vec<DVec3> = merged.face_points(0).collect();
        assert_eq!(first.len(), 6);
        assert!((merged.area() - 300.0).abs() < 1e-9, "{}", merged.area());
        // Folded by 5°, the third square joins at tolerance 1 (10°), not at 0.4 (4°).
        assert_eq!(cleanup(&strip(5.0), EDGES, 0.4).face_count(), 2);
        assert_eq!(cleanup(&strip(5.0), EDGES, 1.0).face_count(), 1);
        // With the vertices cleaned too, the straight corners go.
        let all = Cleanup {
            vertices: true,
            faces: true,
            edges: true,
        };
        let clean = cleanup(&strip(30.0), all, 0.0);
        assert_eq!(clean.face_points(0).count(), 4);
    }
}
