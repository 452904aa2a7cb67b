//! Component extraction (faces, edges, vertices) with local frames, and face classification.
//!
//! # Frames
//! - A **face** gets x along its first edge, z along its normal and y = z × x (so y points into the
//!   face from its first edge); its scope is the tightest box in that frame, with zero depth. For a
//!   wall quad whose first edge runs along the ground, y is up the wall.
//! - An **edge** gets x along the edge, in the direction of the first face that uses it, z along
//!   the mean normal of the faces that use it (made orthogonal to x), and y = z × x; its scope is
//!   `(length, 0, 0)`.
//! - A **face edge** (one per edge of every face, shared edges once per face) gets x along the
//!   edge in the face's winding, z pointing out of the face, perpendicular to the edge and the
//!   face's normal, and y = z × x, the face's normal; its scope is `(length, 0, 0)` with the
//!   origin at the edge's first corner.
//! - A **vertex** gets z along the mean normal of the faces around it, x along the world x axis
//!   projected off z (or world z when z is vertical), y = z × x; its scope has zero size.
//!
//! # Face classes
//! [`FaceClass::of`] names a face by the axis of the reference scope its normal is closest to:
//! +y top, −y bottom, +z front, −z back, +x right, −x left, as CGA's `comp(f)` selectors do. On an
//! exact tie between axes, y wins over z, and z over x, so the 45° faces of a hip roof are top
//! faces, and the corner facets of a box chamfered at 45° face front or back.

use crate::{DMat3, DVec3, Mesh, Scope};

/// Which kind of component a [`Component`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ComponentKind {
    /// A face (polygon).
    Face,
    /// An edge (segment).
    Edge,
    /// An edge of one face, directed along the face's winding.
    FaceEdge,
    /// A corner of one face.
    FaceVertex,
    /// A vertex (point).
    Vertex,
}

/// The side of a scope a face looks towards.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FaceClass {
    /// Normal closest to the scope's +z axis.
    Front,
    /// Normal closest to −z.
    Back,
    /// Normal closest to −x.
    Left,
    /// Normal closest to +x.
    Right,
    /// Normal closest to +y.
    Top,
    /// Normal closest to −y.
    Bottom,
}

impl FaceClass {
    /// Classifies a world-space normal relative to a scope's axes (see the module docs).
    pub fn of(normal: DVec3, reference: &Scope) -> Self {
        let n = reference.direction_to_local(normal);
        let a = n.abs();
        if a.y >= a.z && a.y >= a.x {
            if n.y >= 0.0 { Self::Top } else { Self::Bottom }
        } else if a.z >= a.x {
            if n.z >= 0.0 { Self::Front } else { Self::Back }
        } else if n.x >= 0.0 {
            Self::Right
        } else {
            Self::Left
        }
    }

    /// Whether this is one of the four side classes (CGA's `side` selector).
    pub fn is_side(self) -> bool {
        !matches!(self, Self::Top | Self::Bottom)
    }

    /// The CGA selector name: `front`, `back`, `left`, `right`, `top` or `bottom`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Front => "front",
            Self::Back => "back",
            Self::Left => "left",
            Self::Right => "right",
            Self::Top => "top",
            Self::Bottom => "bottom",
        }
    }
}

/// One component of a mesh with its own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Face, edge or vertex.
    pub kind: ComponentKind,
    /// Index among the components of this kind, in mesh order.
    pub index: usize,
    /// What it came from: the face index for faces and face edges, the vertex index for
    /// vertices, the position in [`Mesh::edges`] for edges.
    pub source: usize,
    /// The component's scope: its local frame, fitted around its points.
    pub scope: Scope,
    /// The component's points in world coordinates: the face loop, the edge's two ends, or the
    /// vertex.
    pub points: Vec<DVec3>,
    /// The outward normal (mean of the adjacent faces for edges and vertices; zero if none); for
    /// a face edge, the direction out of its face in the face's plane.
    pub normal: DVec3,
}

/// The faces of a mesh as components, skipping faces without area.
pub fn faces(mesh: &Mesh) -> Vec<Component> {
    (0..mesh.face_count())
        .filter_map(|f| {
            let points: Vec<DVec3> = mesh.face_points(f).collect();
            let normal = mesh.face_normal(f);
            let first_edge = points
                .iter()
                .zip(points.iter().cycle().skip(1))
                .find_map(|(a, b)| (*b - *a).reject_from(normal).try_normalize())?;
            Some((f, points, normal, first_edge))
        })
        .enumerate()
        .map(|(index, (source, points, normal, x))| Component {
            kind: ComponentKind::Face,
            index,
            source,
            scope: Scope::fit(frame(x, normal), points.iter().copied()),
            points,
            normal,
        })
        .collect()
}

/// The edges of a mesh as components, in order of first use.
pub fn edges(mesh: &Mesh) -> Vec<Component> {
    mesh.edges()
        .into_iter()
        .enumerate()
        .filter_map(|(source, e)| {
            let (from, to) = if e.forward.is_empty() {
                (e.b, e.a)
            } else {
                (e.a, e.b)
            };
            let points = vec![mesh.position(from), mesh.position(to)];
            let x = (points[1] - points[0]).try_normalize()?;
            let normal = mean_normal(mesh, e.forward.iter().chain(&e.backward).copied());
            let z = normal
                .reject_from(x)
                .try_normalize()
                .unwrap_or_else(|| x.any_orthonormal_vector());
            Some((source, points, normal, frame(x, z)))
        })
        .enumerate()
        .map(|(index, (source, points, normal, axes))| Component {
            kind: ComponentKind::Edge,
            index,
            source,
            scope: Scope::fit(axes, points.iter().copied()),
            points,
            normal,
        })
        .collect()
}

/// The edges of every face of a mesh as components, face after face, each edge of a face in
/// order from its first corner; edges without length are skipped.
pub fn face_edges(mesh: &Mesh) -> Vec<Component> {
    let mut out = Vec::new();
    for f in 0..mesh.face_count() {
        let normal = mesh.face_normal(f);
        let points: Vec<DVec3> = mesh.face_points(f).collect();
        for (i, &a) in points.iter().enumerate() {
            let b = points[(i + 1) % points.len()];
            let Some(x) = (b - a).try_normalize() else {
                continue;
            };
            let z = x
                .cross(normal)
                .try_normalize()
                .unwrap_or_else(|| x.any_orthonormal_vector());
            out.push(Component {
                kind: ComponentKind::FaceEdge,
                index: out.len(),
                source: f,
                scope: Scope::new(a, frame(x, z), DVec3::new(a.distance(b), 0.0, 0.0)),
                points: vec![a, b],
                normal: z,
            });
        }
    }
    out
}

/// The corners of every face of a mesh as components, face after face, each face's from its
/// first; corners whose outgoing edge has no length are skipped.
pub fn face_vertices(mesh: &Mesh) -> Vec<Component> {
    face_edges(mesh)
        .into_iter()
        .enumerate()
        .map(|(index, edge)| Component {
            kind: ComponentKind::FaceVertex,
            index,
            source: edge.source,
            scope: Scope::new(edge.points[0], edge.scope.axes, DVec3::ZERO),
            points: vec![edge.points[0]],
            normal: edge.normal,
        })
        .collect()
}

/// The vertices used by faces of a mesh as components, in index order.
pub fn vertices(mesh: &Mesh) -> Vec<Component> {
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); mesh.vertex_count()];
    for (f, face) in mesh.faces().enumerate() {
        for &v in face {
            around[v as usize].push(f);
        }
    }
    around
        .iter()
        .enumerate()
        .filter(|(_, faces)| !faces.is_empty())
        .enumerate()
        .map(|(index, (v, faces))| {
            let p = mesh.position(v as u32);
            let normal = mean_normal(mesh, faces.iter().copied());
            let z = normal.try_normalize().unwrap_or(DVec3::Y);
            let x = DVec3::X
                .reject_from(z)
                .try_normalize()
                .unwrap_or_else(|| DVec3::Z.reject_from(z).normalize());
            Component {
                kind: ComponentKind::Vertex,
                index,
                source: v,
                scope: Scope::new(p, frame(x, z), DVec3::ZERO),
                points: vec![p],
                normal,
            }
        })
        .collect()
}

/// An edge component turned around: from its second point to its first, x and y reversed.
pub fn reversed_edge(edge: &Component) -> Component {
    let points = vec![edge.points[1], edge.points[0]];
    let axes = frame(-edge.scope.axes.x_axis, edge.scope.axes.z_axis);
    Component {
        scope: Scope::fit(axes, points.iter().copied()),
        points,
        ..edge.clone()
    }
}

/// The right-handed frame with unit x and z given (orthogonal), y = z × x.
fn frame(x: DVec3, z: DVec3) -> DMat3 {
    DMat3::from_cols(x, z.cross(x), z)
}

/// The normalised sum of the normals of some faces, or zero.
fn mean_normal(mesh: &Mesh, faces: impl Iterator<Item = usize>) -> DVec3 {
    faces
        .map(|f| mesh.face_normal(f))
        .sum::<DVec3>()
        .normalize_or_zero()
}
