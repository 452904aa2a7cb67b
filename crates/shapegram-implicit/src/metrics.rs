//! The verification metrics of Section 4: surface area (eq. 9), volume (eq. 10 and exactly by the
//! divergence theorem), the concavity and convexity factor (eq. 11) and element counts.

use shapegram_geom::{EdgeReport, Mesh};

use crate::mesher::Meshing;

/// Default angle (degrees) below which two neighbouring faces count as flat for eq. (11).
/// Marching cubes places vertices by linear interpolation, which ripples flat and gently curved
/// surfaces by up to about a degree; counting those ripples would score a meshed sphere near
/// 84 % instead of 100 %.
pub const DEFAULT_FLAT_ANGLE: f64 = 3.0;

/// Surface area, eq. (9): the sum over faces of half the length of the cross product of two edge
/// vectors (Newell's method for faces with more than three corners). Summed in face order.
pub fn surface_area(mesh: &Mesh) -> f64 {
    mesh.area()
}

/// Volume enclosed by a closed, outward-oriented mesh (divergence theorem): the sum of the signed
/// volumes of the cones from a reference point to every face.
pub fn mesh_volume(mesh: &Mesh) -> f64 {
    mesh.signed_volume()
}

/// How the edges of a mesh bend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Convexity {
    /// Edges where the surface folds away from its outward normals (as along a cube's edges):
    /// the paper's `T_G`, signed dihedral angle above 0.
    pub convex: usize,
    /// Edges where the surface folds towards its normals (a groove): `T_L`, angle below 0.
    pub concave: usize,
    /// Edges whose faces meet at less than the flat angle; counted in neither.
    pub flat: usize,
}

impl Convexity {
    /// Eq. (11): `100 · T_G / (T_G + T_L)`, so 100 % is convex; 100 when no edge bends.
    pub fn factor(&self) -> f64 {
        let bent = self.convex + self.concave;
        if bent == 0 {
            100.0
        } else {
            100.0 * self.convex as f64 / bent as f64
        }
    }
}

/// Classifies every edge shared by exactly two faces by the signed dihedral angle between them:
/// the angle between their normals, positive when the second face lies behind the first one's
/// plane (a convex fold), negative in front (concave). Edges bending less than `flat_degrees`
/// are flat. Boundary and non-manifold edges are skipped.
pub fn convexity(mesh: &Mesh, flat_degrees: f64) -> Convexity {
    edge_analysis(mesh, flat_degrees).0
}

/// One pass over the edges of a mesh: how they bend and how they pair up (the same counts as
/// [`Mesh::edge_report`], found by sorting instead of hashing, which matters for meshes of
/// millions of triangles).
pub fn edge_analysis(mesh: &Mesh, flat_degrees: f64) -> (Convexity, EdgeReport) {
    // (undirected edge key, face, runs from the lower vertex to the higher one)
    let mut uses: Vec<(u64, u32, bool)> = Vec::with_capacity(mesh.indices_len());
    for (f, face) in mesh.faces().enumerate() {
        for (i, &u) in face.iter().enumerate() {
            let v = face[(i + 1) % face.len()];
            if u != v {
                let key = u64::from(u.min(v)) << 32 | u64::from(u.max(v));
                uses.push((key, f as u32, u < v));
            }
        }
    }
    uses.sort_unstable();
    let normals: Vec<_> = (0..mesh.face_count())
        .map(|f| mesh.face_normal(f))
        .collect();
    let flat_cos = flat_degrees.to_radians().cos();
    let mut bends = Convexity {
        convex: 0,
        concave: 0,
        flat: 0,
    };
    let mut report = EdgeReport::default();
    for group in uses.chunk_by(|x, y| x.0 == y.0) {
        report.edges += 1;
        let forward = group.iter().filter(|u| u.2).count();
        match (forward, group.len() - forward) {
            (1, 1) => {}
            (f, b) if f + b == 1 => {
                report.boundary += 1;
                continue;
            }
            (f, b) if f + b > 2 => {
                report.non_manifold += 1;
                continue;
            }
            _ => {
                report.misoriented += 1;
                continue;
            }
        }
        let (f1, f2) = (group[0].1 as usize, group[1].1 as usize);
        let (n1, n2) = (normals[f1], normals[f2]);
        let corner = mesh.position((group[0].0 >> 32) as u32);
        if n1.dot(n2) >= flat_cos {
            bends.flat += 1;
        } else if (mesh.face_centroid(f2) - corner).dot(n1) < 0.0 {
            bends.convex += 1;
        } else {
            bends.concave += 1;
        }
    }
    (bends, report)
}

/// All metrics of a meshed solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Triangles (faces) of the mesh.
    pub triangles: usize,
    /// Vertices of the mesh.
    pub vertices: usize,
    /// Primitives in the solid's expression tree.
    pub elements: usize,
    /// Surface area, eq. (9).
    pub area: f64,
    /// Volume by voxel count, eq. (10).
    pub voxel_volume: f64,
    /// Volume of the closed mesh by the divergence theorem.
    pub mesh_volume: f64,
    /// Edge bends for eq. (11).
    pub convexity: Convexity,
    /// How the mesh's edges pair up (watertight when all counts but `edges` are zero).
    pub edges: EdgeReport,
}

impl Metrics {
    /// Measures a meshing of a solid made of `elements` primitives.
    pub fn measure(meshing: &Meshing, elements: usize) -> Self {
        let mesh = &meshing.mesh;
        let (convexity, edges) = edge_analysis(mesh, DEFAULT_FLAT_ANGLE);
        Self {
            triangles: mesh.face_count(),
            vertices: mesh.vertex_count(),
            elements,
            area: surface_area(mesh),
            voxel_volume: meshing.voxel_volume(),
            mesh_volume: mesh_volume(mesh),
            convexity,
            edges,
        }
    }
}
