//! A primitive's vertices made compact: gathered from its chunks, coplanar rectangles merged
//! (where allowed), vertices that agree in every attribute shared, and (unless the triangle
//! order must stay) triangles put in vertex-cache order with vertices in first-use order, by
//! meshoptimizer. Every step is deterministic: it depends on the data only.

use std::borrow::Cow;
use std::ops::Range;

use meshopt::VertexStream;
use shapegram_geom::DVec3;

use super::Primitive;
use super::chunk::FlatFaces;
use super::coplanar::{self, Rectangle};
use super::triples::{Triples, point};
use crate::flat::unit;

/// A primitive's vertex data, one entry per vertex in each attribute that it has, and its
/// indices (pairs for lines, triples for triangles).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Vertices<'a> {
    /// Empty when the vertices are `model`'s.
    pub(crate) positions: Vec<[f32; 3]>,
    /// Empty for lines, and for flat primitives once compacted unless flat normals are written.
    pub(crate) normals: Vec<[f32; 3]>,
    /// Empty unless the primitive is textured.
    pub(crate) uvs: Vec<[f32; 2]>,
    /// Empty unless the primitive is normal-mapped.
    pub(crate) tangents: Vec<[f32; 4]>,
    /// Each vertex's joint; empty unless the primitive is skinned.
    pub(crate) joints: Vec<u16>,
    /// Each vertex's feature id; empty unless the file has features. Part of a vertex's
    /// identity like any attribute, so no vertex is shared by two features.
    pub(crate) features: Vec<u32>,
    pub(crate) indices: Vec<u32>,
    /// A smooth part's vertices as the model holds them, read instead of `positions` and
    /// `normals` (then empty), which would copy them.
    pub(crate) model: Option<ModelVertices<'a>>,
}

/// A smooth part's shared vertices and their normals, in the model's f64.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ModelVertices<'a> {
    pub(crate) positions: &'a [DVec3],
    /// One per position, none zero or infinite.
    pub(crate) normals: Cow<'a, [DVec3]>,
}

/// What compaction may do to a primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Compaction {
    /// Merge coplanar rectangles and reorder triangles: off when triangles must stay in the
    /// order of the model's faces ([`super::write_glb_with_layout`]).
    pub(crate) reorder: bool,
}

impl<'a> Vertices<'a> {
    /// The primitive's vertices, compacted as `compaction` allows; when `pooled`, only
    /// gathered and merged, since the mesh's vertex pool shares and orders them (see
    /// [`super::pool`]).
    pub(crate) fn of_primitive(
        primitive: &mut Primitive<'a>,
        compaction: Compaction,
        pooled: bool,
    ) -> Self {
        // A smooth part alone in its primitive with nothing but positions and normals (a
        // tube) is written from the model's vertices as they are: it would not be compacted.
        let plain = primitive.normals
            && primitive.skinned.is_none()
            && !primitive.textured
            && primitive.features.is_none();
        if let [chunk] = &mut primitive.chunks[..]
            && plain
            && !pooled
            && let Some((model, indices)) = chunk.take_model_vertices()
        {
            return Self {
                indices,
                model: Some(model),
                ..Self::default()
            };
        }
        // Rectangles merge only where each vertex carries nothing but a position and a
        // normal: uvs, tangents and joints would have to agree across the merge too.
        let merge = compaction.reorder
            && !primitive.lines
            && !primitive.textured
            && !primitive.tangents
            && primitive.skinned.is_none();
        let mut vertices = Self::default();
        // Corners of the faces that may merge come after the merge (see below).
        let count: usize = primitive
            .chunks
            .iter()
            .filter(|c| !(merge && c.flat_faces().is_some()))
            .map(|c| c.vertex_count())
            .sum();
        vertices.positions.reserve_exact(count);
        if primitive.normals {
            vertices.normals.reserve_exact(count);
        }
        // At most the chunks' indices, sized once rather than grown by doubling, unless the
        // first chunk hands over its own list (below).
        let first_takes = primitive
            .chunks
            .first()
            .is_some_and(|c| !(merge && c.flat_faces().is_some()));
        if !first_takes {
            let indices = primitive.chunks.iter().map(|c| c.index_count()).sum();
            vertices.indices.reserve_exact(indices);
        }
        // Sized once: a city's walls are millions of rectangles, copied at every doubling.
        let faces = primitive.chunks.iter().filter_map(|c| c.flat_faces());
        let mut rectangles = Vec::with_capacity(if merge {
            faces.map(|f| f.faces.len()).sum()
        } else {
            0
        });
        // The feature of each rectangle, when there are features.
        let mut rectangle_features = Vec::new();
        let features = primitive.features.as_deref();
        for (c, chunk) in primitive.chunks.iter_mut().enumerate() {
            let feature = features.map(|ids| ids[c]);
            // Where faces merge, only the faces that are no rectangles bring their corners:
            // no index would name a rectangle's, and sharing drops what no index names.
            if let Some(flat) = chunk.flat_faces().filter(|_| merge) {
                vertices.split_rectangles(&flat, primitive.normals, &mut rectangles);
                if let Some(feature) = feature {
                    rectangle_features.resize(rectangles.len(), feature);
                    vertices.features.resize(vertices.positions.len(), feature);
                }
                continue;
            }
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
            if let Some(feature) = feature {
                vertices.features.resize(vertices.positions.len(), feature);
            }
            // A primitive's only chunk (a tube's mesh, say) gives up its indices rather than
            // have hundreds of megabytes copied; the chunk is let go after this.
            if vertices.indices.is_empty() && base == 0 {
                vertices.indices = chunk.take_indices();
            } else {
                vertices
                    .indices
                    .extend(chunk.indices().iter().map(|&i| base + i));
            }
        }
        if features.is_some() {
            vertices.merge_by_feature(&rectangles, &rectangle_features, primitive.normals);
        } else {
            let merged = coplanar::merge(&rectangles);
            vertices.positions.reserve_exact(4 * merged.len());
            if primitive.normals {
                vertices.normals.reserve_exact(4 * merged.len());
            }
            for rectangle in &merged {
                vertices.push_rectangle(rectangle, primitive.normals);
            }
        }
        // Smooth parts and line sets come with their vertices shared already (a tube's rings,
        // a cave's surface), in an order that is mostly cache friendly: hashing and reordering
        // them would cost more than it saves.
        if !pooled && primitive.chunks.iter().any(|c| c.flat_faces().is_some()) {
            vertices.share(primitive.lines, compaction.reorder);
        }
        vertices
    }

    /// Takes the faces of a flat chunk that are rectangles of two triangles into `rectangles`,
    /// and the others' corners (with their normals, when `normals`) and triangles into the
    /// vertices.
    fn split_rectangles(
        &mut self,
        flat: &FlatFaces<'_>,
        normals: bool,
        rectangles: &mut Vec<Rectangle>,
    ) {
        let (mut corner, mut index) = (0, 0);
        for &[corners, triangles] in flat.faces {
            let (corners, corner_indices) = (corners as usize, 3 * triangles as usize);
            let face = &flat.positions[corner..corner + corners];
            let quad = (corners == 4 && triangles == 2)
                .then(|| Rectangle::new([face[0], face[1], face[2], face[3]], flat.normals[corner]))
                .flatten();
            match quad {
                Some(rectangle) => rectangles.push(rectangle),
                None => {
                    // The face's indices count from the chunk's first corner, its corners
                    // here from `first`.
                    let first = self.positions.len() as u32;
                    self.positions.extend_from_slice(face);
                    if normals {
                        self.normals
                            .extend_from_slice(&flat.normals[corner..corner + corners]);
                    }
                    let triangles = &flat.indices[index..index + corner_indices];
                    self.indices
                        .extend(triangles.iter().map(|&i| i - corner as u32 + first));
                }
            }
            corner += corners;
            index += corner_indices;
        }
    }

    /// Merges the rectangles of each feature (`features`, one per rectangle) apart, since a
    /// merged face would belong to two, and appends them, with their feature, in feature order.
    fn merge_by_feature(&mut self, rectangles: &[Rectangle], features: &[u32], normals: bool) {
        let mut order: Vec<usize> = (0..rectangles.len()).collect();
        order.sort_by_key(|&i| features[i]);
        let mut group = Vec::new();
        for (k, &i) in order.iter().enumerate() {
            group.push(rectangles[i]);
            let last = order
                .get(k + 1)
                .is_none_or(|&next| features[next] != features[i]);
            if !last {
                continue;
            }
            for rectangle in &coplanar::merge(&group) {
                self.push_rectangle(rectangle, normals);
            }
            self.features.resize(self.positions.len(), features[i]);
            group.clear();
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
        if !self.features.is_empty() {
            streams.push(VertexStream::new(self.features.as_ptr()));
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
        if let Some(&f) = self.features.get(v) {
            self.features.push(f);
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
        moved(&mut self.features, unique, remap);
    }

    /// How many vertices there are.
    pub(crate) fn len(&self) -> usize {
        match &self.model {
            Some(model) => model.positions.len(),
            None => self.positions.len(),
        }
    }

    /// The vertices and indices as they are, without copying.
    pub(crate) fn view(&self) -> View<'_> {
        self.window(0..self.len(), 0..self.indices.len())
    }

    /// The vertices in `range` and the indices in `indices` (positions in the index list),
    /// which all name vertices in `range`.
    fn window(&self, range: Range<usize>, indices: Range<usize>) -> View<'_> {
        let (positions, normals) = match &self.model {
            Some(model) => (
                Triples::Points(&model.positions[range.clone()]),
                Triples::Normals(&model.normals[range.clone()]),
            ),
            None => (
                Triples::F32(&self.positions[range.clone()]),
                Triples::F32(attribute(&self.normals, &range)),
            ),
        };
        View {
            positions,
            normals,
            uvs: attribute(&self.uvs, &range),
            tangents: attribute(&self.tangents, &range),
            joints: attribute(&self.joints, &range),
            features: attribute(&self.features, &range),
            indices: &self.indices[indices],
            base: range.start as u32,
        }
    }

    /// The triangles cut into runs (in order) of at most `limit` vertices each; a primitive
    /// that fits stays whole. Runs of fewer than 65,535 vertices take u16 indices: half the
    /// bytes of u32 ones. Where each run's triangles span a window of consecutive vertices (a
    /// tube's rings, a smooth mesh built in order) that together cover the vertices about
    /// once, the runs are those windows, written from the vertices as they are; otherwise
    /// each run gathers the vertices it uses, in order of first use.
    pub(crate) fn split(&self, limit: usize) -> Vec<Run> {
        if self.len() <= limit {
            return vec![Run::Whole];
        }
        self.windows(limit)
            .unwrap_or_else(|| self.gather(limit).into_iter().map(Run::Gathered).collect())
    }

    /// Runs over windows of consecutive vertices, or `None` when a triangle spans more than
    /// `limit` vertices or the windows would repeat more than one vertex in 64.
    fn windows(&self, limit: usize) -> Option<Vec<Run>> {
        let budget = self.len() + self.len() / 64;
        let mut runs = Vec::new();
        let mut covered = 0;
        let (mut start, mut low, mut high) = (0, usize::MAX, 0);
        // Closes the window of triangles `start..end` over vertices `low..=high`; `false` when
        // the windows would repeat too many vertices.
        let mut close = |runs: &mut Vec<Run>, start, end, low: usize, high: usize| {
            covered += high + 1 - low;
            runs.push(Run::Window {
                vertices: low..high + 1,
                triangles: start..end,
            });
            covered <= budget
        };
        // A tube has tens of millions of triangles: plain min and max of the three corners.
        for (t, c) in self.indices.chunks_exact(3).enumerate() {
            let t_low = c[0].min(c[1]).min(c[2]) as usize;
            let t_high = c[0].max(c[1]).max(c[2]) as usize;
            if t_high - t_low >= limit {
                return None;
            }
            let (new_low, new_high) = (low.min(t_low), high.max(t_high));
            if new_high - new_low >= limit {
                if !close(&mut runs, start, t, low, high) {
                    return None;
                }
                (start, low, high) = (t, t_low, t_high);
            } else {
                (low, high) = (new_low, new_high);
            }
        }
        let triangles = self.indices.len() / 3;
        close(&mut runs, start, triangles, low, high).then_some(runs)
    }

    /// Runs that each gather the vertices they use, in order of first use.
    fn gather(&self, limit: usize) -> Vec<Vertices<'static>> {
        let mut runs = Vec::new();
        let mut slot = vec![u32::MAX; self.len()];
        let mut run = Vertices::default();
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
                    run.push_vertex(self, v as usize);
                }
                run.indices.push(slot[v as usize]);
            }
        }
        runs.push(run);
        runs
    }

    /// Appends vertex `v` of `from` with every attribute it has.
    fn push_vertex(&mut self, from: &Vertices<'_>, v: usize) {
        match &from.model {
            Some(model) => {
                self.positions.push(point(model.positions[v]));
                self.normals.push(unit(model.normals[v]));
            }
            None => {
                self.positions.push(from.positions[v]);
                if let Some(&n) = from.normals.get(v) {
                    self.normals.push(n);
                }
            }
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
        if let Some(&f) = from.features.get(v) {
            self.features.push(f);
        }
    }
}

/// The values of an attribute in `range`: none for an attribute the vertices do not have.
fn attribute<'a, T>(values: &'a [T], range: &Range<usize>) -> &'a [T] {
    if values.is_empty() {
        values
    } else {
        &values[range.clone()]
    }
}

/// A primitive's vertex data borrowed: each attribute it has and the indices.
#[derive(Clone, Copy, Debug)]
pub(crate) struct View<'a> {
    pub(crate) positions: Triples<'a>,
    /// Empty when the vertices have none.
    pub(crate) normals: Triples<'a>,
    pub(crate) uvs: &'a [[f32; 2]],
    pub(crate) tangents: &'a [[f32; 4]],
    pub(crate) joints: &'a [u16],
    pub(crate) features: &'a [u32],
    pub(crate) indices: &'a [u32],
    /// The vertex that index `base` names, the first of the view: indices are written less
    /// `base`.
    pub(crate) base: u32,
}

impl<'a> View<'a> {
    /// Positions without other attributes, and `indices` into them.
    pub(crate) fn bare(positions: &'a [[f32; 3]], indices: &'a [u32]) -> Self {
        Self {
            positions: Triples::F32(positions),
            normals: Triples::F32(&[]),
            uvs: &[],
            tangents: &[],
            joints: &[],
            features: &[],
            indices,
            base: 0,
        }
    }

    /// How many vertices there are.
    pub(crate) fn len(&self) -> usize {
        self.positions.len()
    }
}

/// A run of a primitive's triangles, written as a glTF primitive of its own.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Run {
    /// All of the primitive's triangles and vertices.
    Whole,
    /// Triangles (numbered in order) over a window of consecutive vertices.
    Window {
        vertices: Range<usize>,
        triangles: Range<usize>,
    },
    /// Triangles over vertices gathered from the primitive's.
    Gathered(Vertices<'static>),
}

impl Run {
    /// The run's vertex data, taken from `of` (the primitive's) where it is not its own.
    pub(crate) fn view<'a>(&'a self, of: &'a Vertices<'_>) -> View<'a> {
        match self {
            Self::Whole => of.view(),
            Self::Window {
                vertices,
                triangles,
            } => of.window(vertices.clone(), 3 * triangles.start..3 * triangles.end),
            Self::Gathered(own) => own.view(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of `quads` quads along x: two vertices per column, with normals.
    fn strip(quads: u32) -> Vertices<'static> {
        let mut vertices = Vertices::default();
        for i in 0..=quads {
            for y in [0.0, 1.0] {
                vertices.positions.push([i as f32, y, 0.0]);
                vertices.normals.push([0.0, 0.0, 1.0]);
            }
        }
        for i in 0..quads {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            vertices.indices.extend([a, b, c, a, c, d]);
        }
        vertices
    }

    fn triangles(v: View<'_>) -> Vec<[[f32; 3]; 3]> {
        v.indices
            .chunks_exact(3)
            .map(|t| [0, 1, 2].map(|k| v.positions.get((t[k] - v.base) as usize)))
            .collect()
    }

    #[test]
    fn a_primitive_built_in_order_splits_into_windows_of_its_vertices() {
        let vertices = strip(1000);
        assert_eq!(vertices.split(2002), [Run::Whole]);
        let runs = vertices.split(200);
        // Windows of at most 200 consecutive vertices, each after the first starting at the
        // edge its predecessor ends with.
        let windows: Vec<_> = runs
            .iter()
            .map(|r| match r {
                Run::Window { vertices, .. } => vertices.clone(),
                other => panic!("{other:?} is no window"),
            })
            .collect();
        assert_eq!(windows.len(), 11);
        assert_eq!(windows[0], 0..200);
        assert_eq!(windows[1], 198..398);
        assert_eq!(windows.last().unwrap().end, 2002);
        let views: Vec<View<'_>> = runs.iter().map(|r| r.view(&vertices)).collect();
        assert!(
            views
                .iter()
                .all(|v| v.len() <= 200 && v.normals.len() == v.len())
        );
        let joined: Vec<_> = views.iter().copied().flat_map(triangles).collect();
        assert_eq!(joined, triangles(vertices.view()));
    }

    #[test]
    fn a_scattered_model_primitive_gathers_its_vertices_rounded() {
        // The strip's shuffled indices over f64 vertices of the model: runs gather f32 copies.
        let ordered = strip(10);
        let positions: Vec<DVec3> = (0..22)
            .map(|i| DVec3::new(f64::from(i) / 3.0, 0.1, -1e-7))
            .collect();
        let normals: Vec<DVec3> = (0..22)
            .map(|i| DVec3::new(0.0, 2.0, f64::from(i)))
            .collect();
        let vertices = Vertices {
            indices: ordered.indices.iter().map(|v| 7 * v % 22).collect(),
            model: Some(ModelVertices {
                positions: &positions,
                normals: Cow::Borrowed(&normals),
            }),
            ..Vertices::default()
        };
        assert_eq!(vertices.len(), 22);
        let runs = vertices.split(8);
        assert!(runs.iter().all(|r| matches!(r, Run::Gathered(_))));
        let whole = vertices.view();
        let mut gathered = 0;
        for run in &runs {
            let Run::Gathered(own) = run else { continue };
            assert!(own.len() <= 8 && own.normals.len() == own.len());
            for corners in own.indices.chunks_exact(3) {
                gathered += 1;
                for &c in corners {
                    let c = c as usize;
                    let source = (0..22)
                        .find(|&v| whole.positions.get(v) == own.positions[c])
                        .expect("every gathered position is a model position rounded");
                    assert_eq!(own.normals[c], whole.normals.get(source));
                }
            }
        }
        assert_eq!(gathered, ordered.indices.len() / 3);
    }

    #[test]
    fn a_scattered_primitive_splits_into_runs_that_gather_their_vertices() {
        // The strip's vertices shuffled (i -> 7i mod 22): its triangles span the whole list.
        let ordered = strip(10);
        let mut vertices = ordered.clone();
        for (i, (p, n)) in ordered.positions.iter().zip(&ordered.normals).enumerate() {
            vertices.positions[7 * i % 22] = *p;
            vertices.normals[7 * i % 22] = *n;
        }
        for v in &mut vertices.indices {
            *v = 7 * *v % 22;
        }
        let runs = vertices.split(8);
        assert!(runs.iter().all(|r| matches!(r, Run::Gathered(_))));
        let views: Vec<View<'_>> = runs.iter().map(|r| r.view(&vertices)).collect();
        assert!(
            views
                .iter()
                .all(|v| v.len() <= 8 && v.normals.len() == v.len())
        );
        let joined: Vec<_> = views.iter().copied().flat_map(triangles).collect();
        assert_eq!(joined, triangles(ordered.view()));
    }
}
