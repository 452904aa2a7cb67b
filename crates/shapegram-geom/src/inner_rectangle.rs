//! The largest rectangle inside a polygon with its sides along given directions (CGA's
//! `innerRectangle` and `innerRect`), and what is left of the polygon around it.
//!
//! For two positions `x1 < x2` across the polygon, the polygon's edges that pass over the open
//! strip between them block the heights their part in the strip spans; the gaps between blocked
//! heights that lie inside the polygon are the rectangles of that width, and the tallest is
//! exact. The widths are searched over the corners' positions and an even grid, and the best
//! pair is then refined by halving steps, so rectangles whose sides sit on corners or on grid
//! lines are found exactly and the others to within rounding.

use crate::{DVec2, DVec3, Plane, mesh::newell, planar::Polygon, split::split_polygon};

/// Even grid lines across the polygon tried besides its corners.
const GRID: usize = 48;

/// Halving steps of the refinement.
const REFINE_STEPS: usize = 60;

/// The largest rectangle inside a simple planar polygon with two sides along `along` (projected
/// into the polygon's plane), as its four corners counter-clockwise about the polygon's normal,
/// starting at the corner least along `along` and least across it. `None` for invalid polygons
/// (see [`crate::offset::offset_polygon`]) and a direction along the normal.
pub fn inner_rectangle(points: &[DVec3], along: DVec3) -> Option<[DVec3; 4]> {
    let polygon = Polygon::new(points, true)?;
    let normal = polygon.frame.normal;
    let u = along.reject_from(normal).try_normalize()?;
    let v = normal.cross(u);
    let origin = polygon.frame.origin;
    let flat: Vec<DVec2> = polygon
        .world
        .iter()
        .map(|&p| DVec2::new((p - origin).dot(u), (p - origin).dot(v)))
        .collect();
    let (lo, hi) = best_rectangle(&flat, polygon.eps)?;
    let at = |x: f64, y: f64| origin + u * x + v * y;
    Some([
        at(lo.x, lo.y),
        at(hi.x, lo.y),
        at(hi.x, hi.y),
        at(lo.x, hi.y),
    ])
}

/// The pieces of a simple planar polygon left when `rectangle` (inside it, as
/// [`inner_rectangle`] gives it) is taken out: the polygon cut along the rectangle's four sides,
/// all pieces but the rectangle, counter-clockwise like the polygon.
pub fn around_rectangle(points: &[DVec3], rectangle: &[DVec3; 4]) -> Vec<Vec<DVec3>> {
    let [a, b, _, d] = *rectangle;
    let (Some(u), Some(v)) = ((b - a).try_normalize(), (d - a).try_normalize()) else {
        return vec![points.to_vec()];
    };
    let (width, height) = (a.distance(b), a.distance(d));
    let mut rest = Vec::new();
    let mut middle = vec![points.to_vec()];
    // Cut away what lies before and beyond the rectangle along u, then along v.
    for (axis, start, length) in [(u, a.dot(u), width), (v, a.dot(v), height)] {
        let mut kept = Vec::new();
        for piece in middle {
            let (before, after) = split_polygon(
                &piece,
                &Plane {
                    normal: axis,
                    offset: start,
                },
            );
            rest.extend(before);
            for piece in after {
                let (inside, beyond) = split_polygon(
                    &piece,
                    &Plane {
                        normal: axis,
                        offset: start + length,
                    },
                );
                rest.extend(beyond);
                kept.extend(inside);
            }
        }
        middle = kept;
    }
    // What is left between the four lines is the rectangle and, for a concave polygon, other
    // pieces of the polygon in its shadow; the rectangle is the piece of its area.
    let area = width * height;
    let mut rectangle_found = false;
    for piece in middle {
        let piece_area = newell(piece.iter().copied()).length() * 0.5;
        if !rectangle_found && (piece_area - area).abs() <= 1e-9 * area.max(1.0) {
            rectangle_found = true;
        } else {
            rest.push(piece);
        }
    }
    rest
}

/// The largest axis-aligned rectangle inside a simple counter-clockwise 2D polygon, as its
/// least and greatest corners.
fn best_rectangle(polygon: &[DVec2], eps: f64) -> Option<(DVec2, DVec2)> {
    let (min, max) = polygon
        .iter()
        .fold((DVec2::MAX, DVec2::MIN), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let cell = (max.x - min.x) / GRID as f64;
    let mut xs: Vec<f64> = polygon.iter().map(|p| p.x).collect();
    xs.extend((1..GRID).map(|k| min.x + cell * k as f64));
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| (*a - *b).abs() <= eps);
    let mut best = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (i, &x1) in xs.iter().enumerate() {
        for &x2 in &xs[i + 1..] {
            let (area, y1, y2) = tallest(polygon, x1, x2, eps);
            if area > best.0 {
                best = (area, x1, x2, y1, y2);
            }
        }
    }
    if best.0 <= 0.0 {
        return None;
    }
    // Refine both sides by halving steps while the area grows.
    let mut step = cell * 0.5;
    for _ in 0..REFINE_STEPS {
        let (_, x1, x2, ..) = best;
        let mut moved = false;
        for (n1, n2) in [
            (x1 - step, x2),
            (x1 + step, x2),
            (x1, x2 - step),
            (x1, x2 + step),
        ] {
            if n1 < min.x || n2 > max.x || n2 <= n1 {
                continue;
            }
            let (area, y1, y2) = tallest(polygon, n1, n2, eps);
            if area > best.0 * (1.0 + 1e-12) {
                best = (area, n1, n2, y1, y2);
                moved = true;
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    let (_, x1, x2, y1, y2) = best;
    Some((DVec2::new(x1, y1), DVec2::new(x2, y2)))
}

/// The tallest rectangle inside the polygon over the open strip `x1 < x < x2`: its area and its
/// lower and upper sides.
fn tallest(polygon: &[DVec2], x1: f64, x2: f64, eps: f64) -> (f64, f64, f64) {
    let n = polygon.len();
    let mut blocked: Vec<(f64, f64)> = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        let (left, right) = if a.x <= b.x { (a, b) } else { (b, a) };
        if right.x <= x1 || left.x >= x2 {
            continue;
        }
        let y_at = |x: f64| {
            if right.x - left.x <= eps {
                left.y
            } else {
                left.y + (right.y - left.y) * ((x - left.x) / (right.x - left.x))
            }
        };
        let (ya, yb) = (y_at(x1.max(left.x)), y_at(x2.min(right.x)));
        let (ya, yb) = if right.x - left.x <= eps {
            (left.y, right.y)
        } else {
            (ya, yb)
        };
        blocked.push((ya.min(yb), ya.max(yb)));
    }
    blocked.sort_by(|p, q| p.0.total_cmp(&q.0));
    let middle = 0.5 * (x1 + x2);
    let mut best = (0.0, 0.0, 0.0);
    let mut reach = f64::NEG_INFINITY;
    for &(lo, hi) in &blocked {
        if reach.is_finite() && lo > reach + eps {
            let gap = lo - reach;
            let area = gap * (x2 - x1);
            if area > best.0 && contains(polygon, DVec2::new(middle, 0.5 * (lo + reach))) {
                best = (area, reach, lo);
            }
        }
        reach = reach.max(hi);
    }
    best
}

/// Even–odd point-in-polygon test.
fn contains(polygon: &[DVec2], p: DVec2) -> bool {
    let n = polygon.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (b.x - a.x) * (p.y - a.y) / (b.y - a.y) {
            inside = !inside;
        }
    }
    inside
}
