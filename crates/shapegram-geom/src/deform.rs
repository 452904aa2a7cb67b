//! Deformations of a mesh along one axis of its scope: [`taper`], [`twist`] and [`shear`], the
//! "simple taper, twist and shear rules" of the Michelangelo paper (seed 003).
//!
//! The mesh is in scope-local coordinates and `size` is the scope's size. Each deformation moves
//! a point by its relative position along the axis, `t = p[axis] / size[axis]`: 0 at the start of
//! the scope, 1 at its far end (0 everywhere when the scope has no extent along the axis). The
//! *centre line* is the line along the axis through the middle of the scope's cross-section.
//!
//! Vertices move and edges stay straight. A face that the move bends out of its plane becomes
//! triangles: a convex face a fan around its centre (moved too, so it lies on the deformed
//! surface), any other face the triangles it is cut into where it is still flat: every face of the
//! result is planar, and the surface stays closed. Box faces stay whole under a taper (its side
//! faces run along the axis, its ends across it) and under a shear (an affine map keeps every
//! plane). A twist slices the mesh across the axis first, so that no slice turns more than
//! [`TWIST_STEP_DEGREES`] (with at most [`MAX_TWIST_SLICES`] slices), and then triangulates the
//! walls it bent; a taper slices a mesh that has faces slanted against the axis likewise. The
//! three maps keep orientation, and the slices keep their piecewise-straight images from folding,
//! so normals keep pointing outward and a watertight mesh stays watertight.

use crate::{
    DQuat, DVec3, Mesh,
    mesh::newell,
    split::slice_faces,
    triangulate::{Triangulator, is_convex},
};

/// The largest turn, in degrees, of one slice of a [`twist`] (unless that takes more than
/// [`MAX_TWIST_SLICES`] slices).
pub const TWIST_STEP_DEGREES: f64 = 7.5;

/// The most slices a [`twist`] (or a [`taper`]) cuts a mesh into (360° at
/// [`TWIST_STEP_DEGREES`] each).
pub const MAX_TWIST_SLICES: usize = 48;

/// The largest change of scale across one slice of a [`taper`] of a mesh with slanted faces.
pub const TAPER_STEP: f64 = 0.125;

/// How far a corner may lie off its face's plane (relative to the face's size) before the face
/// counts as bent and is triangulated.
const PLANARITY: f64 = 1e-9;

/// A deformed mesh, with the face of the input each of its faces comes from (a face may become
/// several: the slices of a twist, the triangles of a bent face).
#[derive(Clone, Debug, PartialEq)]
pub struct Deformed {
    /// The deformed mesh.
    pub mesh: Mesh,
    /// For face `i` of `mesh`, the input face it is (a piece of).
    pub sources: Vec<u32>,
}

/// Tapers a mesh along `axis` (0, 1, 2 for x, y, z): the cross-section shrinks (or, with a factor
/// above 1, grows) about the centre line, linearly from its full size at `t = 0` to `factor`
/// times it at `t = 1`. Geometry beyond the ends of the scope keeps the scale of the nearer end.
/// A factor of 0 draws the far end into one apex on the centre line (a pyramid over a box, a
/// wedge over a flat face); the faces it collapses are dropped and the faces around it meet there.
///
/// Faces along the axis and across it stay planar (a box keeps its six faces). A mesh with faces
/// slanted against the axis, which the taper bends, is sliced across it first, so that the scale
/// changes by at most [`TAPER_STEP`] a slice (at most [`MAX_TWIST_SLICES`] slices), as a twist is.
///
/// `None` for an axis above 2, a factor that is negative or not finite, or a result that is not.
pub fn taper(mesh: &Mesh, size: DVec3, axis: usize, factor: f64) -> Option<Deformed> {
    if axis > 2 || !(factor >= 0.0 && factor.is_finite()) {
        return None;
    }
    let identity = factor == 1.0 || !has_slanted_faces(mesh, axis);
    let (mesh, sources) = &if identity {
        (mesh.clone(), (0..mesh.face_count() as u32).collect())
    } else {
        let slices = ((factor - 1.0).abs() / TAPER_STEP - 1e-9).ceil();
        sliced(
            mesh,
            size,
            axis,
            (slices.max(1.0) as usize).min(MAX_TWIST_SLICES),
        )
    };
    let centre = size * 0.5;
    let map = |p: DVec3| {
        let t = snapped(relative(p, size, axis)).clamp(0.0, 1.0);
        let scale = 1.0 + (factor - 1.0) * t;
        let mut q = centre + (p - centre) * scale;
        q[axis] = p[axis];
        (q, scale)
    };
    let mut positions = Vec::with_capacity(mesh.vertex_count());
    // Vertices drawn into the apex all become this one (factor 0 only).
    let mut apex: Option<u32> = None;
    let mut remap: Vec<u32> = Vec::with_capacity(mesh.vertex_count());
    for &p in mesh.positions() {
        let (q, scale) = map(p);
        if scale == 0.0 {
            let a = *apex.get_or_insert_with(|| {
                positions.push(q);
                (positions.len() - 1) as u32
            });
            remap.push(a);
        } else {
            positions.push(q);
            remap.push((positions.len() - 1) as u32);
        }
    }
    rebuild(mesh, sources, positions, &remap, &|p| map(p).0)
}

/// Twists a mesh about the centre line of `axis`: the cross-section at `t` turns by
/// `t × degrees`, right-handed about the axis (counter-clockwise seen from its far end). The
/// mesh is first sliced across the axis into as many slices as the scope needs for no slice to
/// turn more than [`TWIST_STEP_DEGREES`] (at most [`MAX_TWIST_SLICES`]); geometry beyond the
/// ends of the scope turns on at the same rate but is not sliced further. Faces that are not
/// convex and do not lie across the axis are also sliced through their reflex corners (when
/// there are at most [`MAX_TWIST_SLICES`] such heights), so that every piece that bends is convex
/// and becomes a fan around its centre.
///
/// The walls run straight between slices, so the volume shrinks a little: by 0.14 % for a
/// twisted box (the cross-sections at the slice planes keep their area exactly).
///
/// `None` for an axis above 2, an angle that is not finite, or a result that is not.
pub fn twist(mesh: &Mesh, size: DVec3, axis: usize, degrees: f64) -> Option<Deformed> {
    if axis > 2 || !degrees.is_finite() {
        return None;
    }
    let mut direction = DVec3::ZERO;
    direction[axis] = 1.0;
    let (sliced, sources) = if degrees == 0.0 {
        (mesh.clone(), (0..mesh.face_count() as u32).collect())
    } else {
        sliced(mesh, size, axis, twist_slices(degrees))
    };
    let centre = size * 0.5;
    let map = |p: DVec3| {
        let t = relative(p, size, axis);
        let turn = DQuat::from_axis_angle(direction, (degrees * t).to_radians());
        let mut q = centre + turn * (p - centre);
        q[axis] = p[axis];
        q
    };
    let positions = sliced.positions().iter().map(|&p| map(p)).collect();
    let remap: Vec<u32> = (0..sliced.vertex_count() as u32).collect();
    rebuild(&sliced, &sources, positions, &remap, &map)
}

/// The mesh cut into `slices` equal slices across `axis` of the scope, and also through the
/// reflex corners of faces that are not convex and not across the axis, so that the pieces of
/// faces that bend are convex; with the input face of each face.
fn sliced(mesh: &Mesh, size: DVec3, axis: usize, slices: usize) -> (Mesh, Vec<u32>) {
    let length = size[axis];
    let mut direction = DVec3::ZERO;
    direction[axis] = 1.0;
    let mut offsets: Vec<f64> = Vec::new();
    if length > 0.0 {
        offsets.extend((1..slices).map(|k| length * k as f64 / slices as f64));
        offsets.extend(reflex_heights(mesh, axis, &offsets));
    }
    slice_faces(mesh, direction, &offsets)
}

/// Whether some face of the mesh is slanted against `axis`: neither along it nor across it.
/// A taper bends such faces (and only those).
fn has_slanted_faces(mesh: &Mesh, axis: usize) -> bool {
    (0..mesh.face_count()).any(|f| {
        let along = mesh.face_normal(f)[axis].abs();
        along > PLANARITY && along < 1.0 - PLANARITY
    })
}

/// The heights along `axis` of the reflex corners of the faces that are not convex and not
/// across the axis, other than those in `planes` (within the mesh's tolerance); none when there
/// are more than [`MAX_TWIST_SLICES`].
fn reflex_heights(mesh: &Mesh, axis: usize, planes: &[f64]) -> Vec<f64> {
    let Some(bounds) = mesh.bounds() else {
        return Vec::new();
    };
    let eps = bounds.tolerance();
    let mut heights = Vec::new();
    let mut points = Vec::new();
    for f in 0..mesh.face_count() {
        let normal = mesh.face_normal(f);
        if normal[axis].abs() >= 1.0 - PLANARITY {
            // Across the axis: it turns as a whole.
            continue;
        }
        points.clear();
        points.extend(mesh.face_points(f));
        if is_convex(&points) {
            continue;
        }
        let n = points.len();
        for i in 0..n {
            let (a, b, c) = (points[(i + n - 1) % n], points[i], points[(i + 1) % n]);
            if (b - a).cross(c - b).dot(normal) < 0.0 {
                heights.push(b[axis]);
            }
        }
    }
    heights.sort_by(f64::total_cmp);
    heights.dedup_by(|a, b| (*a - *b).abs() <= eps);
    heights.retain(|&h| {
        h > bounds.min[axis] + eps
            && h < bounds.max[axis] - eps
            && planes.iter().all(|&p| (p - h).abs() > eps)
    });
    if heights.len() > MAX_TWIST_SLICES {
        heights.clear();
    }
    heights
}

/// How many slices [`twist`] cuts a mesh into for a turn of `degrees`: enough for no slice to
/// turn more than [`TWIST_STEP_DEGREES`], at least 1 and at most [`MAX_TWIST_SLICES`].
pub fn twist_slices(degrees: f64) -> usize {
    let needed = (degrees.abs() / TWIST_STEP_DEGREES - 1e-9).ceil();
    if needed.is_finite() {
        (needed.max(1.0) as usize).min(MAX_TWIST_SLICES)
    } else {
        MAX_TWIST_SLICES
    }
}

/// Shears a mesh: every point moves along `toward` by `amount` times its relative position
/// along `axis`, so the end at `t = 0` stays and the far end moves by `amount`. An affine map
/// with determinant 1: volumes and planar faces are kept.
///
/// `None` for an axis above 2, `toward == axis`, an amount that is not finite, or a result
/// that is not.
pub fn shear(
    mesh: &Mesh,
    size: DVec3,
    axis: usize,
    toward: usize,
    amount: f64,
) -> Option<Deformed> {
    if axis > 2 || toward > 2 || axis == toward || !amount.is_finite() {
        return None;
    }
    let map = |p: DVec3| {
        let mut q = p;
        q[toward] += amount * relative(p, size, axis);
        q
    };
    let positions = mesh.positions().iter().map(|&p| map(p)).collect();
    let remap: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
    let sources: Vec<u32> = (0..mesh.face_count() as u32).collect();
    rebuild(mesh, &sources, positions, &remap, &map)
}

/// The relative position of `p` along `axis` of a scope of size `size` (0 for a scope without
/// extent along it).
fn relative(p: DVec3, size: DVec3, axis: usize) -> f64 {
    if size[axis] > 0.0 {
        p[axis] / size[axis]
    } else {
        0.0
    }
}

/// `t` snapped to exactly 0 or 1 when it is that within rounding (a vertex on the top of a box
/// split from a taller one lies at 0.999…).
fn snapped(t: f64) -> f64 {
    if t.abs() <= PLANARITY {
        0.0
    } else if (t - 1.0).abs() <= PLANARITY {
        1.0
    } else {
        t
    }
}

/// The mesh with its vertices at `positions` (where `map` takes the points of `mesh`), each
/// input vertex `v` now being `remap[v]`: repeated corners are dropped and faces left with fewer
/// than three corners go. A face the move bent out of its plane becomes triangles: a convex one a
/// fan around its centre, moved by `map` (so the centre lies on the deformed surface, and no
/// choice of diagonals bulges the surface in or out); any other, or one pinched by the move (a
/// loop passing a vertex twice: a crenel's merlons drawn into one apex), is triangulated where
/// `mesh` still has it flat and simple, and the triangles the move collapsed go. `sources` gives
/// the origin of `mesh`'s faces. `None` when a position is not finite (a deformation so large
/// that it leaves the range of numbers).
fn rebuild(
    mesh: &Mesh,
    sources: &[u32],
    positions: Vec<DVec3>,
    remap: &[u32],
    map: &dyn Fn(DVec3) -> DVec3,
) -> Option<Deformed> {
    if !positions.iter().all(|p| p.is_finite()) {
        return None;
    }
    let mut out = Mesh::from_faces(positions, std::iter::empty::<[u32; 3]>());
    let mut out_sources = Vec::with_capacity(sources.len());
    let mut triangulator = Triangulator::new();
    let mut corners = Vec::new();
    let mut flat = Vec::new();
    for (f, face) in mesh.faces().enumerate() {
        corners.clear();
        corners.extend(face.iter().map(|&v| remap[v as usize]));
        corners.dedup();
        while corners.len() > 1 && corners.first() == corners.last() {
            corners.pop();
        }
        if corners.len() < 3 {
            continue;
        }
        let pinched = (1..corners.len()).any(|i| corners[..i].contains(&corners[i]));
        if !pinched && is_planar(out.positions(), &corners) {
            out.add_face(&corners);
            out_sources.push(sources[f]);
            continue;
        }
        flat.clear();
        flat.extend(face.iter().map(|&v| mesh.position(v)));
        let n = face.len();
        if corners.len() == n && !pinched && is_convex(&flat) {
            let centre = out.add_vertex(map(flat.iter().sum::<DVec3>() / n as f64));
            for i in 0..n {
                out.add_face(&[corners[i], corners[(i + 1) % n], centre]);
                out_sources.push(sources[f]);
            }
            continue;
        }
        let mut triangles = triangulator.triangulate(&flat, &[]);
        if triangles.is_empty() {
            // A face without area before the move: fan it, there is nothing to cover.
            triangles = (1..n as u32 - 1).map(|i| [0, i, i + 1]).collect();
        }
        for t in triangles {
            let [a, b, c] = t.map(|i| remap[face[i as usize] as usize]);
            if a != b && b != c && c != a {
                out.add_face(&[a, b, c]);
                out_sources.push(sources[f]);
            }
        }
    }
    if !out.positions().iter().all(|p| p.is_finite()) {
        return None;
    }
    Some(Deformed {
        mesh: out,
        sources: out_sources,
    })
}

/// Whether the corners of a loop lie in one plane, within [`PLANARITY`] of the loop's size.
fn is_planar(positions: &[DVec3], loop_: &[u32]) -> bool {
    if loop_.len() == 3 {
        return true;
    }
    let points = loop_.iter().map(|&v| positions[v as usize]);
    let normal = newell(points.clone()).normalize_or_zero();
    let Some(size) = crate::Aabb::from_points(points.clone()).map(|b| b.diagonal()) else {
        return true;
    };
    if normal == DVec3::ZERO {
        // No area, so no plane to leave.
        return true;
    }
    let origin = positions[loop_[0] as usize];
    points
        .into_iter()
        .all(|p| (p - origin).dot(normal).abs() <= PLANARITY * size)
}
