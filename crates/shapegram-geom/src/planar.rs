//! Planar polygons in their own 2D frame: validation and clean-up shared by roofs and offsets.

use std::ops::{Add, Mul, Sub};

use crate::{DVec2, DVec3, mesh::newell, triangulate::plane_basis};

/// How far (relative to the polygon's size) a corner may lie off the polygon's plane.
const PLANARITY: f64 = 1e-6;

/// Relative tolerance below which two corners coincide or a corner lies on a line.
pub(crate) const FLAT_EPSILON: f64 = 1e-9;

/// A right-handed frame in a polygon's plane: `u × v = normal`, so a polygon counter-clockwise
/// about `normal` is counter-clockwise in `(u, v)` coordinates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    pub origin: DVec3,
    pub u: DVec3,
    pub v: DVec3,
    pub normal: DVec3,
}

impl Frame {
    /// Plane coordinates of a world point (its height above the plane is dropped).
    pub fn flat(&self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.u), d.dot(self.v))
    }

    /// The world point at plane coordinates `q` and `height` along the normal.
    pub fn lift(&self, q: DVec2, height: f64) -> DVec3 {
        self.origin + self.u * q.x + self.v * q.y + self.normal * height
    }

    /// A plane direction in world coordinates.
    pub fn direction(&self, d: DVec2) -> DVec3 {
        self.u * d.x + self.v * d.y
    }
}

/// A validated planar polygon: its frame and its corners in world and plane coordinates (repeated
/// corners removed, optionally corners on a straight line too).
#[derive(Clone, Debug)]
pub(crate) struct Polygon {
    pub frame: Frame,
    pub world: Vec<DVec3>,
    pub flat: Vec<DVec2>,
    /// The tolerance used for coincidence, scaled to the polygon.
    pub eps: f64,
}

impl Polygon {
    /// Validates a polygon: finite, planar, simple (no edge touches a non-neighbouring edge, no
    /// corner folds back), with area. Its frame's normal is the Newell normal, so the corners run
    /// counter-clockwise in plane coordinates. `drop_collinear` removes corners on a straight line.
    pub fn new(points: &[DVec3], drop_collinear: bool) -> Option<Self> {
        if points.len() < 3 || !points.iter().all(|p| p.is_finite()) {
            return None;
        }
        let normal = newell(points.iter().copied()).try_normalize()?;
        let (u, v) = plane_basis(normal);
        let frame = Frame {
            origin: points[0],
            u,
            v,
            normal,
        };
        let size = crate::Aabb::from_points(points.iter().copied())?.diagonal();
        if points
            .iter()
            .any(|&p| (p - frame.origin).dot(normal).abs() > PLANARITY * size)
        {
            return None;
        }
        let eps = FLAT_EPSILON * size;
        let all: Vec<DVec2> = points.iter().map(|&p| frame.flat(p)).collect();
        let kept = kept_corners(&all, eps, drop_collinear);
        let flat: Vec<DVec2> = kept.iter().map(|&i| all[i]).collect();
        if flat.len() < 3 || signed_area(&flat) <= eps * perimeter(&flat) || !is_simple(&flat, eps)
        {
            return None;
        }
        Some(Self {
            frame,
            world: kept.iter().map(|&i| points[i]).collect(),
            flat,
            eps,
        })
    }
}

/// Indices of the corners of a 2D loop left after dropping repeated corners (within `eps`) and,
/// if asked, corners on a straight line, until none is left to drop.
pub(crate) fn kept_corners(points: &[DVec2], eps: f64, drop_collinear: bool) -> Vec<usize> {
    let mut kept: Vec<usize> = (0..points.len()).collect();
    while kept.len() >= 3 {
        let n = kept.len();
        let drop = (0..n).find(|&k| {
            let (a, b, c) = (
                points[kept[(k + n - 1) % n]],
                points[kept[k]],
                points[kept[(k + 1) % n]],
            );
            a.distance(b) <= eps
                || (drop_collinear
                    && (c - a).perp_dot(b - a).abs() <= eps * (c - a).length()
                    && (b - a).dot(c - b) > 0.0)
        });
        match drop {
            Some(k) => {
                kept.remove(k);
            }
            None => break,
        }
    }
    kept
}

/// Signed area of a 2D loop: positive when counter-clockwise.
pub(crate) fn signed_area(points: &[DVec2]) -> f64 {
    let n = points.len();
    if n < 3 {
        return 0.0;
    }
    let o = points[0];
    (1..n - 1)
        .map(|i| (points[i] - o).perp_dot(points[i + 1] - o))
        .sum::<f64>()
        * 0.5
}

/// Length of the boundary of a 2D loop.
pub(crate) fn perimeter(points: &[DVec2]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].distance(points[(i + 1) % n]))
        .sum()
}

/// Whether a counter-clockwise 2D loop is convex (corners on a straight line allowed).
pub(crate) fn is_convex(points: &[DVec2], eps: f64) -> bool {
    let n = points.len();
    (0..n).all(|i| {
        let (a, b, c) = (points[i], points[(i + 1) % n], points[(i + 2) % n]);
        (b - a).perp_dot(c - b) >= -eps * (c - a).length()
    })
}

/// Whether a 2D loop is simple: non-neighbouring edges stay more than `eps` apart and no corner
/// turns back onto its incoming edge.
pub(crate) fn is_simple(points: &[DVec2], eps: f64) -> bool {
    let n = points.len();
    for i in 0..n {
        let (a, b, c) = (points[i], points[(i + 1) % n], points[(i + 2) % n]);
        let (ab, bc) = (b - a, c - b);
        if ab.perp_dot(bc).abs() <= eps * ab.length().max(bc.length()) && ab.dot(bc) < 0.0 {
            return false;
        }
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (c, d) = (points[j], points[(j + 1) % n]);
            if segment_distance(a, b, c, d, eps) <= eps {
                return false;
            }
        }
    }
    true
}

/// Distance from `p` to the segment `a b`.
pub(crate) fn point_segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// Distance between the segments `a b` and `c d` (zero when they cross), exact to about `eps`.
fn segment_distance(a: DVec2, b: DVec2, c: DVec2, d: DVec2, eps: f64) -> f64 {
    // Signed distances from the other segment's line; only clear signs count as a crossing, as
    // the signs of (nearly) collinear segments are rounding noise.
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p) / p.distance(q).max(eps);
    let opposite = |s: f64, t: f64| (s > eps && t < -eps) || (s < -eps && t > eps);
    if opposite(side(a, b, c), side(a, b, d)) && opposite(side(c, d, a), side(c, d, b)) {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// A point of a plane or of space, for the clipping both kinds of polygon share.
pub(crate) trait Point:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self>
{
    fn dot(self, other: Self) -> f64;
}

impl Point for DVec2 {
    fn dot(self, other: Self) -> f64 {
        DVec2::dot(self, other)
    }
}

impl Point for DVec3 {
    fn dot(self, other: Self) -> f64 {
        DVec3::dot(self, other)
    }
}

/// Keeps the part of a convex polygon where `normal · p <= offset` (Sutherland–Hodgman).
pub(crate) fn clip_convex<P: Point>(polygon: &[P], normal: P, offset: f64) -> Vec<P> {
    let n = polygon.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
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
