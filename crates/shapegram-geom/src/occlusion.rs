//! Occlusion tests: whether a probe shape lies inside a closed solid, overlaps its interior or
//! touches it, decided exactly for solids cut into convex pieces.
//!
//! Definitions, with `eps` the caller's tolerance:
//! - **inside**: every point of the probe lies in the solid or within `eps` of it;
//! - **overlaps**: the probe and the interior of the solid share a region of positive area (a face
//!   of the probe crossing the interior, or a face of a solid probe taking in part of the solid)
//!   or one solid holds the other;
//! - **touches**: overlaps, or a region of positive area of the probe's surface lies on the solid's
//!   surface (within `eps`). Meeting along an edge or at a corner is not touching.
//!
//! "Positive area" means more than `4 · eps` times the perimeter of the face concerned, so slivers
//! that only exist because of the tolerance never count.

use crate::{Aabb, DVec3, Mesh, Scope, mesh::newell, primitives, split::split, triangulate};

/// A convex solid: its faces (convex polygons) with their outward planes, and its bounds.
#[derive(Clone, Debug)]
pub struct ConvexSolid {
    /// Outward unit normals and offsets of the face planes (`normal · p = offset`).
    planes: Vec<(DVec3, f64)>,
    faces: Vec<Face>,
    centre: DVec3,
    bounds: Aabb,
}

impl ConvexSolid {
    /// The box of a scope, or `None` when the box has no volume.
    pub fn from_scope(scope: &Scope) -> Option<Self> {
        if !scope.size.cmpgt(DVec3::ZERO).all() || !scope.size.is_finite() {
            return None;
        }
        let mut mesh = primitives::cuboid(scope.size);
        mesh.transform(&scope.local_to_world());
        Self::from_convex_mesh(&mesh)
    }

    /// A convex closed mesh as a solid (faces may wind either way), or `None` without volume.
    fn from_convex_mesh(mesh: &Mesh) -> Option<Self> {
        let bounds = mesh.bounds()?;
        let faces: Vec<Face> = (0..mesh.face_count())
            .filter_map(|f| Face::new(mesh.face_points(f).collect()))
            .collect();
        let count = faces.iter().map(|f| f.points.len()).sum::<usize>().max(1);
        let centre = faces.iter().flat_map(|f| &f.points).sum::<DVec3>() / count as f64;
        let planes: Vec<(DVec3, f64)> = faces
            .iter()
            .map(|f| {
                let corner = f.points[0];
                let mut normal = newell(f.points.iter().copied()).normalize();
                if normal.dot(corner - centre) < 0.0 {
                    normal = -normal;
                }
                (normal, normal.dot(corner))
            })
            .collect();
        let solid = planes.len() >= 4 && bounds.size().cmpgt(DVec3::ZERO).all();
        solid.then_some(Self {
            planes,
            faces,
            centre,
            bounds,
        })
    }

    /// The axis-aligned bounds.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The enclosed volume (pyramids from the centre over every face).
    pub fn volume(&self) -> f64 {
        self.faces
            .iter()
            .zip(&self.planes)
            .map(|(f, &(n, d))| f.area * (d - n.dot(self.centre)) / 3.0)
            .sum()
    }

    /// Whether `p` lies in the solid or within `eps` of it.
    pub fn contains(&self, p: DVec3, eps: f64) -> bool {
        self.planes.iter().all(|&(n, d)| n.dot(p) - d <= eps)
    }

    /// Area of the part of a convex polygon inside the solid grown by `grow` (shrunk when
    /// negative). `a` and `b` are scratch buffers.
    fn clipped_area(
        &self,
        polygon: &[DVec3],
        grow: f64,
        a: &mut Vec<DVec3>,
        b: &mut Vec<DVec3>,
    ) -> f64 {
        a.clear();
        a.extend_from_slice(polygon);
        for &(n, d) in &self.planes {
            b.clear();
            for (i, &p) in a.iter().enumerate() {
                let q = a[(i + 1) % a.len()];
                let (dp, dq) = (n.dot(p) - d - grow, n.dot(q) - d - grow);
                if dp <= 0.0 {
                    b.push(p);
                }
                if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
                    b.push(p + (q - p) * (dp / (dp - dq)));
                }
            }
            std::mem::swap(a, b);
            if a.len() < 3 {
                return 0.0;
            }
        }
        newell(a.iter().copied()).length() * 0.5
    }
}

/// Cuts a closed mesh into convex pieces along its own face planes (an extruded L becomes two
/// boxes). `None` when the mesh is not closed or needs more than `max_pieces` pieces.
pub fn convex_pieces(mesh: &Mesh, max_pieces: usize) -> Option<Vec<ConvexSolid>> {
    if mesh.face_count() < 4 || !mesh.is_watertight() {
        return None;
    }
    let mut work = vec![mesh.clone()];
    let mut pieces = Vec::new();
    while let Some(part) = work.pop() {
        let tolerance = part.bounds()?.tolerance() * 16.0;
        match splitting_plane(&part, tolerance) {
            None => pieces.extend(ConvexSolid::from_convex_mesh(&part)),
            Some(plane) => {
                let (below, above) = split(&part, &plane);
                work.extend(
                    [below, above]
                        .into_iter()
                        .filter(|m| m.signed_volume().abs() > tolerance.powi(3)),
                );
            }
        }
        if pieces.len() + work.len() > max_pieces {
            return None;
        }
    }
    Some(pieces)
}

/// The plane of the first face that has corners of the mesh on both sides, if any: a mesh
/// without one is convex.
fn splitting_plane(mesh: &Mesh, tolerance: f64) -> Option<crate::Plane> {
    (0..mesh.face_count()).find_map(|f| {
        let normal = mesh.face_normal(f);
        if normal == DVec3::ZERO {
            return None;
        }
        let plane = crate::Plane::from_point_normal(mesh.face_centroid(f), normal);
        let (mut below, mut above) = (false, false);
        for &p in mesh.positions() {
            let d = plane.signed_distance(p);
            below |= d < -tolerance;
            above |= d > tolerance;
        }
        (below && above).then_some(plane)
    })
}

/// The geometry of a shape that asks about occlusion, in world coordinates: its faces as convex
/// polygons and, when it is a closed solid, its convex pieces.
#[derive(Clone, Debug)]
pub struct Probe {
    faces: Vec<Face>,
    pieces: Vec<ConvexSolid>,
    bounds: Aabb,
}

#[derive(Clone, Debug)]
struct Face {
    points: Vec<DVec3>,
    area: f64,
    perimeter: f64,
    bounds: Aabb,
}

impl Face {
    fn new(points: Vec<DVec3>) -> Option<Self> {
        let area = newell(points.iter().copied()).length() * 0.5;
        let perimeter = (0..points.len())
            .map(|i| points[i].distance(points[(i + 1) % points.len()]))
            .sum();
        let bounds = Aabb::from_points(points.iter().copied())?;
        (area > 0.0).then_some(Self {
            points,
            area,
            perimeter,
            bounds,
        })
    }
}

impl Probe {
    /// The box of a scope: a solid box, or a rectangle when one size is zero. `None` for a box
    /// flat in more than one axis (a line or a point).
    pub fn from_scope(scope: &Scope) -> Option<Self> {
        let flat = (0..3).filter(|&i| scope.size[i] == 0.0).count();
        match flat {
            0 => {
                let solid = ConvexSolid::from_scope(scope)?;
                let faces = solid.faces.clone();
                Some(Self {
                    bounds: solid.bounds,
                    faces,
                    pieces: vec![solid],
                })
            }
            1 => {
                let (u, v) = match scope.size.to_array().iter().position(|&s| s == 0.0) {
                    Some(0) => (1, 2),
                    Some(1) => (0, 2),
                    _ => (0, 1),
                };
                let corner = |a: f64, b: f64| {
                    let mut local = DVec3::ZERO;
                    local[u] = a * scope.size[u];
                    local[v] = b * scope.size[v];
                    scope.to_world(local)
                };
                let quad = vec![
                    corner(0.0, 0.0),
                    corner(1.0, 0.0),
                    corner(1.0, 1.0),
                    corner(0.0, 1.0),
                ];
                let face = Face::new(quad)?;
                Some(Self {
                    bounds: face.bounds,
                    faces: vec![face],
                    pieces: Vec::new(),
                })
            }
            _ => None,
        }
    }

    /// A mesh in world coordinates: non-convex faces are triangulated; a closed mesh is also
    /// cut into at most `max_pieces` convex pieces (beyond that it counts as a surface only).
    pub fn from_mesh(mesh: &Mesh, max_pieces: usize) -> Option<Self> {
        let mut faces = Vec::new();
        for f in 0..mesh.face_count() {
            let points: Vec<DVec3> = mesh.face_points(f).collect();
            if triangulate::is_convex(&points) {
                faces.extend(Face::new(points));
            } else {
                let loop_mesh = Mesh::from_polygon(&points);
                for [a, b, c] in loop_mesh.triangulate() {
                    let corner = |i: u32| loop_mesh.position(i);
                    faces.extend(Face::new(vec![corner(a), corner(b), corner(c)]));
                }
            }
        }
        let bounds = faces.iter().map(|f| f.bounds).reduce(Aabb::union)?;
        let pieces = convex_pieces(mesh, max_pieces).unwrap_or_default();
        Some(Self {
            faces,
            pieces,
            bounds,
        })
    }

    /// The axis-aligned bounds.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
}

/// How a probe meets a solid: see the module documentation for the definitions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Contact {
    /// The probe lies in the solid (or on its surface).
    pub inside: bool,
    /// The probe and the solid's interior share a region of positive area or volume.
    pub overlaps: bool,
    /// The probe overlaps the solid or lies on its surface over a region of positive area.
    pub touches: bool,
}

/// How `probe` meets the solid made of `pieces` (convex pieces with disjoint interiors).
pub fn contact(probe: &Probe, pieces: &[ConvexSolid], eps: f64) -> Contact {
    let mut result = Contact::default();
    let near: Vec<&ConvexSolid> = pieces
        .iter()
        .filter(|p| meets(&p.bounds, &probe.bounds, eps))
        .collect();
    if near.is_empty() || probe.faces.is_empty() {
        return result;
    }
    let (mut a, mut b) = (Vec::with_capacity(16), Vec::with_capacity(16));
    result.inside = match near.as_slice() {
        [one] => probe
            .faces
            .iter()
            .all(|f| f.points.iter().all(|&p| one.contains(p, eps))),
        _ => probe.faces.iter().all(|f| {
            let covered: f64 = near
                .iter()
                .map(|piece| piece.clipped_area(&f.points, eps, &mut a, &mut b))
                .sum();
            covered >= f.area - threshold(f.perimeter, eps)
        }),
    };
    for f in &probe.faces {
        let least = threshold(f.perimeter, eps);
        for piece in near.iter().filter(|p| meets(&p.bounds, &f.bounds, eps)) {
            if !result.overlaps && piece.clipped_area(&f.points, -eps, &mut a, &mut b) > least {
                result.overlaps = true;
            }
            if !result.touches && piece.clipped_area(&f.points, eps, &mut a, &mut b) > least {
                result.touches = true;
            }
            if result.overlaps && result.touches {
                return result;
            }
        }
    }
    if !result.overlaps && solids_overlap(&probe.pieces, &near, eps, &mut a, &mut b) {
        result.overlaps = true;
        result.touches = true;
    }
    result
}

/// Whether the solid of a probe holds part of the interior of the occluder: a face of one
/// crosses the interior of the other, or one's centre lies strictly inside the other (equal
/// solids have no face crossing an interior).
fn solids_overlap(
    probe: &[ConvexSolid],
    occluder: &[&ConvexSolid],
    eps: f64,
    a: &mut Vec<DVec3>,
    b: &mut Vec<DVec3>,
) -> bool {
    probe.iter().any(|q| {
        occluder.iter().any(|c| {
            meets(&q.bounds, &c.bounds, -eps)
                && (q.contains(c.centre, -eps)
                    || c.contains(q.centre, -eps)
                    || c.faces.iter().any(|f| {
                        q.clipped_area(&f.points, -eps, a, b) > threshold(f.perimeter, eps)
                    }))
        })
    })
}

/// The least area that counts as a region rather than a sliver of the tolerance.
fn threshold(perimeter: f64, eps: f64) -> f64 {
    4.0 * eps * perimeter
}

/// Whether two boxes come within `eps` of each other (overlap by more than `-eps` when negative).
fn meets(a: &Aabb, b: &Aabb, eps: f64) -> bool {
    (a.min - eps).cmple(b.max).all() && (b.min - eps).cmple(a.max).all()
}
