//! Merging polygons of one plane that touch along their edges into the outlines of their union
//! (the pieces of a perimeter split back into whole parts).
//!
//! Corners within a tolerance are welded and corners lying on another polygon's edge split it
//! (T-junctions), so that shared boundaries become pairs of opposite edges; those cancel, and
//! what is left is traced into loops. A union with a hole has no single outline: it is refused,
//! since Shapegram's faces hold no holes.

use std::collections::BTreeMap;

use crate::DVec2;
use crate::planar::signed_area;

/// The outlines of the union of counter-clockwise 2D polygons that do not overlap, each
/// counter-clockwise without corners on a straight line; polygons that touch others only at a
/// corner, or not at all, stay apart. `None` when the union has a hole. Corners within `eps`
/// count as one.
pub(crate) fn merge_loops(polygons: &[Vec<DVec2>], eps: f64) -> Option<Vec<Vec<DVec2>>> {
    let mut corners: Vec<DVec2> = Vec::new();
    // Corners by column of width `eps` along x: a corner within `eps` of another lies in its
    // column or a neighbouring one.
    let cell = eps.max(f64::MIN_POSITIVE);
    let column = |x: f64| (x / cell).floor() as i64;
    let mut columns: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
    let mut weld = |p: DVec2| {
        let c = column(p.x);
        let near = (c - 1..=c + 1)
            .filter_map(|k| columns.get(&k))
            .flatten()
            .copied()
            .filter(|&i| corners[i].distance(p) <= eps)
            .min();
        near.unwrap_or_else(|| {
            corners.push(p);
            columns.entry(c).or_default().push(corners.len() - 1);
            corners.len() - 1
        })
    };
    let loops: Vec<Vec<usize>> = polygons
        .iter()
        .map(|polygon| {
            let mut indices: Vec<usize> = polygon.iter().map(|&p| weld(p)).collect();
            indices.dedup();
            while indices.len() > 1 && indices.first() == indices.last() {
                indices.pop();
            }
            indices
        })
        .filter(|l| l.len() >= 3)
        .collect();
    // Directed edges, each split at the corners lying on it; opposite pairs cancel.
    let mut by_x: Vec<usize> = (0..corners.len()).collect();
    by_x.sort_by(|&a, &b| corners[a].x.total_cmp(&corners[b].x));
    let mut edges: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for l in &loops {
        for (k, &a) in l.iter().enumerate() {
            let b = l[(k + 1) % l.len()];
            let chain = split_at_corners(&corners, &by_x, (a, b), eps);
            for pair in chain.windows(2) {
                let (u, v) = (pair[0], pair[1]);
                match edges.get_mut(&(v, u)) {
                    Some(count) if *count > 0 => *count -= 1,
                    _ => *edges.entry((u, v)).or_default() += 1,
                }
            }
        }
    }
    let mut outgoing: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (&(u, v), &count) in &edges {
        for _ in 0..count {
            outgoing.entry(u).or_default().push(v);
        }
    }
    let mut result = Vec::new();
    while let Some((&start, _)) = outgoing.iter().find(|(_, next)| !next.is_empty()) {
        let mut loop_ = vec![start];
        let mut from = start;
        let mut at = take_next(&mut outgoing, &corners, None, start)?;
        while at != start {
            loop_.push(at);
            let incoming = corners[at] - corners[from];
            from = at;
            at = take_next(&mut outgoing, &corners, Some(incoming), at)?;
        }
        let points: Vec<DVec2> = loop_.iter().map(|&i| corners[i]).collect();
        let points = without_straight_corners(points, eps);
        if points.len() < 3 {
            continue;
        }
        if signed_area(&points) < 0.0 {
            return None;
        }
        result.push(points);
    }
    Some(result)
}

/// The corners from `a` to `b` along the edge between them: `a`, the welded corners lying on
/// the edge in order, `b`. `by_x` lists the corners by x.
fn split_at_corners(
    corners: &[DVec2],
    by_x: &[usize],
    (a, b): (usize, usize),
    eps: f64,
) -> Vec<usize> {
    let (pa, pb) = (corners[a], corners[b]);
    let d = pb - pa;
    let length2 = d.length_squared();
    let (lo, hi) = (pa.x.min(pb.x) - eps, pa.x.max(pb.x) + eps);
    let first = by_x.partition_point(|&i| corners[i].x < lo);
    let mut on: Vec<(f64, usize)> = by_x[first..]
        .iter()
        .take_while(|&&i| corners[i].x <= hi)
        .filter(|&&i| i != a && i != b)
        .filter_map(|&i| {
            let p = corners[i];
            let t = (p - pa).dot(d) / length2;
            let off = (p - pa).perp_dot(d).abs() / length2.sqrt();
            (t > 0.0 && t < 1.0 && off <= eps).then_some((t, i))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    std::iter::once(a)
        .chain(on.into_iter().map(|(_, i)| i))
        .chain(std::iter::once(b))
        .collect()
}

/// Removes and returns the edge to follow out of corner `at`: the one turning furthest left
/// from the incoming direction (towards the inside), which keeps loops that touch at a corner
/// apart.
fn take_next(
    outgoing: &mut BTreeMap<usize, Vec<usize>>,
    corners: &[DVec2],
    incoming: Option<DVec2>,
    at: usize,
) -> Option<usize> {
    let next = outgoing.get_mut(&at)?;
    let turn = |v: usize| {
        incoming.map_or(0.0, |d| {
            let out = corners[v] - corners[at];
            d.perp_dot(out).atan2(d.dot(out))
        })
    };
    let k = (0..next.len()).max_by(|&x, &y| turn(next[x]).total_cmp(&turn(next[y])))?;
    Some(next.swap_remove(k))
}

/// A loop without corners on a straight line (or repeated), until none is left.
fn without_straight_corners(mut points: Vec<DVec2>, eps: f64) -> Vec<DVec2> {
    loop {
        let n = points.len();
        if n < 3 {
            return points;
        }
        let straight = (0..n).find(|&k| {
            let (a, b, c) = (points[(k + n - 1) % n], points[k], points[(k + 1) % n]);
            let ac = c - a;
            a.distance(b) <= eps
                || ((b - a).perp_dot(ac).abs() <= eps * ac.length() && (b - a).dot(c - b) > 0.0)
        });
        match straight {
            Some(k) => {
                points.remove(k);
            }
            None => return points,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, s: f64) -> Vec<DVec2> {
        vec![
            DVec2::new(x, y),
            DVec2::new(x + s, y),
            DVec2::new(x + s, y + s),
            DVec2::new(x, y + s),
        ]
    }

    #[test]
    fn two_squares_sharing_an_edge_become_one_rectangle() {
        let merged = merge_loops(&[square(0.0, 0.0, 1.0), square(1.0, 0.0, 1.0)], 1e-9).unwrap();
        assert_eq!(merged.len(), 1);
        assert_eq!(merged[0].len(), 4);
        assert!((signed_area(&merged[0]) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_t_junction_still_merges() {
        // A 2 × 1 rectangle on top of two unit squares: its bottom edge holds their shared corner.
        let top = vec![
            DVec2::new(0.0, 1.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        let merged =
            merge_loops(&[square(0.0, 0.0, 1.0), square(1.0, 0.0, 1.0), top], 1e-9).unwrap();
        assert_eq!(merged.len(), 1);
        assert_eq!(merged[0].len(), 4);
        assert!((signed_area(&merged[0]) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn apart_and_corner_touching_polygons_stay_apart() {
        let merged = merge_loops(&[square(0.0, 0.0, 1.0), square(1.0, 1.0, 1.0)], 1e-9).unwrap();
        assert_eq!(merged.len(), 2);
        assert!(merged.iter().all(|l| l.len() == 4));
    }

    #[test]
    fn a_ring_has_a_hole_and_is_refused() {
        let mut ring = Vec::new();
        for (x, y) in [
            (0, 0),
            (1, 0),
            (2, 0),
            (0, 1),
            (2, 1),
            (0, 2),
            (1, 2),
            (2, 2),
        ] {
            ring.push(square(f64::from(x), f64::from(y), 1.0));
        }
        assert!(merge_loops(&ring, 1e-9).is_none());
    }
}
