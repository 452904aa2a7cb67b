//! The vertex data of a GLB's primitives: each part's or line set's [`Chunk`] of positions,
//! normals, uvs, tangents and indices, taken from the model as the writer streams it.

use std::borrow::Cow;

use shapegram_geom::{DVec2, DVec3, Lines, Mesh, Part};

use super::compact::ModelVertices;
use super::tangents::{face_tangent, vertex_tangents};
use crate::flat::{
    FaceSplitter, drawable, flat_faces, is_smooth, segment_is_exportable, texture_uvs, unit,
    usable_normals,
};

/// Vertices taken from a model's own list: all of them, or those in `keep` (in that order) when
/// some are not used by anything written.
pub(crate) struct Shared<'a> {
    all: &'a [DVec3],
    keep: Option<Vec<u32>>,
}

impl Shared<'_> {
    fn len(&self) -> usize {
        self.keep.as_ref().map_or(self.all.len(), Vec::len)
    }

    /// Calls `visit` with the index in `all` of every vertex written, in order.
    fn each(&self, mut visit: impl FnMut(usize)) {
        match &self.keep {
            Some(keep) => keep.iter().for_each(|&v| visit(v as usize)),
            None => (0..self.all.len()).for_each(visit),
        }
    }
}

/// Keeps only the vertices `indices` use, renumbering `indices` when some are left out.
fn shared<'a>(all: &'a [DVec3], indices: &mut Cow<'_, [u32]>) -> Shared<'a> {
    let mut used = vec![false; all.len()];
    for &v in indices.iter() {
        used[v as usize] = true;
    }
    if used.iter().all(|&u| u) {
        return Shared { all, keep: None };
    }
    let mut remap = vec![u32::MAX; all.len()];
    let mut keep = Vec::new();
    for (v, _) in used.iter().enumerate().filter(|(_, u)| **u) {
        remap[v] = keep.len() as u32;
        keep.push(v as u32);
    }
    for v in indices.to_mut().iter_mut() {
        *v = remap[*v as usize];
    }
    Shared {
        all,
        keep: Some(keep),
    }
}

/// The faces of a flat chunk.
pub(crate) struct FlatFaces<'a> {
    /// Per face, in order: how many corners and how many triangles it has.
    pub(crate) faces: &'a [[u32; 2]],
    /// Each corner's position, face after face.
    pub(crate) positions: &'a [[f32; 3]],
    /// Each corner's normal: its face's.
    pub(crate) normals: &'a [[f32; 3]],
    /// The faces' triangles, counted from the chunk's first corner.
    pub(crate) indices: &'a [u32],
}

/// Part of a primitive's vertex data, with indices counted from its own first vertex.
pub(crate) enum Chunk<'a> {
    /// Flat-shaded faces: corners per face, each with the face normal (and its vertex's uv,
    /// for a textured part; empty otherwise).
    Flat {
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        uvs: Vec<[f32; 2]>,
        /// One per corner, for a normal-mapped part; empty otherwise.
        tangents: Vec<[f32; 4]>,
        indices: Vec<u32>,
        /// Per face, in order: how many corners and how many triangles it has.
        faces: Vec<[u32; 2]>,
    },
    /// A smooth part's shared vertices with their normals (and uvs, for a textured part).
    Smooth {
        vertices: Shared<'a>,
        normals: Cow<'a, [DVec3]>,
        uvs: Option<&'a [DVec2]>,
        /// One per mesh vertex, for a normal-mapped part.
        tangents: Option<Vec<[f32; 4]>>,
        indices: Vec<u32>,
    },
    /// A line set's points and segments.
    Lines {
        points: Shared<'a>,
        indices: Cow<'a, [u32]>,
    },
}

impl<'a> Chunk<'a> {
    /// A part's triangles: smooth when it has one normal per vertex, flat otherwise.
    pub(crate) fn of_part(part: &'a Part) -> Option<Self> {
        let uvs = texture_uvs(part);
        let normal_mapped = uvs.is_some()
            && part
                .surface
                .as_ref()
                .and_then(|s| s.maps.normal.as_deref())
                .is_some_and(drawable);
        let chunk = if is_smooth(part) {
            smooth_chunk(part, uvs, normal_mapped)
        } else {
            flat_chunk(&part.mesh, uvs, normal_mapped)
        };
        (chunk.index_count() > 0).then_some(chunk)
    }

    /// A line set's segments (those [`segment_is_exportable`] keeps).
    pub(crate) fn of_lines(lines: &'a Lines) -> Option<Self> {
        let drawn = |s: &[u32; 2]| segment_is_exportable(&lines.points, *s);
        let mut indices: Cow<'_, [u32]> = if lines.segments.iter().all(drawn) {
            Cow::Borrowed(lines.segments.as_flattened())
        } else {
            Cow::Owned(
                lines
                    .segments
                    .iter()
                    .filter(|s| drawn(s))
                    .flatten()
                    .copied()
                    .collect(),
            )
        };
        if indices.is_empty() {
            return None;
        }
        let points = shared(&lines.points, &mut indices);
        Some(Self::Lines { points, indices })
    }

    pub(crate) fn vertex_count(&self) -> usize {
        match self {
            Self::Flat { positions, .. } => positions.len(),
            Self::Smooth { vertices, .. } => vertices.len(),
            Self::Lines { points, .. } => points.len(),
        }
    }

    pub(crate) fn indices(&self) -> &[u32] {
        match self {
            Self::Flat { indices, .. } | Self::Smooth { indices, .. } => indices,
            Self::Lines { indices, .. } => indices,
        }
    }

    /// Its indices, leaving it none.
    pub(crate) fn take_indices(&mut self) -> Vec<u32> {
        match self {
            Self::Flat { indices, .. } | Self::Smooth { indices, .. } => std::mem::take(indices),
            Self::Lines { indices, .. } => std::mem::take(indices).into_owned(),
        }
    }

    /// A smooth chunk's vertices as the model holds them and its indices, leaving it none,
    /// when it writes every vertex of its mesh with nothing but a position and a normal;
    /// `None` otherwise.
    pub(crate) fn take_model_vertices(&mut self) -> Option<(ModelVertices<'a>, Vec<u32>)> {
        match self {
            Self::Smooth {
                vertices: Shared { all, keep: None },
                normals,
                uvs: None,
                tangents: None,
                indices,
            } => Some((
                ModelVertices {
                    positions: all,
                    normals: std::mem::take(normals),
                },
                std::mem::take(indices),
            )),
            _ => None,
        }
    }

    pub(crate) fn index_count(&self) -> usize {
        self.indices().len()
    }

    /// Calls `visit` with every f32 position, in vertex order.
    pub(crate) fn positions(&self, mut visit: impl FnMut([f32; 3])) {
        match self {
            Self::Flat { positions, .. } => positions.iter().copied().for_each(visit),
            Self::Smooth {
                vertices: shared, ..
            }
            | Self::Lines { points: shared, .. } => {
                shared.each(|v| visit(shared.all[v].as_vec3().to_array()))
            }
        }
    }

    /// A flat chunk's faces (`None` for the others).
    pub(crate) fn flat_faces(&self) -> Option<FlatFaces<'_>> {
        match self {
            Self::Flat {
                faces,
                positions,
                normals,
                indices,
                ..
            } => Some(FlatFaces {
                faces,
                positions,
                normals,
                indices,
            }),
            Self::Smooth { .. } | Self::Lines { .. } => None,
        }
    }

    /// Whether the chunk is a smooth part's, whose normals differ from its faces'.
    pub(crate) fn is_smooth(&self) -> bool {
        matches!(self, Self::Smooth { .. })
    }

    /// Whether the chunk has a uv per vertex.
    pub(crate) fn has_uvs(&self) -> bool {
        match self {
            Self::Flat { uvs, .. } => !uvs.is_empty(),
            Self::Smooth { uvs, .. } => uvs.is_some(),
            Self::Lines { .. } => false,
        }
    }

    /// Calls `visit` with every uv as glTF has it (v down), in vertex order (none without).
    pub(crate) fn uvs(&self, mut visit: impl FnMut([f32; 2])) {
        match self {
            Self::Flat { uvs, .. } => uvs.iter().copied().for_each(visit),
            Self::Smooth {
                vertices,
                uvs: Some(uvs),
                ..
            } => vertices.each(|v| visit(gltf_uv(uvs[v]))),
            Self::Smooth { .. } | Self::Lines { .. } => {}
        }
    }

    /// Whether the chunk has a tangent per vertex.
    pub(crate) fn has_tangents(&self) -> bool {
        match self {
            Self::Flat { tangents, .. } => !tangents.is_empty(),
            Self::Smooth { tangents, .. } => tangents.is_some(),
            Self::Lines { .. } => false,
        }
    }

    /// Calls `visit` with every tangent, in vertex order (none without).
    pub(crate) fn tangents(&self, mut visit: impl FnMut([f32; 4])) {
        match self {
            Self::Flat { tangents, .. } => tangents.iter().copied().for_each(visit),
            Self::Smooth {
                vertices,
                tangents: Some(tangents),
                ..
            } => vertices.each(|v| visit(tangents[v])),
            Self::Smooth { .. } | Self::Lines { .. } => {}
        }
    }

    /// Calls `visit` with every f32 unit normal, in vertex order (none for lines).
    pub(crate) fn normals(&self, mut visit: impl FnMut([f32; 3])) {
        match self {
            Self::Flat { normals, .. } => normals.iter().copied().for_each(visit),
            Self::Smooth {
                vertices, normals, ..
            } => vertices.each(|v| visit(unit(normals[v]))),
            Self::Lines { .. } => {}
        }
    }
}

/// A uv as glTF stores it: v runs down the image, where CGA's runs up.
pub(crate) fn gltf_uv(uv: DVec2) -> [f32; 2] {
    [uv.x as f32, (1.0 - uv.y) as f32]
}

/// A mesh's faces with vertices of their own, as flat shading needs (with tangents, when
/// `normal_mapped` and there are uvs).
fn flat_chunk<'a>(mesh: &Mesh, texture_uvs: Option<&[DVec2]>, normal_mapped: bool) -> Chunk<'a> {
    // Sized for every face and corner at once: a city has a chunk per leaf, and growing its
    // lists one push at a time costs more allocations than the leaf's own.
    let corners = mesh.indices_len();
    let mut positions = Vec::with_capacity(corners);
    let mut normals = Vec::with_capacity(corners);
    let mut indices = Vec::with_capacity(3 * corners.saturating_sub(2 * mesh.face_count()));
    let mut faces = Vec::with_capacity(mesh.face_count());
    let (mut uvs, mut tangents) = (Vec::new(), Vec::new());
    flat_faces(mesh, |face| {
        let base = positions.len() as u32;
        faces.push([face.corners.len() as u32, face.triangles.len() as u32]);
        positions.extend_from_slice(face.corners);
        normals.extend(std::iter::repeat_n(face.normal, face.corners.len()));
        if let Some(texture_uvs) = texture_uvs {
            let first = uvs.len();
            uvs.extend(
                face.vertices
                    .iter()
                    .map(|&v| gltf_uv(texture_uvs[v as usize])),
            );
            if normal_mapped {
                let tangent =
                    face_tangent(face.normal, face.corners, &uvs[first..], face.triangles);
                tangents.extend(std::iter::repeat_n(tangent, face.corners.len()));
            }
        }
        indices.extend(face.triangles.iter().flatten().map(|&c| base + c));
    });
    Chunk::Flat {
        positions,
        normals,
        uvs,
        tangents,
        indices,
        faces,
    }
}

/// A smooth part's faces over its shared vertices (see [`usable_normals`]).
fn smooth_chunk<'a>(part: &'a Part, uvs: Option<&'a [DVec2]>, normal_mapped: bool) -> Chunk<'a> {
    let mesh = &part.mesh;
    let mut splitter = FaceSplitter::default();
    let mut fan = Vec::new();
    // Every corner beyond the first two of a face adds a triangle.
    let mut indices =
        Vec::with_capacity(3 * mesh.indices_len().saturating_sub(2 * mesh.face_count()));
    for face in mesh.faces() {
        fan.clear();
        if splitter
            .split_loop(mesh.positions(), face, &mut fan)
            .is_some()
        {
            // A triangle at a time: a flattened iterator pushed its indices one by one.
            for t in &fan {
                indices.extend_from_slice(&t.map(|c| face[c as usize]));
            }
        }
    }
    let normals = usable_normals(part);
    let tangents = uvs.filter(|_| normal_mapped).map(|uvs| {
        let positions: Vec<[f32; 3]> = mesh
            .positions()
            .iter()
            .map(|p| p.as_vec3().to_array())
            .collect();
        let units: Vec<[f32; 3]> = normals.iter().map(|&n| unit(n)).collect();
        let flipped: Vec<[f32; 2]> = uvs.iter().map(|&uv| gltf_uv(uv)).collect();
        vertex_tangents(&positions, &units, &flipped, &indices)
    });
    let mut indices = Cow::Owned(indices);
    let vertices = shared(mesh.positions(), &mut indices);
    Chunk::Smooth {
        vertices,
        normals,
        uvs,
        tangents,
        indices: indices.into_owned(),
    }
}
