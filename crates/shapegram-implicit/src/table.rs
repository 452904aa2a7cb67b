//! The marching-cubes case table, derived here from first principles rather than typed in.
//!
//! Corner `c` of a cell sits at `(c & 1, c >> 1 & 1, c >> 2 & 1)`. Edge `4·a + k` runs along axis
//! `a` from the corner with bit `a` clear; `k` holds the corner's other two coordinate bits (the
//! lower axis in bit 0). For each of the 256 inside/outside patterns the surface is built face by
//! face: on each cell face, segments join the sign changes on its edges so that they separate
//! inside corners from outside ones, and on an ambiguous face (two inside corners on a diagonal)
//! the segments cut off the inside corners. That rule depends only on the face, so neighbouring
//! cells agree on their shared face and the mesh has no cracks. Segments are oriented with the
//! inside on their right seen from outside the cell; they chain into closed loops, and each loop
//! is fanned into triangles whose normals point from inside to outside.

use std::sync::OnceLock;

/// Up to this many triangles per case.
pub const MAX_TRIANGLES: usize = 12;

/// Corner number of a triangle that stands for the centre of ring `r`: `CENTRE + r`.
pub const CENTRE: u8 = 12;

/// The triangles of one inside/outside pattern.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// Triangles in use: `triangles[..count]`.
    pub count: u8,
    /// Corners of each triangle, counter-clockwise seen from outside the solid: edge numbers, or
    /// [`CENTRE`]` + r` for a vertex at the mean of ring `r`'s vertices.
    pub triangles: [[u8; 3]; MAX_TRIANGLES],
    /// Rings (closed loops of edges) in use: `rings[..ring_count]`, each `ring_len[r]` long.
    pub ring_count: u8,
    /// Edge numbers around each ring.
    pub rings: [[u8; 12]; 4],
    /// Length of each ring.
    pub ring_len: [u8; 4],
}

/// The table, built on first use.
pub fn cases() -> &'static [Case; 256] {
    static TABLE: OnceLock<Box<[Case; 256]>> = OnceLock::new();
    TABLE.get_or_init(|| Box::new(std::array::from_fn(|pattern| build_case(pattern as u8))))
}

/// The two corners of edge `e`, the one with the axis bit clear first.
pub const fn edge_corners(e: usize) -> (usize, usize) {
    let axis = e / 4;
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let (lo_axis, hi_axis) = if u < v { (u, v) } else { (v, u) };
    let k = e % 4;
    let base = ((k & 1) << lo_axis) | ((k >> 1 & 1) << hi_axis);
    (base, base | 1 << axis)
}

/// The edge joining corners `a` and `b`, which differ in exactly one bit.
fn edge_between(a: usize, b: usize) -> usize {
    let axis = (a ^ b).trailing_zeros() as usize;
    (0..12)
        .find(|&e| edge_corners(e) == (a.min(b), a.max(b)) && e / 4 == axis)
        .expect("corners differ in one bit")
}

fn corner_point(c: usize) -> [f64; 3] {
    [(c & 1) as f64, (c >> 1 & 1) as f64, (c >> 2 & 1) as f64]
}

fn edge_midpoint(e: usize) -> [f64; 3] {
    let (a, b) = edge_corners(e);
    let (pa, pb) = (corner_point(a), corner_point(b));
    std::array::from_fn(|i| (pa[i] + pb[i]) * 0.5)
}

fn build_case(pattern: u8) -> Case {
    let inside = |c: usize| pattern >> c & 1 == 1;
    // next[e] = the edge the surface loop goes to after edge e.
    let mut next = [usize::MAX; 12];
    for axis in 0..3 {
        for side in 0..2 {
            for (from, to) in face_segments(axis, side, &inside) {
                next[from] = to;
            }
        }
    }
    let mut case = Case {
        count: 0,
        triangles: [[0; 3]; MAX_TRIANGLES],
        ring_count: 0,
        rings: [[0; 12]; 4],
        ring_len: [0; 4],
    };
    let mut seen = [false; 12];
    for start in 0..12 {
        if next[start] == usize::MAX || seen[start] {
            continue;
        }
        let mut ring = Vec::new();
        let mut e = start;
        while !seen[e] {
            seen[e] = true;
            ring.push(e);
            e = next[e];
        }
        let r = case.ring_count as usize;
        case.ring_count += 1;
        case.ring_len[r] = ring.len() as u8;
        for (slot, &e) in case.rings[r].iter_mut().zip(&ring) {
            *slot = e as u8;
        }
        let mut add = |t: [u8; 3]| {
            case.triangles[case.count as usize] = t;
            case.count += 1;
        };
        match fan_start(&ring) {
            Some(first) => {
                ring.rotate_left(first);
                for i in 1..ring.len() - 1 {
                    add([ring[0] as u8, ring[i] as u8, ring[i + 1] as u8]);
                }
            }
            None => {
                for i in 0..ring.len() {
                    add([
                        CENTRE + r as u8,
                        ring[i] as u8,
                        ring[(i + 1) % ring.len()] as u8,
                    ]);
                }
            }
        }
    }
    case
}

/// A rotation of the ring whose fan has no diagonal between two edges of one cell face, or
/// `None`. Such a diagonal lies in the face, and the neighbouring cell may draw the same one:
/// four triangles on one edge. Rings without a safe fan get a centre vertex instead.
fn fan_start(ring: &[usize]) -> Option<usize> {
    let n = ring.len();
    (0..n).find(|&first| (2..n - 1).all(|i| !share_face(ring[first], ring[(first + i) % n])))
}

/// Whether cell edges `a` and `b` lie on a common face of the cell.
fn share_face(a: usize, b: usize) -> bool {
    let (a0, a1) = edge_corners(a);
    let (b0, b1) = edge_corners(b);
    // A face fixes one coordinate bit: both edges keep it at the same value.
    (0..3).any(|bit| {
        let value = a0 >> bit & 1;
        [a0, a1, b0, b1].iter().all(|&c| c >> bit & 1 == value)
    })
}

/// The oriented segments `(from edge, to edge)` on the face of the cell normal to `axis` at
/// coordinate `side`.
fn face_segments(axis: usize, side: usize, inside: &impl Fn(usize) -> bool) -> Vec<(usize, usize)> {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    // The face's corners in cyclic order around it.
    let ring: [usize; 4] =
        [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(i, j)| side << axis | i << u | j << v);
    let crossing = |k: usize| inside(ring[k]) != inside(ring[(k + 1) % 4]);
    let crossings: Vec<usize> = (0..4).filter(|&k| crossing(k)).collect();
    let ring_edge = |k: usize| edge_between(ring[k], ring[(k + 1) % 4]);
    // Pair the crossings: each pair bounds a run of corners of one kind. Pairing each crossing
    // with the next one around the face after an inside corner run cuts off inside corners.
    let mut pairs = Vec::new();
    match crossings.len() {
        0 => {}
        2 => pairs.push((crossings[0], crossings[1])),
        4 => {
            // Ambiguous: the inside corners are the ones that follow crossings leading in.
            for &k in &crossings {
                let entering_inside = inside(ring[(k + 1) % 4]);
                if entering_inside {
                    pairs.push((k, (k + 1) % 4));
                }
            }
        }
        _ => unreachable!("a face loop changes sign an even number of times"),
    }
    pairs
        .into_iter()
        .map(|(k1, k2)| {
            let (e1, e2) = (ring_edge(k1), ring_edge(k2));
            let corner = ring[(k1 + 1) % 4];
            let witness = if inside(corner) { corner } else { ring[k1] };
            orient(e1, e2, witness, axis, side)
        })
        .collect()
}

/// Orders the segment between the midpoints of edges `e1` and `e2` so that the inside corner
/// `witness` lies on its right seen from outside the cell (the face's outward normal is
/// `±axis`).
fn orient(e1: usize, e2: usize, witness: usize, axis: usize, side: usize) -> (usize, usize) {
    let (a, b, w) = (edge_midpoint(e1), edge_midpoint(e2), corner_point(witness));
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let r = [w[0] - a[0], w[1] - a[1], w[2] - a[2]];
    let cross = [
        d[1] * r[2] - d[2] * r[1],
        d[2] * r[0] - d[0] * r[2],
        d[0] * r[1] - d[1] * r[0],
    ];
    let outward = if side == 1 { 1.0 } else { -1.0 };
    if cross[axis] * outward < 0.0 {
        (e1, e2)
    } else {
        (e2, e1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Edges of the triangles of `case` as (from, to) corner keys, centres numbered after edges.
    fn directed_edges(case: &Case) -> Vec<(u8, u8)> {
        case.triangles[..case.count as usize]
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .collect()
    }

    #[test]
    fn every_case_is_a_patch_bounded_by_its_face_segments() {
        let table = cases();
        for (pattern, case) in table.iter().enumerate() {
            let inside = |c: usize| pattern >> c & 1 == 1;
            let crossing = (0..12)
                .filter(|&e| {
                    let (a, b) = edge_corners(e);
                    inside(a) != inside(b)
                })
                .count();
            // Each crossed edge is on exactly one ring, and only crossed edges are.
            let ring_edges: usize = case.ring_len[..case.ring_count as usize]
                .iter()
                .map(|&l| l as usize)
                .sum();
            assert_eq!(ring_edges, crossing, "pattern {pattern}");
            let edges = directed_edges(case);
            let count = |a: u8, b: u8| edges.iter().filter(|&&e| e == (a, b)).count();
            let mut boundary = Vec::new();
            for &(a, b) in &edges {
                match (count(a, b), count(b, a)) {
                    (1, 1) => {}
                    (1, 0) => boundary.push((a as usize, b as usize)),
                    other => panic!("pattern {pattern}: edge {a}-{b} used {other:?}"),
                }
            }
            // The open edges of the patch are exactly the face segments, in their orientation.
            let mut segments: Vec<(usize, usize)> = (0..3)
                .flat_map(|axis| (0..2).map(move |side| (axis, side)))
                .flat_map(|(axis, side)| face_segments(axis, side, &inside))
                .collect();
            boundary.sort_unstable();
            segments.sort_unstable();
            assert_eq!(boundary, segments, "pattern {pattern}");
            // No triangle repeats an edge.
            for t in &case.triangles[..case.count as usize] {
                assert!(
                    t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
                    "pattern {pattern}"
                );
            }
        }
        assert_eq!(table[0].count + table[255].count, 0);
        // One corner inside: a single triangle; a face of four inside corners: two.
        assert_eq!(table[1].count, 1);
        assert_eq!(table[0b0000_1111].count, 2);
    }

    #[test]
    fn complementary_patterns_use_the_same_edges() {
        let table = cases();
        for pattern in 0..256usize {
            let edges = |p: usize| {
                let mut e: Vec<u8> = table[p].rings[..table[p].ring_count as usize]
                    .iter()
                    .zip(&table[p].ring_len)
                    .flat_map(|(r, &l)| r[..l as usize].to_vec())
                    .collect();
                e.sort_unstable();
                e
            };
            assert_eq!(edges(pattern), edges(255 - pattern), "pattern {pattern}");
        }
    }
}
