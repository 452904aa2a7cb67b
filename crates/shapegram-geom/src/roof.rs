//! Roofs on planar footprints, as CGA's `roofGable`, `roofHip`, `roofPyramid` and `roofShed` build
//! them.
//!
//! A footprint is a simple polygon, counter-clockwise about its normal, in any plane: roofs are
//! built in the polygon's own frame with their height along its normal (+y for a lot). Every roof
//! is a closed mesh with outward normals: the footprint, reversed, is its bottom face. Repeated
//! corners and corners on a straight line are dropped first, so they add no faces.
//!
//! The angle is the slope of the roof planes in degrees, strictly between 0 and 90. Invalid input
//! gives `None`: an angle out of range or not finite, a negative or non-finite overhang, a
//! footprint with fewer than three distinct corners, without area, not planar (a corner more than
//! 10⁻⁶ of the footprint's size off its plane) or touching itself.
//!
//! Hip roofs, and gable roofs on non-convex footprints, come from the straight skeleton (see the
//! private `skeleton` module), which merges events closer than 10⁻⁸ of the footprint's size:
//! faces are planar to that tolerance, exactly so on regular footprints. It costs O(n³) for n
//! corners, fine for building footprints.
//!
//! # Overhang
//! With an overhang the eaves reach out by that horizontal distance. The roof planes still pass
//! through the footprint's edges at height zero, so the eaves end `overhang · tan(angle)` below the
//! footprint's plane. The mesh stays closed: its bottom face is the footprint grown by the overhang
//! (mitred corners), lowered to the eaves. (CGA leaves the underside open; a closed mesh keeps
//! volumes and later cuts well defined.)

use crate::{
    DVec2, DVec3, Mesh, Plane,
    extrude::extrude_polygon,
    offset::grown_outline,
    planar::{Polygon, clip_convex, is_convex, signed_area},
    skeleton::{Skeleton, propagate},
    split::split,
};

/// A hip roof: every edge of the footprint carries a roof plane rising inward at `angle_deg`, and
/// each plane holds the part of the roof its edge reaches first as the edges move inward: the
/// straight skeleton of the footprint. A rectangle gets two trapezoids and two triangles meeting
/// a ridge, a square a pyramid; on any convex footprint the roof is the footprint's prism cut by
/// every edge's slope plane. Non-convex footprints (L, T, U shapes…) get the full straight-skeleton
/// roof, with valleys from the reflex corners. See the module docs for `overhang` and invalid input.
pub fn roof_hip(points: &[DVec3], angle_deg: f64, overhang: f64) -> Option<Mesh> {
    let slope = slope(angle_deg)?;
    let footprint = Polygon::new(points, true)?;
    let base = Base::new(&footprint, overhang, slope)?;
    let skeleton = propagate(&base.flat, f64::INFINITY, true)?;
    Some(base.roof(&footprint, &skeleton, slope))
}

/// A gable roof: two roof planes rising at `angle_deg` meet at a level ridge, and the ends are
/// upright gable walls.
///
/// On a convex footprint the ridge runs parallel to the longest edge (the first one on a tie): the
/// two planes rise from the two outermost lines parallel to that edge that touch the footprint, and
/// the roof is the prism over the footprint cut by both. A rectangle gets its ridge along the long
/// axis, two rectangular slopes and two gable triangles; on other shapes the edges not parallel to
/// the ridge carry upright walls. A non-convex footprint gets its hip roof with every hip end (a
/// triangle under the end of a level ridge) turned into a gable by running the ridge out to the
/// edge; hips whose ridge would leave the edge stay hips. See the module docs for `overhang` and
/// invalid input.
pub fn roof_gable(points: &[DVec3], angle_deg: f64, overhang: f64) -> Option<Mesh> {
    roof_gable_with(
        points,
        angle_deg,
        &Gable {
            overhang_x: overhang,
            overhang_y: overhang,
            ridge_edge: None,
        },
    )
}

/// The options of a gable roof beyond its angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gable {
    /// The overhang at the eaves, across the ridge.
    pub overhang_x: f64,
    /// The overhang at the gable ends, along the ridge; negative shortens the roof there.
    pub overhang_y: f64,
    /// The edge the ridge runs along (counted after dropping repeated corners and corners on a
    /// straight line, modulo their count) instead of the longest; only for convex footprints.
    pub ridge_edge: Option<usize>,
}

/// A gable roof as [`roof_gable`] builds it, with separate overhangs at the eaves and at the
/// gable ends and, on a convex footprint, the ridge along a chosen edge. On a convex footprint
/// every edge along the ridge moves out by `overhang_x` and every other edge (the gable walls)
/// by `overhang_y`, mitred; the eaves end `overhang_x · tan(angle)` below the footprint's plane.
/// Non-convex footprints take `overhang_x` all round and their ridges as [`roof_gable`] finds
/// them. A negative `overhang_x`, or an `overhang_y` that leaves no roof, gives `None`.
pub fn roof_gable_with(points: &[DVec3], angle_deg: f64, gable: &Gable) -> Option<Mesh> {
    let slope = slope(angle_deg)?;
    let footprint = Polygon::new(points, true)?;
    if is_convex(&footprint.flat, footprint.eps) {
        let ridge_edge = match gable.ridge_edge {
            Some(i) => i % footprint.flat.len(),
            None => longest_edge(&footprint.flat)?,
        };
        let base = if gable.overhang_x == gable.overhang_y {
            Base::new(&footprint, gable.overhang_x, slope)?
        } else {
            Base::gable_ends(&footprint, ridge_edge, gable, slope)?
        };
        return convex_gable(&footprint, &base, slope, ridge_edge);
    }
    let base = Base::new(&footprint, gable.overhang_x, slope)?;
    let mut skeleton = propagate(&base.flat, f64::INFINITY, true)?;
    raise_gables(&mut skeleton, &base.flat);
    Some(base.roof(&footprint, &skeleton, slope))
}

/// A ridge roof (CGA's `roofRidge`): one level ridge along `along` (projected into the
/// footprint's plane), two planes rising at `angle_deg` from the outermost lines of the
/// footprint on either side of it, and upright walls on every other edge up to them; no hips and
/// no gables of their own. Any simple footprint, convex or not; a direction along the normal or
/// invalid input (see the module docs) gives `None`.
pub fn roof_ridge(points: &[DVec3], angle_deg: f64, along: DVec3) -> Option<Mesh> {
    let slope = slope(angle_deg)?;
    let footprint = Polygon::new(points, true)?;
    let out = ridge_across(&footprint, along)?;
    let base = Base::new(&footprint, 0.0, slope)?;
    ridged(&footprint, &base, slope, out)
}

/// The unit direction across a ridge along `along`, in the footprint's plane coordinates.
fn ridge_across(footprint: &Polygon, along: DVec3) -> Option<DVec2> {
    let frame = &footprint.frame;
    let d = along.reject_from(frame.normal).try_normalize()?;
    let flat = DVec2::new(d.dot(frame.u), d.dot(frame.v));
    Some(DVec2::new(flat.y, -flat.x))
}

/// The roofs whose angle [`roof_run`] relates to their height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RoofShape {
    /// [`roof_hip`] (and [`roof_gable`] on a non-convex footprint).
    Hip,
    /// [`roof_gable_with`] on a convex footprint, the ridge along the given edge or the longest.
    Gable(Option<usize>),
    /// [`roof_pyramid`].
    Pyramid,
    /// [`roof_shed`] rising from the given edge.
    Shed(usize),
    /// [`roof_ridge`] with its ridge along the direction.
    Ridge(DVec3),
}

/// How far, across the footprint, a roof rises to its highest point: its height is this run
/// times the tangent of its angle, whatever the overhang; `atan(height / run)` is the angle of a
/// roof of a given height (CGA's `byHeight`). The greatest depth of the straight skeleton for a
/// hip roof (and a gable roof on a non-convex footprint), half the footprint's width across the
/// ridge for a gable roof, the distance from the centroid to the nearest edge's line for a
/// pyramid, the footprint's depth behind the edge for a shed roof. `None` for invalid
/// footprints.
pub fn roof_run(points: &[DVec3], shape: RoofShape) -> Option<f64> {
    let footprint = Polygon::new(points, true)?;
    let flat = &footprint.flat;
    let n = flat.len();
    let skeleton_depth = || {
        let skeleton = propagate(flat, f64::INFINITY, true)?;
        Some(
            skeleton
                .nodes
                .iter()
                .map(|node| node.time)
                .fold(0.0, f64::max),
        )
    };
    let run = match shape {
        RoofShape::Gable(edge) if is_convex(flat, footprint.eps) => {
            let edge = match edge {
                Some(i) => i % n,
                None => longest_edge(flat)?,
            };
            let out = outward(flat[edge], flat[(edge + 1) % n]);
            let across = flat.iter().map(|q| q.dot(out));
            let near = across.clone().fold(f64::INFINITY, f64::min);
            0.5 * (across.fold(f64::NEG_INFINITY, f64::max) - near)
        }
        RoofShape::Hip | RoofShape::Gable(_) => skeleton_depth()?,
        RoofShape::Ridge(along) => {
            let out = ridge_across(&footprint, along)?;
            let across = flat.iter().map(|q| q.dot(out));
            let near = across.clone().fold(f64::INFINITY, f64::min);
            0.5 * (across.fold(f64::NEG_INFINITY, f64::max) - near)
        }
        RoofShape::Pyramid => {
            let centroid = area_centroid(flat);
            (0..n)
                .map(|i| {
                    let (a, b) = (flat[i], flat[(i + 1) % n]);
                    (b - a).normalize().perp_dot(centroid - a)
                })
                .fold(f64::INFINITY, f64::min)
        }
        RoofShape::Shed(edge) => {
            let frame = &footprint.frame;
            let a = frame.flat(*points.get(edge)?);
            let b = frame.flat(points[(edge + 1) % points.len()]);
            if a.distance(b) <= footprint.eps {
                return None;
            }
            let out = outward(a, b);
            -flat.iter().map(|&q| (q - a).dot(out)).fold(0.0, f64::min)
        }
    };
    (run > footprint.eps).then_some(run)
}

/// The first edge within rounding of the longest, so that squares pick a stable ridge.
fn longest_edge(flat: &[DVec2]) -> Option<usize> {
    let n = flat.len();
    let length = |i: usize| flat[i].distance(flat[(i + 1) % n]);
    let longest = (0..n).map(length).fold(0.0, f64::max);
    (0..n).find(|&i| length(i) >= longest * (1.0 - 1e-9))
}

/// A pyramid roof: one triangle per edge up to an apex above the footprint's centroid.
///
/// The apex height makes the face over the edge nearest to the centroid rise at `angle_deg`
/// (height = tan(angle) · distance from the centroid to the nearest edge line), so faces over
/// farther edges are less steep; on a square or a regular polygon all faces have the slope. The
/// footprint must be star-shaped about its centroid (every edge seen from it from the inside, true
/// for every convex footprint), else the faces would overlap and the result is `None`.
pub fn roof_pyramid(points: &[DVec3], angle_deg: f64) -> Option<Mesh> {
    let slope = slope(angle_deg)?;
    let footprint = Polygon::new(points, true)?;
    let flat = &footprint.flat;
    let n = flat.len();
    let centroid = area_centroid(flat);
    let nearest = (0..n)
        .map(|i| {
            let (a, b) = (flat[i], flat[(i + 1) % n]);
            (b - a).normalize().perp_dot(centroid - a)
        })
        .fold(f64::INFINITY, f64::min);
    if nearest <= footprint.eps {
        return None;
    }
    let mut positions = footprint.world.clone();
    positions.push(footprint.frame.lift(centroid, slope * nearest));
    let (n, apex) = (n as u32, n as u32);
    let mut mesh = Mesh::from_faces(positions, [(0..n).rev().collect::<Vec<_>>()]);
    for i in 0..n {
        mesh.add_face(&[i, (i + 1) % n, apex]);
    }
    Some(mesh)
}

/// A pyramid of `height` over a simple planar polygon (CGA's `taper(height)`): its apex
/// `height` along the normal above the polygon's centroid (the centre of its area), joined to
/// every corner; a negative height points the apex the other way. The polygon (turned to face
/// away from the apex) is the bottom, so the mesh is closed with outward normals. `None` for a
/// height of zero or not finite, and for invalid polygons (see the module docs).
pub fn pyramid(points: &[DVec3], height: f64) -> Option<Mesh> {
    if height == 0.0 || !height.is_finite() {
        return None;
    }
    let footprint = Polygon::new(points, true)?;
    let n = footprint.world.len() as u32;
    let mut positions = footprint.world.clone();
    positions.push(footprint.frame.lift(area_centroid(&footprint.flat), height));
    let apex = n;
    let up = height > 0.0;
    let bottom: Vec<u32> = if up {
        (0..n).rev().collect()
    } else {
        (0..n).collect()
    };
    let mut mesh = Mesh::from_faces(positions, [bottom]);
    for i in 0..n {
        let (a, b) = (i, (i + 1) % n);
        mesh.add_face(&if up { [a, b, apex] } else { [b, a, apex] });
    }
    Some(mesh)
}

/// A shed roof: one plane rising at `angle_deg` from edge `edge_index` (from `points[edge_index]`
/// to the next point) across the footprint, over upright walls on the other edges.
///
/// The whole footprint must lie on the inner side of that edge's line (always so for a convex
/// footprint), else the plane would dip below it; that, an index out of range or an edge of zero
/// length give `None`, as does invalid input (see the module docs).
pub fn roof_shed(points: &[DVec3], angle_deg: f64, edge_index: usize) -> Option<Mesh> {
    let slope = slope(angle_deg)?;
    let footprint = Polygon::new(points, true)?;
    let frame = &footprint.frame;
    let start = *points.get(edge_index)?;
    let (a, b) = (
        frame.flat(start),
        frame.flat(points[(edge_index + 1) % points.len()]),
    );
    if a.distance(b) <= footprint.eps {
        return None;
    }
    let out = outward(a, b);
    let depth = footprint
        .flat
        .iter()
        .map(|&q| (q - a).dot(out))
        .fold(f64::INFINITY, f64::min);
    if footprint
        .flat
        .iter()
        .any(|&q| (q - a).dot(out) > footprint.eps)
    {
        return None;
    }
    let prism = extrude_polygon(&footprint.world, -2.0 * slope * depth)?;
    let plane = Plane::from_point_normal(start, frame.normal + frame.direction(out) * slope);
    let (roof, _) = split(&prism, &plane);
    (!roof.is_empty()).then_some(roof)
}

/// The tangent of a roof angle in degrees, if the angle is strictly between 0 and 90.
fn slope(angle_deg: f64) -> Option<f64> {
    (angle_deg > 0.0 && angle_deg < 90.0).then(|| angle_deg.to_radians().tan())
}

/// The unit normal of the edge `a → b` pointing out of a counter-clockwise polygon.
fn outward(a: DVec2, b: DVec2) -> DVec2 {
    let dir = (b - a).normalize();
    DVec2::new(dir.y, -dir.x)
}

/// The centroid of the area of a simple 2D polygon.
fn area_centroid(points: &[DVec2]) -> DVec2 {
    let o = points[0];
    let n = points.len();
    let (sum, twice_area) = (1..n - 1).fold((DVec2::ZERO, 0.0), |(sum, area), i| {
        let (b, c) = (points[i] - o, points[i + 1] - o);
        let cross = b.perp_dot(c);
        (sum + (b + c) * cross, area + cross)
    });
    o + sum / (3.0 * twice_area)
}

/// The polygon a roof stands on: the footprint itself, or the footprint grown by the overhang and
/// lowered to the eaves.
struct Base {
    flat: Vec<DVec2>,
    world: Vec<DVec3>,
    /// Height of the base above the footprint's plane (negative with an overhang).
    height: f64,
}

impl Base {
    /// The base for an overhang (`None` for a negative or non-finite one).
    fn new(footprint: &Polygon, overhang: f64, slope: f64) -> Option<Self> {
        if !(overhang >= 0.0 && overhang.is_finite()) {
            return None;
        }
        if overhang == 0.0 {
            return Some(Self {
                flat: footprint.flat.clone(),
                world: footprint.world.clone(),
                height: 0.0,
            });
        }
        let flat = grown_outline(&footprint.flat, overhang, footprint.eps)?;
        let height = -overhang * slope;
        let world = flat
            .iter()
            .map(|&q| footprint.frame.lift(q, height))
            .collect();
        Some(Self {
            flat,
            world,
            height,
        })
    }

    /// The base of a convex gable roof with separate overhangs: the edges parallel to the ridge's
    /// edge moved out by the eaves' overhang, the others by the gable ends', each the boundary of
    /// a half-plane; the base is where they all hold, lowered to the eaves.
    fn gable_ends(
        footprint: &Polygon,
        ridge_edge: usize,
        gable: &Gable,
        slope: f64,
    ) -> Option<Self> {
        let (x, y) = (gable.overhang_x, gable.overhang_y);
        if !(x >= 0.0 && x.is_finite() && y.is_finite()) {
            return None;
        }
        let flat = &footprint.flat;
        let n = flat.len();
        let direction = |i: usize| (flat[(i + 1) % n] - flat[i]).normalize();
        let ridge = direction(ridge_edge);
        let reach =
            flat.iter().fold(0.0_f64, |r, q| r.max(q.distance(flat[0]))) + x.abs() + y.abs();
        let mut region = vec![
            flat[0] + DVec2::new(-2.0, -2.0) * reach,
            flat[0] + DVec2::new(2.0, -2.0) * reach,
            flat[0] + DVec2::new(2.0, 2.0) * reach,
            flat[0] + DVec2::new(-2.0, 2.0) * reach,
        ];
        for i in 0..n {
            let out = outward(flat[i], flat[(i + 1) % n]);
            let moved = if direction(i).perp_dot(ridge).abs() <= 1e-9 {
                x
            } else {
                y
            };
            region = clip_convex(&region, out, out.dot(flat[i]) + moved);
        }
        if region.len() < 3 || signed_area(&region) <= 1e-9 * signed_area(flat) {
            return None;
        }
        let height = -x * slope;
        let world = region
            .iter()
            .map(|&q| footprint.frame.lift(q, height))
            .collect();
        Some(Self {
            flat: region,
            world,
            height,
        })
    }

    /// The closed roof mesh over this base from the faces of its skeleton: base corners as they
    /// are, the other nodes lifted by their time times the slope.
    fn roof(&self, footprint: &Polygon, skeleton: &Skeleton, slope: f64) -> Mesh {
        let n = self.world.len();
        let positions: Vec<DVec3> = skeleton
            .nodes
            .iter()
            .enumerate()
            .map(|(i, node)| match self.world.get(i) {
                Some(&corner) => corner,
                None => footprint
                    .frame
                    .lift(node.p, self.height + node.time * slope),
            })
            .collect();
        let mut mesh = Mesh::from_faces(positions, [(0..n as u32).rev().collect::<Vec<_>>()]);
        for face in &skeleton.faces {
            mesh.add_face(&face.iter().map(|&i| i as u32).collect::<Vec<_>>());
        }
        mesh.compacted()
    }
}

/// The gable roof of a convex footprint: its prism cut by the two planes rising from the outermost
/// lines parallel to the ridge's edge.
fn convex_gable(footprint: &Polygon, base: &Base, slope: f64, ridge_edge: usize) -> Option<Mesh> {
    let flat = &footprint.flat;
    let n = flat.len();
    let out = outward(flat[ridge_edge], flat[(ridge_edge + 1) % n]);
    ridged(footprint, base, slope, out)
}

/// The prism over `base` cut by two planes rising at `slope` toward each other from the
/// outermost lines of the base across `out` (a unit direction in the footprint's plane).
fn ridged(footprint: &Polygon, base: &Base, slope: f64, out: DVec2) -> Option<Mesh> {
    let across = base.flat.iter().map(|q| q.dot(out));
    let near = across.clone().fold(f64::INFINITY, f64::min);
    let far = across.fold(f64::NEG_INFINITY, f64::max);
    let ridge_height = slope * (far - near) * 0.5;
    // Tall enough that the two cuts remove the whole top; not tall enough to hurt precision.
    let prism = extrude_polygon(&base.world, 3.0 * ridge_height)?;
    let frame = &footprint.frame;
    let rising_from = |line: f64, side: f64| {
        Plane::from_point_normal(
            frame.lift(out * line, base.height),
            frame.normal + frame.direction(out) * (side * slope),
        )
    };
    let (roof, _) = split(&prism, &rising_from(far, 1.0));
    let (roof, _) = split(&roof, &rising_from(near, -1.0));
    (!roof.is_empty()).then_some(roof)
}

/// Turns the hip ends of a skeleton roof into gables: where the face of edge `i` is a triangle
/// whose apex ends a level ridge, the apex slides along the ridge onto edge `i`, so the triangle
/// stands upright over its edge. The ridge is level exactly when the edges before and after `i`
/// run in opposite directions; then it is parallel to them, which gives its direction exactly
/// (short ridges would give it poorly), and both neighbouring faces, which contain it, stay planar.
/// The apex must be shared by those three faces only, with the ridge its one other path. Ends whose
/// ridge would leave the edge stay hips.
fn raise_gables(skeleton: &mut Skeleton, base: &[DVec2]) {
    let n = base.len();
    let direction = |i: usize| (base[(i + 1) % n] - base[i]).normalize();
    let mut uses = vec![0usize; skeleton.nodes.len()];
    for &node in skeleton.faces.iter().flatten() {
        uses[node] += 1;
    }
    for i in 0..n {
        let (before, after) = ((i + n - 1) % n, (i + 1) % n);
        let (prev, face, next) = (
            &skeleton.faces[before],
            &skeleton.faces[i],
            &skeleton.faces[after],
        );
        // The face of edge i is [a, b, apex]; the previous face runs a → apex → ridge, the next
        // one ridge → apex → b.
        let [_, _, apex] = face[..] else {
            continue;
        };
        let ridge_prev = prev.get(3);
        let ridge_next = next.len().checked_sub(2).and_then(|k| next.get(k));
        if uses[apex] != 3
            || prev.get(2) != Some(&apex)
            || next.last() != Some(&apex)
            || ridge_prev.is_none()
            || ridge_prev != ridge_next
        {
            continue;
        }
        let (d_prev, d_next) = (direction(before), direction(after));
        if d_prev.perp_dot(d_next).abs() > 1e-9 || d_prev.dot(d_next) >= 0.0 {
            continue;
        }
        let (a, b) = (base[i], base[after]);
        let out = outward(a, b);
        let toward = d_next.dot(out);
        if toward.abs() < 1e-9 {
            continue;
        }
        let top = skeleton.nodes[apex].p;
        let end = top - d_next * ((top - a).dot(out) / toward);
        let at = (end - a).dot(b - a) / a.distance_squared(b);
        if at > 1e-6 && at < 1.0 - 1e-6 {
            skeleton.nodes[apex].p = end;
        }
    }
}
