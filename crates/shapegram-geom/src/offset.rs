//! Offsetting (growing) and insetting (shrinking) polygons, convex or not.
//!
//! Convex polygons move their edges and intersect half-planes ([`offset_convex`]). Other simple
//! polygons use the wavefront of the straight skeleton: every edge moves at unit speed and corners
//! slide along their bisectors (mitred corners), and where the moving outline meets itself it
//! changes shape as it should: a narrow part of an inset pinches off and the polygon falls into
//! several, a notch of an outward offset closes, a bay that closes off becomes a hole. The border
//! ring of [`inset_border`] consists of the regions the edges swept on the way, so the inside and
//! the border always tile the polygon.

use crate::{
    DVec2, DVec3,
    mesh::newell,
    planar::{Polygon, clip_convex, is_convex, kept_corners, signed_area},
    skeleton::{Skeleton, outline, propagate, propagate_weighted},
};

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
        if let Some(&(_, last, _)) = edges.last()
            && last.cross(dir).length() < 1e-12
            && last.dot(dir) > 0.0
        {
            continue;
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

/// Offsets a simple planar polygon (counter-clockwise about its normal, convex or not) by moving
/// every edge `distance` outward (inward when negative), with mitred corners; returns the loops of
/// the result, counter-clockwise, with holes clockwise.
///
/// An inset can fall into several polygons or vanish (no loops); an outward offset is one polygon
/// whose closed-off bays become holes. Convex input goes through [`offset_convex`]. A distance of
/// zero returns the polygon without repeated corners. Invalid input (fewer than three distinct
/// corners, no area, not planar, self-touching, non-finite) gives no loops.
pub fn offset_polygon(points: &[DVec3], distance: f64) -> Vec<Vec<DVec3>> {
    let Some(polygon) = Polygon::new(points, false) else {
        return Vec::new();
    };
    if !distance.is_finite() {
        return Vec::new();
    }
    if distance == 0.0 {
        return vec![polygon.world];
    }
    if is_convex(&polygon.flat, polygon.eps) {
        return offset_convex(&polygon.world, distance)
            .into_iter()
            .collect();
    }
    let Some(wave) = Wavefront::run(&polygon.flat, distance) else {
        return Vec::new();
    };
    wave.skeleton
        .front
        .iter()
        .map(|loop_| {
            let mut points: Vec<DVec3> = loop_.iter().map(|&i| wave.world(&polygon, i)).collect();
            if wave.outward {
                points.reverse();
            }
            points
        })
        .collect()
}

/// CGA's `offset(distance) comp(f) { inside : … | border : … }` on a simple planar polygon
/// (counter-clockwise about its normal, convex or not): returns `(inside, border)`.
///
/// A negative `distance` insets: `inside` holds the inset polygon(s) (none once the polygon has
/// vanished) and `border` the ring between the outline and the inset, one polygon per edge (in
/// edge order, repeated corners dropped): the region that edge swept while moving inward, a
/// trapezoid while no corner of the inset has run into another, a triangle for an edge that shrank
/// away, and so on. A positive `distance` grows: `inside` is the polygon itself and `border` the
/// regions the edges swept outward. Either way the pieces tile the result without gaps or overlaps
/// and share their corners. A distance of zero gives the polygon and no border; invalid input (see
/// [`offset_polygon`]) gives nothing.
pub fn inset_border(points: &[DVec3], distance: f64) -> (Vec<Vec<DVec3>>, Vec<Vec<DVec3>>) {
    let Some(polygon) = Polygon::new(points, false) else {
        return (Vec::new(), Vec::new());
    };
    if !distance.is_finite() {
        return (Vec::new(), Vec::new());
    }
    if distance == 0.0 {
        return (vec![polygon.world], Vec::new());
    }
    let Some(wave) = Wavefront::run(&polygon.flat, distance) else {
        return (Vec::new(), Vec::new());
    };
    let loops = |loops: &[Vec<usize>]| -> Vec<Vec<DVec3>> {
        loops
            .iter()
            .map(|l| l.iter().map(|&i| wave.world(&polygon, i)).collect())
            .collect()
    };
    let faces = loops(&wave.skeleton.faces);
    if wave.outward {
        // Edge k of the reversed polygon is edge n − 2 − k of the polygon, run backwards.
        let n = faces.len();
        let border = (0..n).map(|e| faces[(2 * n - 2 - e) % n].clone()).collect();
        (vec![polygon.world.clone()], border)
    } else {
        (loops(&wave.skeleton.front), faces)
    }
}

/// The outline of a simple counter-clockwise 2D polygon grown outward by `distance` (> 0) with
/// mitred corners, without repeated corners or corners on a straight line; holes that closed off
/// are ignored. `None` if the propagation fails.
pub(crate) fn grown_outline(flat: &[DVec2], distance: f64, eps: f64) -> Option<Vec<DVec2>> {
    let reversed: Vec<DVec2> = flat.iter().rev().copied().collect();
    let skeleton = propagate(&reversed, distance, false)?;
    // Run backwards, the outer loop is the one turning clockwise.
    let outer: Vec<DVec2> = skeleton
        .front
        .iter()
        .map(|l| {
            l.iter()
                .rev()
                .map(|&i| skeleton.nodes[i].p)
                .collect::<Vec<_>>()
        })
        .max_by(|a, b| signed_area(a).total_cmp(&signed_area(b)))?;
    let kept = kept_corners(&outer, eps, true);
    (kept.len() >= 3).then(|| kept.iter().map(|&i| outer[i]).collect())
}

/// A wavefront propagated from a polygon's outline, inward or (on the reversed outline) outward.
struct Wavefront {
    skeleton: Skeleton,
    outward: bool,
}

impl Wavefront {
    /// Propagates by `|distance|`, outward for a positive distance.
    fn run(flat: &[DVec2], distance: f64) -> Option<Self> {
        let outward = distance > 0.0;
        let skeleton = if outward {
            let reversed: Vec<DVec2> = flat.iter().rev().copied().collect();
            propagate(&reversed, distance, false)?
        } else {
            propagate(flat, -distance, true)?
        };
        Some(Self { skeleton, outward })
    }

    /// World position of node `i`: the polygon's own corners exactly, the others in its plane.
    fn world(&self, polygon: &Polygon, i: usize) -> DVec3 {
        let n = polygon.world.len();
        match (i < n, self.outward) {
            (true, false) => polygon.world[i],
            (true, true) => polygon.world[n - 1 - i],
            _ => polygon.frame.lift(self.skeleton.nodes[i].p, 0.0),
        }
    }
}

/// The strip a setback cuts along one edge.
#[derive(Clone, Debug, PartialEq)]
pub struct Strip {
    /// The edge's index in the polygon (corners on a straight line dropped first).
    pub edge: usize,
    /// The edge's start and end corners.
    pub ends: [DVec3; 2],
    /// The strip, counter-clockwise about the polygon's normal, starting with the edge.
    pub polygon: Vec<DVec3>,
}

/// What CGA's `setback` cuts from a polygon: a strip along each moving edge and what remains.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Setback {
    /// The strips of the moving edges, in edge order (edges whose strip has no area left out).
    pub strips: Vec<Strip>,
    /// The outline of all strips together (CGA's `shape` of `shapeL` and friends), one loop per
    /// connected piece, counter-clockwise.
    pub outline: Vec<Vec<DVec3>>,
    /// The rest of the polygon: none, one or (for a waisted polygon) several loops.
    pub remainder: Vec<Vec<DVec3>>,
}

/// CGA's `setback` on a simple planar polygon (counter-clockwise about its normal, convex or
/// not): edge `i` moves inward by `distance(i, start, end)` (0 or more; 0 stays where it is) and
/// the corners between edges slide along the lines of their neighbours (a weighted straight
/// skeleton; edges of equal distance meet in mitres). The strips the moving edges sweep and the
/// remainder tile the polygon. Corners on a straight line are dropped before edges are counted.
/// `None` for invalid input (see [`offset_polygon`]), a distance that is negative or not
/// finite, or a setback so deep that a moving edge runs onto the line of an edge moving slower
/// (where no weighted skeleton goes on); when no edge moves the polygon stays whole.
pub fn setback(points: &[DVec3], distance: impl Fn(usize, DVec3, DVec3) -> f64) -> Option<Setback> {
    let polygon = Polygon::new(points, true)?;
    let n = polygon.world.len();
    let ends = |i: usize| [polygon.world[i], polygon.world[(i + 1) % n]];
    let distances: Vec<f64> = (0..n)
        .map(|i| {
            let [a, b] = ends(i);
            distance(i, a, b)
        })
        .collect();
    if distances.iter().any(|d| !(d.is_finite() && *d >= 0.0)) {
        return None;
    }
    let deepest = distances.iter().copied().fold(0.0, f64::max);
    if deepest == 0.0 {
        return Some(Setback {
            strips: Vec::new(),
            outline: Vec::new(),
            remainder: vec![polygon.world],
        });
    }
    // The deepest edges move at unit speed, exactly.
    let speeds: Vec<f64> = distances
        .iter()
        .map(|&d| if d == deepest { 1.0 } else { d / deepest })
        .collect();
    let skeleton = propagate_weighted(&polygon.flat, &speeds, deepest, true)?;
    let world = |i: usize| match i < n {
        true => polygon.world[i],
        false => polygon.frame.lift(skeleton.nodes[i].p, 0.0),
    };
    let area = |loop_: &[usize]| {
        let flat: Vec<DVec2> = loop_.iter().map(|&k| skeleton.nodes[k].p).collect();
        signed_area(&flat)
    };
    let tiny = polygon.eps * polygon.eps;
    let strips: Vec<usize> = (0..n)
        .filter(|&i| speeds[i] > 0.0 && area(&skeleton.faces[i]) > tiny)
        .collect();
    let remainder: Vec<&Vec<usize>> = skeleton.front.iter().filter(|l| area(l) > tiny).collect();
    // A moving edge that runs onto the line of a slower one has no weighted skeleton (the
    // corner between them cannot keep to both): the pieces would not tile the polygon, which is
    // refused rather than returned.
    let pieces: f64 = strips
        .iter()
        .map(|&i| area(&skeleton.faces[i]))
        .sum::<f64>()
        + remainder.iter().map(|l| area(l)).sum::<f64>();
    let whole = signed_area(&polygon.flat);
    if (pieces - whole).abs() > 1e-9 * whole.max(1.0) + tiny * n as f64 {
        return None;
    }
    let faces: Vec<&[usize]> = strips
        .iter()
        .map(|&i| skeleton.faces[i].as_slice())
        .collect();
    let loops = |loops: &[&[usize]]| -> Vec<Vec<DVec3>> {
        loops
            .iter()
            .map(|l| l.iter().map(|&k| world(k)).collect())
            .collect()
    };
    let positions: Vec<DVec2> = skeleton.nodes.iter().map(|node| node.p).collect();
    let outline = outline(&faces, &positions)?;
    let outline: Vec<&[usize]> = outline.iter().map(Vec::as_slice).collect();
    let remainder: Vec<&[usize]> = remainder.iter().map(|l| l.as_slice()).collect();
    Some(Setback {
        strips: strips
            .iter()
            .map(|&i| Strip {
                edge: i,
                ends: ends(i),
                polygon: loops(&[skeleton.faces[i].as_slice()]).remove(0),
            })
            .collect(),
        outline: loops(&outline),
        remainder: loops(&remainder),
    })
}
