//! Offsetting (growing) and insetting (shrinking) convex polygons.

use crate::{DVec3, mesh::newell};

/// Moves every edge of a convex planar polygon (counter-clockwise about its normal) outward by
/// `distance`, or inward when `distance` is negative, and returns the resulting polygon.
///
/// An inset is the intersection of the inward-moved half-planes, so edges that shrink to nothing
/// disappear cleanly; it returns `None` when the polygon vanishes. Corners on a straight line are
/// dropped from the result.
pub fn offset_convex(points: &[DVec3], distance: f64) -> Option<Vec<DVec3>> {
    let normal = newell(points.iter().copied()).normalize_or_zero();
    if normal == DVec3::ZERO || !distance.is_finite() {
        return None;
    }
    let edges = edges_with_outward(points, normal);
    if edges.len() < 3 {
        return None;
    }
    let result = if distance <= 0.0 {
        edges
            .iter()
            .try_fold(points.to_vec(), |poly, &(p, _, out)| {
                let kept = clip_convex(&poly, out, out.dot(p) + distance);
                (kept.len() >= 3).then_some(kept)
            })?
    } else {
        // Outward, no edge can vanish: each corner is where two neighbouring moved edges meet.
        let m = edges.len();
        (0..m)
            .map(|i| {
                let (p0, d0, o0) = edges[(i + m - 1) % m];
                let (p1, d1, o1) = edges[i];
                let (a, b) = (p0 + o0 * distance, p1 + o1 * distance);
                // Solve a + s·d0 = b + t·d1 in the plane.
                let s = (b - a).cross(d1).dot(normal) / d0.cross(d1).dot(normal);
                a + d0 * s
            })
            .collect()
    };
    let area = newell(result.iter().copied()).length() * 0.5;
    (area > 0.0).then_some(result)
}

/// The non-degenerate, non-collinear edges of a polygon as (start, unit direction, unit outward
/// normal in the polygon's plane).
fn edges_with_outward(points: &[DVec3], normal: DVec3) -> Vec<(DVec3, DVec3, DVec3)> {
    let n = points.len();
    let mut edges: Vec<(DVec3, DVec3, DVec3)> = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        let Some(dir) = (b - a).try_normalize() else {
            continue;
        };
        if let Some(&(_, last, _)) = edges.last() {
            if last.cross(dir).length() < 1e-12 && last.dot(dir) > 0.0 {
                continue;
            }
        }
        edges.push((a, dir, dir.cross(normal)));
    }
    if edges.len() > 1 {
        let (first, last) = (edges[0].1, edges[edges.len() - 1].1);
        if last.cross(first).length() < 1e-12 && last.dot(first) > 0.0 {
            edges.remove(0);
        }
    }
    edges
}

/// Keeps the part of a convex polygon where `normal · p <= offset` (Sutherland–Hodgman).
fn clip_convex(poly: &[DVec3], normal: DVec3, offset: f64) -> Vec<DVec3> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let (da, db) = (normal.dot(a) - offset, normal.dot(b) - offset);
        if da <= 0.0 {
            out.push(a);
        }
        if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
    }
    out
}
