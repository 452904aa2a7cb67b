//! Building envelopes (CGA's `envelope`): the largest volume over a footprint that stays under
//! a height limit and, from each edge, under a plane rising inward at that edge's angle above
//! an upright wall of that edge's base height.

use crate::{DVec3, Mesh, Plane, extrude::extrude_along, mesh::newell, split::split};

/// The envelope over a planar polygon (counter-clockwise about its normal): the prism up to
/// `max_height` along `up` (unit length, pointing to the polygon's front side), cut by one plane
/// per edge: edge `i` keeps an upright wall up to `edges[i].0` above it, then a plane rising
/// inward at `edges[i].1` degrees from the polygon's plane (90° or more, or a missing entry,
/// cuts nothing). A closed mesh, `None` for a polygon without area, a height of 0 or less, a
/// negative base or an angle of 0 or less (or anything not finite), or when nothing is left.
pub fn envelope(
    points: &[DVec3],
    up: DVec3,
    max_height: f64,
    edges: &[(f64, f64)],
) -> Option<Mesh> {
    let normal = newell(points.iter().copied()).try_normalize()?;
    let up = up.try_normalize()?;
    if !(max_height > 0.0 && max_height.is_finite()) || up.dot(normal) <= 0.0 {
        return None;
    }
    if edges.iter().any(|&(base, angle)| {
        !(base >= 0.0 && base.is_finite() && angle > 0.0 && angle.is_finite())
    }) {
        return None;
    }
    let mut solid = extrude_along(points, up * max_height)?;
    let n = points.len();
    for (i, &(base, angle)) in edges.iter().enumerate().take(n) {
        if angle >= 90.0 || base >= max_height {
            continue;
        }
        let (a, b) = (points[i], points[(i + 1) % n]);
        let Some(out) = (b - a).cross(normal).try_normalize() else {
            continue;
        };
        // Above the wall, a point may rise tan(angle) for each metre it lies inward.
        let slope = angle.to_radians().tan();
        let plane = Plane::from_point_normal(a + up * base, up + out * slope);
        let (kept, _) = split(&solid, &plane);
        if kept.is_empty() {
            return None;
        }
        solid = kept;
    }
    Some(solid)
}
