//! A primitive's vertices made compact: gathered from its chunks, coplanar rectangles merged
//! (where allowed), vertices that agree in every attribute shared, and (unless the triangle
//! order must stay) triangles put in vertex-cache order with vertices in first-use order, by
//! meshoptimizer. Every step is deterministic: it depends on the data only.

use meshopt::VertexStream;

use super::Primitive;
use super::chunk::FlatFaces;
use super::coplanar::{self, Rectangle};

/// A primitive's vertex data, one entry per vertex in each attribute that it has, and its
/// indices (pairs for lines, triples for triangles).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Vertices {
    pub(crate) positions: Vec<[f32; 3]>,
    /// Empty for lines, and for flat primitives once compacted unless flat normals are written.
    pub(crate) normals: Vec<[f32; 3]>,
    /// Empty unless the primitive is textured.
    pub(crate) uvs: Vec<[f32; 2]>,
    /// Empty unless the primitive is normal-mapped.
    pub(crate) tangents: Vec<[f32; 4]>,
    /// Each vertex's joint; empty unless the primitive is skinned.
    pub(crate) joints: Vec<u16>,
    pub(crate) indices: Vec<u32>,
}

/// What compaction may do to a primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Compaction {
    /// Merge coplanar rectangles and reorder triangles: off when triangles must stay in the
    /// order of the model's faces ([`super::write_glb_with_layout`]).
    pub(crate) reorder: bool,
}

impl Vertices {
    /// The primitive's vertices, compacted as `compaction` allows; when `pooled`, only
    /// gathered and merged, since the mesh's vertex pool shares and orders them (see
    /// [`super::pool`]).
    pub(crate) fn of_primitive(
        primitive: &Primitive<'_>,
        compaction: Compaction,
        pooled: bool,
    ) -> Self {
        // Rectangles merge only where each vertex carries nothing but a position and a
        // normal: uvs, tangents and joints would have to agree across the merge too.
        let merge = compaction.reorder
            && !primitive.lines
            && !primitive.textured
            && !primitive.tangents
            && primitive.skinned.is_none();
        let mut vertices = Self::default();
        let mut rectangles = Vec::new();
        for (c, chunk) in primitive.chunks.iter().enumerate() {
            let base = vertices.positions.len() as u32;
            chunk.positions(|p| vertices.positions.push(p));
            if primitive.normals {
                chunk.normals(|n| vertices.normals.push(n));
            }
            chunk.uvs(|uv| vertices.uvs.push(uv));
            chunk.tangents(|t| vertices.tangents.push(t));
            if let Some(skinned) = &primitive.skinned {
                let joint = skinned.joints[c];
                let count = vertices.positions.len();
                vertices.joints.resize(count, joint);
            }
            let indices = chunk.indices();
            match chunk.flat_faces().filter(|_| merge) {
                Some(flat) => vertices.split_rectangles(base, &flat, indices, &mut rectangles),
                None => vertices.indices.extend(indices.iter().map(|&i| base + i)),
            }
        }
        for rectangle in coplanar::merge(&rectangles) {
            vertices.push_rectangle(&rectangle, primitive.normals);
        }
        // Smooth parts and line sets come with their vertices shared already (a tube's rings,
        // a cave's surface), in an order that is mostly cache friendly: hashing and reordering
        // them would cost more than it saves.
        if !pooled && primitive.chunks.iter().any(|c| c.flat_faces().is_some()) {
            vertices.share(primitive.lines, compaction.reorder);
        }
        vertices
    }

    /// Takes the faces of a flat chunk (its vertices from `base` on) that are rectangles of two
    /// triangles into `rectangles`, and the triangles of the others into the indices.
    fn split_rectangles(
        &mut self,
        base: u32,
        flat: &FlatFaces<'_>,
        indices: &[u32],
        rectangles: &mut Vec<Rectangle>,
    ) {
        let (mut corner, mut index) = (base as usize, 0);
        for &[corners, triangles] in flat.faces {
            let (corners, corner_indices) = (corners as usize, 3 * triangles as usize);
            let quad = (corners == 4 && triangles == 2)
                .then(|| {
                    let p = &self.positions[corner..corner + 4];
                    let normal = flat.normals[corner - base as usize];
                    Rectangle::new([p[0], p[1], p[2], p[3]], normal)
                })
                .flatten();
            match quad {
                Some(rectangle) => rectangles.push(rectangle),
                None => self.indices.extend(
                    indices[index..index + corner_indices]
                        .iter()
                        .map(|&i| base + i),
                ),
            }
            corner += corners;
            index += corner_indices;
        }
    }

    /// Appends a rectangle as four vertices (with its normal, when `normals`) and two
    /// triangles.
    fn push_rectangle(&mut self, rectangle: &Rectangle, normals: bool) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&rectangle.corners);
        if normals {
            self.normals.extend([rectangle.normal; 4]);
        }
        self.indices
            .extend([0, 1, 2, 0, 2, 3].map(|corner| base + corner));
    }

    /// Shares vertices equal in every attribute (bit for bit), drops those no index uses and,
    /// when `reorder`, orders triangles for the vertex cache and vertices by first use.
    fn share(&mut self, lines: bool, reorder: bool) {
        let count = self.positions.len();
        let mut streams = vec![VertexStream::new(self.positions.as_ptr())];
        if !self.normals.is_empty() {
            streams.push(VertexStream::new(self.normals.as_ptr()));
        }
        if !self.uvs.is_empty() {
            streams.push(VertexStream::new(self.uvs.as_ptr()));
        }
        if !self.tangents.is_empty() {
            streams.push(VertexStream::new(self.tangents.as_ptr()));
        }
        if !self.joints.is_empty() {
            streams.push(VertexStream::new(self.joints.as_ptr()));
        }
        let (unique, remap) =
            meshopt::generate_vertex_remap_multi(count, &streams, Some(&self.indices));
        self.remap(unique, &remap);
        if !lines && self.normals.is_empty() {
            self.separate_twins();
        }
        let unique = self.len();
        if reorder && !lines {
            // The FIFO variant: a third of the time of the table-driven one, and as good for
            // the grids of quads that flat parts mostly are.
            let optimized = meshopt::optimize_vertex_cache_fifo(&self.indices, unique, 16);
            self.indices = optimized;
            let remap = meshopt::optimize_vertex_fetch_remap(&self.indices, unique);
            self.remap(unique, &remap);
        }
    }

    /// Gives the second of two triangles over the same corners (a face and its back, which
    /// share corners once normals no longer tell them apart) corners of its own, shared only
    /// with other such second triangles, and a third one corners of its own: readers that keep
    /// one face per set of corners (Blender) would drop it.
    fn separate_twins(&mut self) {
        let mut keyed: Vec<([u32; 3], u32)> = self
            .indices
            .chunks_exact(3)
            .enumerate()
            .map(|(t, c)| {
                let mut corners = [c[0], c[1], c[2]];
                corners.sort_unstable();
                (corners, t as u32)
            })
            .collect();
        keyed.sort_unstable();
        let mut second = vec![u32::MAX; self.len()];
        let mut layer = 0;
        for i in 0..keyed.len() {
            layer = if i > 0 && keyed[i].0 == keyed[i - 1].0 {
                layer + 1
            } else {
                0
            };
            if layer == 0 {
                continue;
            }
            let t = keyed[i].1 as usize;
            for corner in 3 * t..3 * t + 3 {
                let v = self.indices[corner] as usize;
                self.indices[corner] = if layer == 1 && second[v] != u32::MAX {
                    second[v]
                } else {
                    let copy = self.len() as u32;
                    self.duplicate(v);
                    if layer == 1 {
                        second[v] = copy;
                    }
                    copy
                };
            }
        }
    }

    /// Appends a copy of vertex `v` with every attribute it has.
    fn duplicate(&mut self, v: usize) {
        self.positions.push(self.positions[v]);
        if let Some(&n) = self.normals.get(v) {
            self.normals.push(n);
        }
        if let Some(&uv) = self.uvs.get(v) {
            self.uvs.push(uv);
        }
        if let Some(&t) = self.tangents.get(v) {
            self.tangents.push(t);
        }
        if let Some(&j) = self.joints.get(v) {
            self.joints.push(j);
        }
    }

    /// Moves vertex `v` to `remap[v]` in every attribute and index (`unique` vertices after).
    fn remap(&mut self, unique: usize, remap: &[u32]) {
        fn moved<T: Clone + Default>(values: &mut Vec<T>, unique: usize, remap: &[u32]) {
            if !values.is_empty() {
                *values = meshopt::remap_vertex_buffer(values, unique, remap);
            }
        }
        self.indices = meshopt::remap_index_buffer(Some(&self.indices), unique, remap);
        moved(&mut self.positions, unique, remap);
        moved(&mut self.normals, unique, remap);
        moved(&mut self.uvs, unique, remap);
        moved(&mut self.tangents, unique, remap);
        moved(&mut self.joints, unique, remap);
    }

    /// How many vertices there are.
    pub(crate) fn len(&self) -> usize {
        self.positions.len()
    }

    /// The triangles cut into runs (in order) of at most `limit` vertices each, every run with
    /// the vertices it uses, in order of first use; a primitive that fits stays whole. Runs of
    /// fewer than 65,535 vertices take u16 indices: half the bytes of u32 ones.
    pub(crate) fn split(self, limit: usize) -> Vec<Self> {
        if self.len() <= limit {
            return vec![self];
        }
        let mut runs = Vec::new();
        let mut slot = vec![u32::MAX; self.len()];
        let mut run = Self::default();
        let mut used = Vec::new();
        for triangle in self.indices.chunks_exact(3) {
            let new = triangle
                .iter()
                .filter(|&&v| slot[v as usize] == u32::MAX)
                .count();
            if used.len() + new > limit {
                for &v in &used {
                    slot[v as usize] = u32::MAX;
                }
                used.clear();
                runs.push(std::mem::take(&mut run));
            }
            for &v in triangle {
                if slot[v as usize] == u32::MAX {
                    slot[v as usize] = used.len() as u32;
                    used.push(v);
                    run.push_vertex(&self, v as usize);
                }
                run.indices.push(slot[v as usize]);
            }
        }
        runs.push(run);
        runs
    }

    /// Appends vertex `v` of `from` with every attribute it has.
    fn push_vertex(&mut self, from: &Self, v: usize) {
        self.positions.push(from.positions[v]);
        if let Some(&n) = from.normals.get(v) {
            self.normals.push(n);
        }
        if let Some(&uv) = from.uvs.get(v) {
            self.uvs.push(uv);
        }
        if let Some(&t) = from.tangents.get(v) {
            self.tangents.push(t);
        }
        if let Some(&j) = from.joints.get(v) {
            self.joints.push(j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_large_primitive_splits_into_runs_that_keep_every_triangle() {
        // A strip of 10 quads: 22 vertices, 20 triangles.
        let mut vertices = Vertices::default();
        for i in 0..11 {
            for y in [0.0, 1.0] {
                vertices.positions.push([i as f32, y, 0.0]);
                vertices.normals.push([0.0, 0.0, 1.0]);
            }
        }
        for i in 0..10u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            vertices.indices.extend([a, b, c, a, c, d]);
        }
        let whole = vertices.clone().split(22);
        assert_eq!(whole, [vertices.clone()]);
        let runs = vertices.clone().split(8);
        assert!(runs.iter().all(|r| r.len() <= 8));
        let triangles = |v: &Vertices| -> Vec<[[f32; 3]; 3]> {
            v.indices
                .chunks_exact(3)
                .map(|t| [0, 1, 2].map(|k| v.positions[t[k] as usize]))
                .collect()
        };
        let joined: Vec<_> = runs.iter().flat_map(triangles).collect();
        assert_eq!(joined, triangles(&vertices));
        assert!(runs.iter().all(|r| r.normals.len() == r.len()));
    }
}
