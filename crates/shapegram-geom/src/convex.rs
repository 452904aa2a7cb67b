//! Cutting polygons into convex pieces (CGA's `convexify`).
//!
//! A concave polygon is triangulated, and the triangles are merged back across their shared
//! diagonals as long as the merged piece stays convex (Hertel and Mehlhorn's greedy method,
//! which leaves at most four times the fewest pieces possible). Diagonals that leave no reflex
//! corner behind go first, then the longer before the shorter, so the cuts that remain start at
//! reflex corners: an L falls into two rectangles' worth of pieces, not a fan.

use crate::{DVec2, DVec3, planar::Polygon, triangulate::Triangulator};

/// The convex pieces of a simple planar polygon, counter-clockwise like it, whose corners are
/// the polygon's own; the polygon itself (repeated corners and corners on a straight line
/// dropped) when it is convex. With `max_cut`, only diagonals shorter than it are cut: pieces
/// that only a longer cut would separate stay together, convex or not. Invalid polygons (see
/// [`crate::offset::offset_polygon`]) come back unchanged, as one piece.
pub fn convex_pieces(points: &[DVec3], max_cut: Option<f64>) -> Vec<Vec<DVec3>> {
    let Some(polygon) = Polygon::new(points, true) else {
        return vec![points.to_vec()];
    };
    let flat = &polygon.flat;
    let n = flat.len();
    if crate::planar::is_convex(flat, polygon.eps) {
        return vec![polygon.world];
    }
    let triangles = Triangulator::new().triangulate(&polygon.world, &[]);
    let mut pieces: Vec<Option<Vec<usize>>> = triangles
        .iter()
        .map(|t| Some(t.iter().map(|&i| i as usize).collect()))
        .collect();
    let reflex: Vec<bool> = (0..n)
        .map(|i| {
            let (a, b, c) = (flat[(i + n - 1) % n], flat[i], flat[(i + 1) % n]);
            (b - a).perp_dot(c - b) < 0.0
        })
        .collect();
    // Each diagonal once, with the two triangles on its sides.
    let mut diagonals: Vec<(usize, usize, usize, usize)> = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
            let outline = (a + 1) % n == b || (b + 1) % n == a;
            if outline || a > b {
                continue;
            }
            let other = triangles.iter().enumerate().find(|(u, o)| {
                *u != t && (0..3).any(|j| o[j] as usize == b && o[(j + 1) % 3] as usize == a)
            });
            if let Some((u, _)) = other {
                diagonals.push((a, b, t, u));
            }
        }
    }
    let length = |&(a, b, ..): &(usize, usize, usize, usize)| flat[a].distance(flat[b]);
    diagonals.sort_by(|p, q| {
        let at_reflex = |d: &(usize, usize, usize, usize)| reflex[d.0] || reflex[d.1];
        at_reflex(p)
            .cmp(&at_reflex(q))
            .then(length(q).total_cmp(&length(p)))
    });
    // Which piece each triangle now belongs to.
    let mut owner: Vec<usize> = (0..triangles.len()).collect();
    let find = |owner: &[usize], mut t: usize| {
        while owner[t] != t {
            t = owner[t];
        }
        t
    };
    for must in [true, false] {
        for d in &diagonals {
            let long = max_cut.is_some_and(|m| length(d) >= m);
            if long != must {
                continue;
            }
            let (p, q) = (find(&owner, d.2), find(&owner, d.3));
            if p == q {
                continue;
            }
            let (Some(left), Some(right)) = (&pieces[p], &pieces[q]) else {
                continue;
            };
            let Some(merged) = merge(left, right, d.0, d.1) else {
                continue;
            };
            let points: Vec<DVec2> = merged.iter().map(|&i| flat[i]).collect();
            if must || crate::planar::is_convex(&points, polygon.eps) {
                pieces[p] = Some(merged);
                pieces[q] = None;
                owner[q] = p;
            }
        }
    }
    pieces
        .into_iter()
        .flatten()
        .map(|piece| piece.iter().map(|&i| polygon.world[i]).collect())
        .collect()
}

/// Two counter-clockwise loops sharing the edge between corners `a` and `b` joined into one.
fn merge(left: &[usize], right: &[usize], a: usize, b: usize) -> Option<Vec<usize>> {
    // Rotate each loop so that it starts just after the shared edge and ends on it.
    let rotated = |ring: &[usize], from: usize, to: usize| -> Option<Vec<usize>> {
        let m = ring.len();
        let start = (0..m).find(|&i| ring[i] == from && ring[(i + 1) % m] == to)?;
        Some((1..=m).map(|k| ring[(start + k) % m]).collect())
    };
    // In one loop the edge runs a → b, in the other b → a.
    let (first, second) = match (rotated(left, a, b), rotated(right, b, a)) {
        (Some(l), Some(r)) => (l, r),
        _ => (rotated(left, b, a)?, rotated(right, a, b)?),
    };
    // `first` runs from the edge's end round to its start; `second` likewise the other way.
    let mut joined: Vec<usize> = first[..first.len() - 1].to_vec();
    joined.extend_from_slice(&second[..second.len() - 1]);
    Some(joined)
}
