//! Boolean 3D operations on polygon meshes: exact for closed meshes (through `manifold-rust`,
//! a port of Manifold), and for open meshes (planes, meshes with holes) against closed ones by
//! clipping each face to the inside or outside of the closed mesh.
//!
//! Results are triangle meshes: the crate works on triangles and gives triangles back.

use manifold_rust::cross_section::CrossSection;
use manifold_rust::linalg::Vec2;
use manifold_rust::manifold::Manifold;
use manifold_rust::polygon::triangulate;
use manifold_rust::types::{Error as ManifoldStatus, MeshGLP, OpType};
use shapegram_geom::{DVec3, Mesh, mesh::newell};

/// Vertices closer than this (metres) are one vertex when a mesh is checked for being closed:
/// parts derived side by side meet at seams computed through different transforms.
pub(crate) const WELD: f64 = 1e-6;

/// A triangle mesh as the crate takes it: f64 positions, u32 indices.
type Gl = MeshGLP<f64, u32>;

/// Which Boolean operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BooleanOp {
    /// Everything in either operand.
    Union,
    /// The first operand without the second.
    Subtract,
    /// What both operands share.
    Intersect,
}

/// An operand made of meshes: the volume its closed meshes enclose (unioned) and the faces of
/// its open meshes, which have no inside.
pub struct Operand {
    solid: Option<Manifold>,
    open: Mesh,
    /// The IDs the crate knows the solid's meshes by, to tell its faces in a result.
    ids: Vec<u32>,
}

/// The result of [`combine`]: a mesh, and for each face whether it came from operand B.
pub struct Combined {
    /// The result's surface.
    pub mesh: Mesh,
    /// By face: whether it lies on operand B's surface (else on A's).
    pub from_b: Vec<bool>,
}

impl Operand {
    /// The operand of several meshes (the leaves of a derivation), in order. Each closed mesh
    /// is a solid and all solids are unioned; the open meshes together may close (the faces of
    /// a component split), else they stay open, and the faces that fall inside the solid go.
    pub fn new(parts: &[Mesh]) -> Self {
        let mut solids = Vec::new();
        let mut ids = Vec::new();
        let mut open = Mesh::new();
        for part in parts {
            match closed(part) {
                Some((solid, id)) => {
                    solids.push(solid);
                    ids.push(id);
                }
                None => open.append(part),
            }
        }
        if !open.is_empty()
            && let Some((solid, id)) = closed(&open)
        {
            solids.push(solid);
            ids.push(id);
            open = Mesh::new();
        }
        let solid = match solids.len() {
            0 => None,
            1 => solids.pop(),
            _ => Some(Manifold::batch_boolean(&solids, OpType::Add)),
        };
        let open = match &solid {
            Some(solid) if !open.is_empty() => clip(&open, solid, false),
            _ => open,
        };
        Self { solid, open, ids }
    }

    /// The operand as one mesh: the solid's surface, then the open faces (in one plane,
    /// their 2-D union).
    pub fn into_mesh(self) -> Mesh {
        let mut mesh = Mesh::new();
        if self.solid.is_none()
            && let Some(plane) = Flat::of(&self.open, &self.open)
        {
            plane.append(&mut mesh, &plane.section(&self.open));
            return mesh;
        }
        if let Some(solid) = &self.solid {
            append_triangles(&mut mesh, &solid.get_mesh_glp(-1), |_, _| Some(false));
        }
        mesh.append(&self.open);
        mesh
    }
}

/// `a op b`. Solids combine exactly; open faces are kept where they lie outside the other
/// operand's solid (union, and subtract for the first operand's faces) or inside it
/// (intersect). An open second operand subtracts nothing: it has no volume.
pub fn combine(op: BooleanOp, a: &Operand, b: &Operand) -> Combined {
    if a.solid.is_none()
        && b.solid.is_none()
        && let Some(plane) = Flat::of(&a.open, &b.open)
    {
        return plane.combine(op, &a.open, &b.open);
    }
    let solid = match (op, &a.solid, &b.solid) {
        (BooleanOp::Union, Some(x), Some(y)) => Some(x.union(y)),
        (BooleanOp::Union, Some(x), None) | (BooleanOp::Union, None, Some(x)) => Some(x.clone()),
        (BooleanOp::Subtract, Some(x), Some(y)) => Some(x.difference(y)),
        (BooleanOp::Subtract, Some(x), None) => Some(x.clone()),
        (BooleanOp::Intersect, Some(x), Some(y)) => Some(x.intersection(y)),
        _ => None,
    };
    let mut mesh = Mesh::new();
    let mut from_b = Vec::new();
    if let Some(solid) = &solid {
        let gl: Gl = solid.get_mesh_glp(-1);
        let mut flags = |run_id: Option<u32>, _| Some(run_id.is_some_and(|id| b.ids.contains(&id)));
        from_b = append_triangles(&mut mesh, &gl, &mut flags);
    }
    let mut faces = |open: &Mesh, other: &Option<Manifold>, inside: bool, is_b: bool| {
        let kept = match other {
            Some(solid) if !open.is_empty() => clip(open, solid, inside),
            None if !inside => open.clone(),
            _ => return,
        };
        mesh.append(&kept);
        from_b.resize(mesh.face_count(), is_b);
    };
    match op {
        BooleanOp::Union => {
            faces(&a.open, &b.solid, false, false);
            faces(&b.open, &a.solid, false, true);
        }
        BooleanOp::Subtract => faces(&a.open, &b.solid, false, false),
        BooleanOp::Intersect => {
            faces(&a.open, &b.solid, true, false);
            faces(&b.open, &a.solid, true, true);
        }
    }
    Combined { mesh, from_b }
}

/// Points farther than this (metres) from the plane of two flat operands make them not
/// coplanar.
const COPLANAR: f64 = 1e-7;

/// The plane two flat operands share, with axes in it, for their 2-D Boolean (through the
/// crate's cross-sections, which are Clipper2's polygons).
struct Flat {
    origin: DVec3,
    normal: DVec3,
    u: DVec3,
    v: DVec3,
}

impl Flat {
    /// The plane of `a`'s first face when both meshes lie in it.
    fn of(a: &Mesh, b: &Mesh) -> Option<Self> {
        let first = (0..a.face_count()).find(|&f| a.face_area(f) > 0.0)?;
        let normal = a.face_normal(first).try_normalize()?;
        let origin = a.face_points(first).next()?;
        let near = |p: &DVec3| (*p - origin).dot(normal).abs() <= COPLANAR;
        let flat = a.positions().iter().all(near) && b.positions().iter().all(near);
        (flat && !b.is_empty()).then(|| {
            let (u, _) = shapegram_geom::triangulate::plane_basis(normal);
            Self {
                origin,
                normal,
                u,
                v: normal.cross(u),
            }
        })
    }

    /// The union of the mesh's faces in the plane's coordinates, each wound counter-clockwise.
    fn section(&self, mesh: &Mesh) -> CrossSection {
        let polygons = (0..mesh.face_count())
            .map(|f| {
                let mut points: Vec<Vec2> = mesh
                    .face_points(f)
                    .map(|p| {
                        Vec2::new((p - self.origin).dot(self.u), (p - self.origin).dot(self.v))
                    })
                    .collect();
                if mesh.face_normal(f).dot(self.normal) < 0.0 {
                    points.reverse();
                }
                points
            })
            .collect();
        CrossSection::new(polygons)
    }

    /// `a op b` in the plane: the target's region first, and for a union the part of B
    /// outside it (overlaps are the target's, as CityEngine gives them its material).
    fn combine(&self, op: BooleanOp, a: &Mesh, b: &Mesh) -> Combined {
        let (a, b) = (self.section(a), self.section(b));
        let parts = match op {
            BooleanOp::Union => {
                let rest = b.difference(&a);
                vec![(a, false), (rest, true)]
            }
            BooleanOp::Subtract => vec![(a.difference(&b), false)],
            BooleanOp::Intersect => vec![(a.intersection(&b), false)],
        };
        let mut mesh = Mesh::new();
        let mut from_b = Vec::new();
        for (section, is_b) in parts {
            self.append(&mut mesh, &section);
            from_b.resize(mesh.face_count(), is_b);
        }
        Combined { mesh, from_b }
    }

    /// Appends a cross-section's triangles, lifted back into the plane.
    fn append(&self, mesh: &mut Mesh, section: &CrossSection) {
        let polygons = section.to_polygons();
        let base = mesh.vertex_count() as u32;
        for p in polygons.iter().flatten() {
            mesh.add_vertex(self.origin + self.u * p.x + self.v * p.y);
        }
        for t in triangulate(&polygons, -1.0, true) {
            let corners = [t.x, t.y, t.z].map(|i| base + i as u32);
            mesh.add_face(&corners);
        }
    }
}

/// The solid a mesh encloses, when it is closed and manifold, and the ID its faces keep
/// through Booleans.
fn closed(mesh: &Mesh) -> Option<(Manifold, u32)> {
    if mesh.is_empty() {
        return None;
    }
    let mut gl = to_gl(&mesh.welded(WELD));
    let id = own_id(&mut gl);
    let solid = Manifold::from_mesh_glp(&gl);
    (solid.status() == ManifoldStatus::NoError && !solid.is_empty()).then_some((solid, id))
}

/// Gives the mesh an ID of its own, which the crate keeps on the faces of results.
fn own_id(gl: &mut Gl) -> u32 {
    let id = Manifold::reserve_ids(1);
    gl.run_original_id = vec![id];
    gl.run_index = vec![0, gl.tri_verts.len() as u32];
    id
}

/// The parts of `open`'s faces inside (or outside) `solid`. Each face becomes a thin prism
/// behind it, which the crate intersects with (or subtracts from) the solid; what is left of
/// the prism's cap, the face itself, is the answer. A face whose prism is not a valid solid
/// (a self-intersecting polygon) is kept whole when outside is asked for.
fn clip(open: &Mesh, solid: &Manifold, inside: bool) -> Mesh {
    let mut out = Mesh::new();
    for face in 0..open.face_count() {
        let points: Vec<DVec3> = open.face_points(face).collect();
        let Some((mut prism, cap)) = prism(&points) else {
            continue;
        };
        let id = own_id(&mut prism);
        let prism = Manifold::from_mesh_glp(&prism);
        if prism.status() != ManifoldStatus::NoError || prism.is_empty() {
            if !inside {
                out.append(&Mesh::from_polygon(&points));
            }
            continue;
        }
        let kept = match inside {
            true => prism.intersection(solid),
            false => prism.difference(solid),
        };
        let gl: Gl = kept.get_mesh_glp(-1);
        append_triangles(&mut out, &gl, |run_id, face_id| {
            (run_id == Some(id) && face_id == Some(cap)).then_some(false)
        });
    }
    out
}

/// The face ID of a prism's cap (its other faces are 0).
const CAP: u32 = 1;

/// A prism with the polygon as its cap, reaching back against the polygon's normal by a
/// hundredth of the polygon's size; `None` for a degenerate polygon.
fn prism(points: &[DVec3]) -> Option<(Gl, u32)> {
    let normal = newell(points.iter().copied()).try_normalize()?;
    let n = points.len();
    let size = points
        .iter()
        .map(|p| p.distance(points[0]))
        .fold(0.0, f64::max);
    let back = normal * (size * 0.01);
    let mut positions = Vec::with_capacity(6 * n);
    for p in points.iter().chain(points) {
        positions.push(*p);
    }
    for p in positions.iter_mut().skip(n) {
        *p -= back;
    }
    let cap = Mesh::from_polygon(points).triangulate();
    let mut triangles = Vec::new();
    let mut faces = Vec::new();
    let n32 = n as u32;
    for t in &cap {
        triangles.push(*t);
        faces.push(CAP);
        triangles.push([t[2] + n32, t[1] + n32, t[0] + n32]);
        faces.push(0);
    }
    for i in 0..n32 {
        let j = (i + 1) % n32;
        triangles.push([i, i + n32, j + n32]);
        triangles.push([i, j + n32, j]);
        faces.extend([0, 0]);
    }
    let mut gl = gl_of(&positions, &triangles);
    gl.face_id = faces;
    Some((gl, CAP))
}

/// A mesh as the crate takes it: its faces triangulated.
fn to_gl(mesh: &Mesh) -> Gl {
    gl_of(mesh.positions(), &mesh.triangulate())
}

fn gl_of(positions: &[DVec3], triangles: &[[u32; 3]]) -> Gl {
    Gl {
        num_prop: 3,
        vert_properties: positions.iter().flat_map(|p| p.to_array()).collect(),
        tri_verts: triangles.iter().flatten().copied().collect(),
        ..Gl::default()
    }
}

/// Appends the triangles of `gl` that `keep` accepts, given the original ID of their run and
/// their face ID, with the vertices they use; returns the flag `keep` gave each, in order.
fn append_triangles(
    mesh: &mut Mesh,
    gl: &Gl,
    mut keep: impl FnMut(Option<u32>, Option<u32>) -> Option<bool>,
) -> Vec<bool> {
    let stride = gl.num_prop as usize;
    let mut added = vec![u32::MAX; gl.vert_properties.len() / stride];
    let mut flags = Vec::new();
    for (t, corners) in gl.tri_verts.chunks_exact(3).enumerate() {
        let run = gl
            .run_index
            .iter()
            .rposition(|&start| start as usize <= 3 * t);
        let run_id = run.and_then(|r| gl.run_original_id.get(r).copied());
        let Some(flag) = keep(run_id, gl.face_id.get(t).copied()) else {
            continue;
        };
        let face: Vec<u32> = corners
            .iter()
            .map(|&v| {
                let v = v as usize;
                if added[v] == u32::MAX {
                    let p = &gl.vert_properties[v * stride..v * stride + 3];
                    added[v] = mesh.add_vertex(DVec3::new(p[0], p[1], p[2]));
                }
                added[v]
            })
            .collect();
        if mesh.add_face(&face).is_some() {
            flags.push(flag);
        }
    }
    flags
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_geom::DAffine3;
    use shapegram_geom::primitives::{cuboid, cylinder};

    fn cube(size: DVec3, at: DVec3) -> Mesh {
        cuboid(size).transformed(&DAffine3::from_translation(at))
    }

    fn unit_quad() -> Mesh {
        Mesh::from_polygon(&[
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, -2.0),
            DVec3::new(0.0, 0.0, -2.0),
        ])
    }

    #[test]
    fn a_bar_through_a_box_leaves_volume_six() {
        let a = Operand::new(&[cube(DVec3::splat(2.0), DVec3::ZERO)]);
        let b = Operand::new(&[cube(DVec3::new(1.0, 1.0, 3.0), DVec3::new(0.5, 0.5, -0.5))]);
        let result = combine(BooleanOp::Subtract, &a, &b);
        let mesh = result.mesh;
        assert!((mesh.signed_volume() - 6.0).abs() < 1e-9);
        // The tunnel's walls are the bar's faces: 4 walls of 2 triangles.
        assert_eq!(result.from_b.iter().filter(|&&b| b).count(), 8);
        assert!(closed(&mesh).is_some());
    }

    #[test]
    fn a_plane_minus_a_box_has_a_hole() {
        let a = Operand::new(&[unit_quad()]);
        assert!(a.solid.is_none());
        let b = Operand::new(&[cube(DVec3::ONE, DVec3::new(0.5, -0.5, -1.5))]);
        let punched = combine(BooleanOp::Subtract, &a, &b).mesh;
        assert!((punched.area() - 3.0).abs() < 1e-9, "{}", punched.area());
        let clipped = combine(BooleanOp::Intersect, &a, &b).mesh;
        assert!((clipped.area() - 1.0).abs() < 1e-9, "{}", clipped.area());
    }

    #[test]
    fn the_faces_of_a_box_together_are_a_solid() {
        let faces: Vec<Mesh> = {
            let cube = cuboid(DVec3::ONE);
            (0..cube.face_count())
                .map(|f| Mesh::from_polygon(&cube.face_points(f).collect::<Vec<_>>()))
                .collect()
        };
        assert!(Operand::new(&faces).solid.is_some());
        let cylinder = cylinder(DVec3::ONE, 16);
        let both = Operand::new(&[cuboid(DVec3::ONE), cylinder]);
        assert!(both.solid.is_some());
    }
}
