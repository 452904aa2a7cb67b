//! CGA's `splitAndSetbackPerimeter` on one polygon: stretches of its boundary, each set back by
//! its own depth, and the remainder.
//!
//! A stretch moves the edges it covers inward by its depth, as [`crate::offset::setback`] moves
//! them (mitred between its own edges, along the lines of the edges that stay), and keeps of
//! each edge's strip the part beside the stretch: a stretch that ends inside an edge ends there
//! square to the edge. Stretches are cut each by itself, so two may overlap (around a corner);
//! the overlap goes to the deeper one (the earlier on a tie) and is cut from the other. The
//! remainder is what no stretch covers.

use crate::merge::merge_loops;
use crate::planar::{Polygon, clip_convex, signed_area};
use crate::{DVec2, DVec3, convex::convex_pieces, offset::setback};

/// A piece of one edge of a polygon: from `from` to `to` metres along it from its first corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgePiece {
    /// The edge's index: edge `i` runs from corner `i` to corner `i + 1`.
    pub edge: usize,
    pub from: f64,
    pub to: f64,
}

/// A stretch of a polygon's boundary, set back by `depth` (0 or more).
#[derive(Clone, Debug, PartialEq)]
pub struct Stretch {
    pub depth: f64,
    /// The pieces of edges the stretch covers.
    pub pieces: Vec<EdgePiece>,
}

/// What a perimeter split cuts from a polygon, counter-clockwise like it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PerimeterCut {
    /// Each stretch's polygons, in the order of the stretches (none when nothing is left of it).
    pub stretches: Vec<Vec<Vec<DVec3>>>,
    /// The rest of the polygon.
    pub remainder: Vec<Vec<DVec3>>,
}

/// Cuts a simple planar polygon (convex or not) along stretches of its boundary (see the module
/// docs). `None` for an invalid polygon (see [`crate::offset::offset_polygon`]), a depth that is
/// negative or not finite, or a stretch so deep that one of its edges runs onto the line of an
/// edge that stays (as [`crate::offset::setback`] refuses it).
pub fn split_setback_perimeter(points: &[DVec3], stretches: &[Stretch]) -> Option<PerimeterCut> {
    let polygon = Polygon::new(points, true)?;
    let tiny = polygon.eps * polygon.eps;
    let corner_of: Vec<usize> = polygon
        .world
        .iter()
        .map(|p| points.iter().position(|q| q == p))
        .collect::<Option<_>>()?;
    // Where an edge of `points` lies on the cleaned polygon: its edge and the distance along it.
    let locate = |edge: usize| {
        let k = corner_of
            .iter()
            .rposition(|&c| c <= edge)
            .unwrap_or(corner_of.len() - 1);
        (k, polygon.world[k].distance(points[edge % points.len()]))
    };
    let mut cut_pieces: Vec<Vec<Vec<DVec2>>> = Vec::with_capacity(stretches.len());
    for stretch in stretches {
        if !(stretch.depth.is_finite() && stretch.depth >= 0.0) {
            return None;
        }
        let spans: Vec<(usize, f64, f64)> = stretch
            .pieces
            .iter()
            .map(|p| {
                let (k, along) = locate(p.edge);
                (k, along + p.from, along + p.to)
            })
            .collect();
        cut_pieces.push(stretch_pieces(&polygon, stretch.depth, &spans, tiny)?);
    }
    // The deeper stretches first: each keeps what the ones before it left.
    let mut order: Vec<usize> = (0..stretches.len()).collect();
    order.sort_by(|&a, &b| stretches[b].depth.total_cmp(&stretches[a].depth));
    let mut placed: Vec<Vec<DVec2>> = Vec::new();
    let mut kept: Vec<Vec<Vec<DVec2>>> = vec![Vec::new(); stretches.len()];
    for s in order {
        let left = subtract_all(std::mem::take(&mut cut_pieces[s]), &placed, tiny);
        placed.extend(left.iter().cloned());
        kept[s] = left;
    }
    let whole: Vec<Vec<DVec2>> = convex_pieces(&polygon.world, None)
        .iter()
        .map(|piece| piece.iter().map(|&p| polygon.frame.flat(p)).collect())
        .collect();
    let rest = subtract_all(whole, &placed, tiny);
    let lift = |pieces: Vec<Vec<DVec2>>| -> Vec<Vec<DVec3>> {
        let merged = merge_loops(&pieces, polygon.eps * 1e3).unwrap_or(pieces);
        merged
            .iter()
            .map(|l| l.iter().map(|&q| polygon.frame.lift(q, 0.0)).collect())
            .collect()
    };
    Some(PerimeterCut {
        stretches: kept.into_iter().map(lift).collect(),
        remainder: lift(rest),
    })
}

/// The convex pieces (in plane coordinates) a stretch of `depth` covers, its spans given as
/// (edge of the cleaned polygon, from, to).
fn stretch_pieces(
    polygon: &Polygon,
    depth: f64,
    spans: &[(usize, f64, f64)],
    tiny: f64,
) -> Option<Vec<Vec<DVec2>>> {
    if depth == 0.0 || spans.is_empty() {
        return Some(Vec::new());
    }
    let n = polygon.flat.len();
    let moving = |k: usize| spans.iter().any(|s| s.0 == k);
    let cut = setback(
        &polygon.world,
        |k, _, _| if moving(k) { depth } else { 0.0 },
    )?;
    let eps = polygon.eps;
    let mut pieces = Vec::new();
    for strip in &cut.strips {
        let k = strip.edge;
        let (a, b) = (polygon.flat[k], polygon.flat[(k + 1) % n]);
        let length = a.distance(b);
        let along = (b - a) / length;
        let convex: Vec<Vec<DVec2>> = convex_pieces(&strip.polygon, None)
            .iter()
            .map(|p| p.iter().map(|&q| polygon.frame.flat(q)).collect())
            .collect();
        for &(_, from, to) in spans.iter().filter(|s| s.0 == k) {
            let (from, to) = (from.max(0.0), to.min(length));
            if to - from <= eps {
                continue;
            }
            for piece in &convex {
                // Square to the edge where the stretch ends inside it; at a corner the strip
                // keeps the shape the setback gave it.
                let mut piece = piece.clone();
                if from > eps {
                    piece = clip_convex(&piece, -along, -(along.dot(a) + from));
                }
                if to < length - eps {
                    piece = clip_convex(&piece, along, along.dot(a) + to);
                }
                if piece.len() >= 3 && signed_area(&piece) > tiny {
                    pieces.push(piece);
                }
            }
        }
    }
    Some(pieces)
}

/// Convex pieces less every convex piece of `taken`, as convex pieces.
fn subtract_all(mut pieces: Vec<Vec<DVec2>>, taken: &[Vec<DVec2>], tiny: f64) -> Vec<Vec<DVec2>> {
    for cutter in taken {
        pieces = pieces
            .into_iter()
            .flat_map(|piece| subtract(piece, cutter, tiny))
            .collect();
    }
    pieces
}

/// A convex piece less a convex cutter (both counter-clockwise): the piece itself when they
/// share no area, else the parts of it outside each of the cutter's edges in turn.
fn subtract(piece: Vec<DVec2>, cutter: &[DVec2], tiny: f64) -> Vec<Vec<DVec2>> {
    let bounds = |points: &[DVec2]| {
        points
            .iter()
            .fold((DVec2::MAX, DVec2::MIN), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            })
    };
    let ((a_lo, a_hi), (b_lo, b_hi)) = (bounds(&piece), bounds(cutter));
    if a_lo.cmpge(b_hi).any() || b_lo.cmpge(a_hi).any() {
        return vec![piece];
    }
    let m = cutter.len();
    let outward = |i: usize| {
        let (a, b) = (cutter[i], cutter[(i + 1) % m]);
        let d = b - a;
        (DVec2::new(d.y, -d.x), a)
    };
    let mut inside = piece.clone();
    for i in 0..m {
        let (o, a) = outward(i);
        inside = clip_convex(&inside, o, o.dot(a));
        if inside.len() < 3 || signed_area(&inside) <= tiny {
            return vec![piece];
        }
    }
    let mut out = Vec::new();
    let mut rest = piece;
    for i in 0..m {
        let (o, a) = outward(i);
        let outside = clip_convex(&rest, -o, -o.dot(a));
        if outside.len() >= 3 && signed_area(&outside) > tiny {
            out.push(outside);
        }
        rest = clip_convex(&rest, o, o.dot(a));
        if rest.len() < 3 {
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `w` × `d` lot in the xz-plane facing +y, its first edge along +x.
    fn lot(w: f64, d: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, d),
            DVec3::new(w, 0.0, d),
            DVec3::new(w, 0.0, 0.0),
        ]
    }

    fn area(loops: &[Vec<DVec3>]) -> f64 {
        loops
            .iter()
            .map(|l| crate::mesh::newell(l.iter().copied()).length() * 0.5)
            .sum()
    }

    fn stretch(depth: f64, pieces: &[(usize, f64, f64)]) -> Stretch {
        Stretch {
            depth,
            pieces: pieces
                .iter()
                .map(|&(edge, from, to)| EdgePiece { edge, from, to })
                .collect(),
        }
    }

    #[test]
    fn a_stretch_inside_an_edge_is_a_rectangle() {
        // 20 × 10: edge 0 runs along z from (0,0,0) to (0,0,10).
        let cut =
            split_setback_perimeter(&lot(20.0, 10.0), &[stretch(2.0, &[(0, 3.0, 7.0)])]).unwrap();
        assert_eq!(cut.stretches[0].len(), 1);
        assert_eq!(cut.stretches[0][0].len(), 4);
        assert!((area(&cut.stretches[0]) - 8.0).abs() < 1e-9);
        assert_eq!(cut.remainder.len(), 1);
        assert_eq!(cut.remainder[0].len(), 8);
        assert!((area(&cut.remainder) - 192.0).abs() < 1e-9);
    }

    #[test]
    fn around_a_corner_the_stretch_mitres_and_the_deeper_wins_an_overlap() {
        let shallow = stretch(1.0, &[(0, 6.0, 10.0)]);
        let deep = stretch(3.0, &[(1, 0.0, 4.0)]);
        let cut = split_setback_perimeter(&lot(20.0, 10.0), &[shallow, deep]).unwrap();
        // The deep one along edge 1 is 4 × 3 and runs along edge 0's line at the corner.
        assert!((area(&cut.stretches[1]) - 12.0).abs() < 1e-9);
        // The shallow one (4 × 1 along edge 0, to the corner) loses its last 3 m to it.
        assert!((area(&cut.stretches[0]) - 1.0).abs() < 1e-9);
        assert!((area(&cut.remainder) - (200.0 - 13.0)).abs() < 1e-9);
    }

    #[test]
    fn one_stretch_all_around_is_a_uniform_setback() {
        let all = stretch(
            2.0,
            &[
                (0, 0.0, 10.0),
                (1, 0.0, 20.0),
                (2, 0.0, 10.0),
                (3, 0.0, 20.0),
            ],
        );
        let cut = split_setback_perimeter(&lot(20.0, 10.0), &[all]).unwrap();
        assert!((area(&cut.remainder) - 16.0 * 6.0).abs() < 1e-9);
        assert_eq!(cut.remainder[0].len(), 4);
        assert!((area(&cut.stretches[0]) - (200.0 - 96.0)).abs() < 1e-9);
    }

    #[test]
    fn negative_depths_are_refused_and_a_stretch_as_deep_as_the_lot_takes_all() {
        let lot = lot(20.0, 10.0);
        assert!(split_setback_perimeter(&lot, &[stretch(-1.0, &[(0, 0.0, 1.0)])]).is_none());
        // Edge 1 moving 12 m reaches edge 3, 10 m away, which stays: the stretch takes it all.
        let cut = split_setback_perimeter(&lot, &[stretch(12.0, &[(1, 0.0, 20.0)])]).unwrap();
        assert!((area(&cut.stretches[0]) - 200.0).abs() < 1e-9, "{cut:?}");
        assert!(cut.remainder.is_empty());
    }
}
