//! The minimum-area rectangle around points in the plane (CGA `alignScopeToGeometryBBox`).
//!
//! The rectangle of least area around a point set has a side along an edge of the set's convex
//! hull, so trying each hull edge finds it (O(h²) for a hull of h points, which is small for
//! building footprints).

use glam::DVec2;

/// A rectangle around points: the unit direction of its longer side and its two extents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    /// Unit direction of the longer side.
    pub long_axis: DVec2,
    /// Length of the longer side.
    pub length: f64,
    /// Length of the shorter side.
    pub width: f64,
}

/// The minimum-area rectangle around `points`, or `None` when they do not span a line (fewer
/// than two distinct points). For collinear points it is the segment they span, of width zero.
/// Among rectangles of equal area (a square's two sides) the first hull edge's wins.
pub fn min_area_rectangle(points: &[DVec2]) -> Option<Rectangle> {
    let hull = convex_hull(points);
    let mut best: Option<(f64, Rectangle)> = None;
    for (i, &a) in hull.iter().enumerate() {
        let b = hull[(i + 1) % hull.len()];
        let Some(along) = (b - a).try_normalize() else {
            continue;
        };
        let across = along.perp();
        let extent = |axis: DVec2| {
            let (lo, hi) = hull
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    let t = p.dot(axis);
                    (lo.min(t), hi.max(t))
                });
            hi - lo
        };
        let (l, w) = (extent(along), extent(across));
        let rectangle = if l >= w {
            Rectangle {
                long_axis: along,
                length: l,
                width: w,
            }
        } else {
            Rectangle {
                long_axis: across,
                length: w,
                width: l,
            }
        };
        let area = l * w;
        // Relative slack, so rounding does not pick a later edge of a rectangle's hull.
        if best.is_none_or(|(smallest, _)| area < smallest * (1.0 - 1e-12)) {
            best = Some((area, rectangle));
        }
    }
    best.map(|(_, r)| r)
}

/// The convex hull of `points`, counter-clockwise, without collinear points (Andrew's monotone
/// chain).
fn convex_hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut sorted: Vec<DVec2> = points.iter().copied().filter(|p| p.is_finite()).collect();
    sorted.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(sorted.len() + 1);
    for pass in [false, true] {
        let start = hull.len();
        let chain: Box<dyn Iterator<Item = &DVec2>> = if pass {
            Box::new(sorted.iter().rev())
        } else {
            Box::new(sorted.iter())
        };
        for &p in chain {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        // The last point of each chain starts the other.
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turned_rectangle_is_found_exactly() {
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let axis = DVec2::new(c, s);
        let corners: Vec<DVec2> = [(0.0, 0.0), (8.0, 0.0), (8.0, 3.0), (0.0, 3.0), (4.0, 1.0)]
            .iter()
            .map(|&(u, v)| axis * u + axis.perp() * v + DVec2::new(5.0, -2.0))
            .collect();
        let r = min_area_rectangle(&corners).unwrap();
        assert!(
            (r.length - 8.0).abs() < 1e-9 && (r.width - 3.0).abs() < 1e-9,
            "{r:?}"
        );
        assert!(r.long_axis.dot(axis).abs() > 1.0 - 1e-12, "{r:?}");
    }

    #[test]
    fn an_l_footprint_gets_its_bounding_box() {
        let l = [
            (0.0, 0.0),
            (4.0, 0.0),
            (4.0, 1.0),
            (1.0, 1.0),
            (1.0, 6.0),
            (0.0, 6.0),
        ]
        .map(|(x, y)| DVec2::new(x, y));
        let r = min_area_rectangle(&l).unwrap();
        assert_eq!((r.length, r.width), (6.0, 4.0));
        assert_eq!(r.long_axis.abs(), DVec2::Y);
    }

    #[test]
    fn degenerate_inputs() {
        assert_eq!(min_area_rectangle(&[]), None);
        assert_eq!(min_area_rectangle(&[DVec2::ONE, DVec2::ONE]), None);
        let line = [DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(5.0, 0.0)];
        let r = min_area_rectangle(&line).unwrap();
        assert_eq!((r.length, r.width), (5.0, 0.0));
    }
}
