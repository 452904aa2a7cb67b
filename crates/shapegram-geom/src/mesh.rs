//! Polygon meshes: shared vertex positions and faces given as vertex loops.

use crate::{Aabb, DAffine3, DVec3};

/// A polygon mesh. Each face is a loop of vertex indices, counter-clockwise seen from the side its
/// normal points to; faces are planar and may be non-convex. Faces are stored back to back in one
/// index array, so a mesh of a thousand quads is three allocations, not a thousand.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    positions: Vec<DVec3>,
    /// Face `i` is `indices[loop_starts[i]..loop_starts[i + 1]]`.
    loop_starts: Vec<u32>,
    indices: Vec<u32>,
}

impl Default for Mesh {
    fn default() -> Self {
        Self::new()
    }
}

impl Mesh {
    /// An empty mesh.
    pub fn new() -> Self {
        Self {
            positions: Vec::new(),
            loop_starts: vec![0],
            indices: Vec::new(),
        }
    }

    /// An empty mesh with room for `vertices` vertices and `faces` faces of `indices` indices
    /// in all, for builders that know their sizes: a large mesh grown one push at a time copies
    /// itself as it doubles.
    pub fn with_capacity(vertices: usize, faces: usize, indices: usize) -> Self {
        let mut loop_starts = Vec::with_capacity(faces + 1);
        loop_starts.push(0);
        Self {
            positions: Vec::with_capacity(vertices),
            loop_starts,
            indices: Vec::with_capacity(indices),
        }
    }

    /// A mesh from positions and face loops. Loops with fewer than three vertices are skipped.
    ///
    /// # Panics
    /// If a loop refers to a vertex that does not exist.
    pub fn from_faces<F: AsRef<[u32]>>(
        positions: Vec<DVec3>,
        faces: impl IntoIterator<Item = F>,
    ) -> Self {
        let mut mesh = Self {
            positions,
            ..Self::new()
        };
        for face in faces {
            mesh.add_face(face.as_ref());
        }
        mesh
    }

    /// A mesh of a single polygon (no face for fewer than three points).
    pub fn from_polygon(points: &[DVec3]) -> Self {
        // Built in place, each list allocated once: a derived model makes one per flat leaf.
        let n = points.len() as u32;
        let (loop_starts, indices) = if n < 3 {
            (vec![0], Vec::new())
        } else {
            (vec![0, n], (0..n).collect())
        };
        Self {
            positions: points.to_vec(),
            loop_starts,
            indices,
        }
    }

    /// A mesh of quads, each list allocated once (see [`Mesh::from_faces`]).
    ///
    /// # Panics
    /// If a quad refers to a vertex that does not exist.
    pub fn from_quads(positions: Vec<DVec3>, quads: &[[u32; 4]]) -> Self {
        assert!(
            quads
                .as_flattened()
                .iter()
                .all(|&i| (i as usize) < positions.len()),
            "face refers to a missing vertex"
        );
        Self {
            positions,
            loop_starts: (0..=quads.len() as u32).map(|face| face * 4).collect(),
            indices: quads.as_flattened().to_vec(),
        }
    }

    /// Adds a vertex and returns its index.
    // Inlined across crates (there is no LTO): builders call it once per vertex, millions of
    // times for an L-system's tubes.
    #[inline]
    pub fn add_vertex(&mut self, p: DVec3) -> u32 {
        self.positions.push(p);
        (self.positions.len() - 1) as u32
    }

    /// Adds a face loop and returns its index, or `None` (adding nothing) for fewer than three
    /// vertices.
    ///
    /// # Panics
    /// If the loop refers to a vertex that does not exist.
    // Inlined like `add_vertex`, so that a caller's fixed-size loop (a quad) is copied without a
    // call to memcpy.
    #[inline]
    pub fn add_face(&mut self, face: &[u32]) -> Option<usize> {
        if face.len() < 3 {
            return None;
        }
        assert!(
            face.iter().all(|&i| (i as usize) < self.positions.len()),
            "face refers to a missing vertex"
        );
        self.indices.extend_from_slice(face);
        self.loop_starts.push(self.indices.len() as u32);
        Some(self.face_count() - 1)
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Position of vertex `i`.
    pub fn position(&self, i: u32) -> DVec3 {
        self.positions[i as usize]
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.loop_starts.len() - 1
    }

    /// Whether the mesh has no faces.
    pub fn is_empty(&self) -> bool {
        self.face_count() == 0
    }

    /// The vertex loop of face `i`.
    pub fn face(&self, i: usize) -> &[u32] {
        &self.indices[self.loop_starts[i] as usize..self.loop_starts[i + 1] as usize]
    }

    /// All face loops in order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        (0..self.face_count()).map(|i| self.face(i))
    }

    /// The corner positions of face `i`.
    pub fn face_points(&self, i: usize) -> impl ExactSizeIterator<Item = DVec3> + Clone + '_ {
        self.face(i).iter().map(|&v| self.positions[v as usize])
    }

    /// Unit normal of face `i` (Newell's method), or zero for a degenerate face.
    pub fn face_normal(&self, i: usize) -> DVec3 {
        newell(self.face_points(i)).normalize_or_zero()
    }

    /// Area of face `i`.
    pub fn face_area(&self, i: usize) -> f64 {
        0.5 * newell(self.face_points(i)).length()
    }

    /// Mean of the corners of face `i`.
    pub fn face_centroid(&self, i: usize) -> DVec3 {
        let n = self.face(i).len() as f64;
        self.face_points(i).sum::<DVec3>() / n
    }

    /// One unit normal per vertex for smooth shading: the area-weighted mean of the normals of
    /// the faces around it. A vertex whose faces cancel out (both sides of a sheet) takes the
    /// normal of its first non-degenerate face, and a vertex without one points up (+y), so the
    /// result never holds NaN or zero vectors.
    pub fn vertex_normals(&self) -> Vec<DVec3> {
        let mut sums = vec![DVec3::ZERO; self.positions.len()];
        // Newell's vector is twice the face's vector area, so summing it weights by area.
        let face_vectors: Vec<DVec3> = (0..self.face_count())
            .map(|i| newell(self.face_points(i)))
            .collect();
        for (face, vector) in self.faces().zip(&face_vectors) {
            for &v in face {
                sums[v as usize] += *vector;
            }
        }
        let mut normals: Vec<DVec3> = sums.iter().map(|s| s.normalize_or_zero()).collect();
        if normals.contains(&DVec3::ZERO) {
            for (face, vector) in self.faces().zip(&face_vectors) {
                let unit = vector.normalize_or_zero();
                for &v in face {
                    if normals[v as usize] == DVec3::ZERO {
                        normals[v as usize] = unit;
                    }
                }
            }
            for n in &mut normals {
                if *n == DVec3::ZERO {
                    *n = DVec3::Y;
                }
            }
        }
        normals
    }

    /// Total number of face corners (the length of all loops together).
    pub fn indices_len(&self) -> usize {
        self.indices.len()
    }

    /// Appends another mesh's vertices and faces.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        let index_base = self.indices.len() as u32;
        self.indices.extend(other.indices.iter().map(|&i| i + base));
        self.loop_starts
            .extend(other.loop_starts[1..].iter().map(|&s| s + index_base));
    }

    /// Applies an affine map to every vertex. A map that mirrors (negative determinant) also
    /// reverses every loop so that normals keep pointing outward.
    pub fn transform(&mut self, map: &DAffine3) {
        for p in &mut self.positions {
            *p = map.transform_point3(*p);
        }
        if map.matrix3.determinant() < 0.0 {
            self.flip();
        }
    }

    /// This mesh under an affine map (see [`Mesh::transform`]).
    pub fn transformed(&self, map: &DAffine3) -> Self {
        let mut copy = self.clone();
        copy.transform(map);
        copy
    }

    /// Reverses every face loop, turning the mesh inside out.
    pub fn flip(&mut self) {
        for w in self.loop_starts.windows(2) {
            self.indices[w[0] as usize..w[1] as usize].reverse();
        }
    }

    /// Bounds of the vertices, `None` for a mesh without vertices.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(self.positions.iter().copied())
    }

    /// Total surface area; 0 (not −0, which an empty float sum gives) for a mesh without faces.
    pub fn area(&self) -> f64 {
        (0..self.face_count())
            .map(|i| self.face_area(i))
            .fold(0.0, |sum, a| sum + a)
    }

    /// Signed volume enclosed by the faces: positive for a closed mesh with outward normals.
    ///
    /// Sums, over the faces, the volume of the cone from a reference point to the face. The
    /// reference point is the first vertex, which keeps the sum accurate far from the origin.
    pub fn signed_volume(&self) -> f64 {
        let Some(&reference) = self.positions.first() else {
            return 0.0;
        };
        let volume: f64 = (0..self.face_count())
            .map(|i| {
                let c = self.face_centroid(i) - reference;
                newell(self.face_points(i)).dot(c) * 0.5
            })
            .sum();
        volume / 3.0
    }

    /// A copy where vertices that fall in the same cell of a grid of spacing `tolerance` are
    /// merged (equal positions always merge; zero tolerance merges only equal ones), repeated
    /// corners are dropped and faces left with fewer than three corners removed. Used to recover
    /// connectivity from formats that store one vertex per corner (STL, flat-shaded glTF).
    pub fn welded(&self, tolerance: f64) -> Self {
        let key = |p: DVec3| {
            // Bits of the grid coordinates: no integer overflow however fine the grid, and where
            // even the division overflows, the coordinate itself.
            p.to_array().map(|x| {
                let cell = (x / tolerance).round();
                let q = if cell.is_finite() { cell } else { x };
                (q + 0.0).to_bits()
            })
        };
        let mut index_of = rustc_hash::FxHashMap::default();
        let mut positions = Vec::new();
        let remap: Vec<u32> = self
            .positions
            .iter()
            .map(|&p| {
                *index_of.entry(key(p)).or_insert_with(|| {
                    positions.push(p);
                    (positions.len() - 1) as u32
                })
            })
            .collect();
        let mut welded = Self {
            positions,
            ..Self::new()
        };
        let mut face = Vec::new();
        for loop_ in self.faces() {
            face.clear();
            for &v in loop_ {
                let w = remap[v as usize];
                if face.last() != Some(&w) {
                    face.push(w);
                }
            }
            while face.len() > 1 && face.first() == face.last() {
                face.pop();
            }
            welded.add_face(&face);
        }
        welded
    }

    /// A copy without unused vertices, vertex order kept.
    pub fn compacted(&self) -> Self {
        let mut used = vec![false; self.positions.len()];
        for &v in &self.indices {
            used[v as usize] = true;
        }
        let mut remap = vec![0u32; self.positions.len()];
        let mut positions = Vec::with_capacity(self.positions.len());
        for (old, _) in used.iter().enumerate().filter(|(_, u)| **u) {
            remap[old] = positions.len() as u32;
            positions.push(self.positions[old]);
        }
        Self {
            positions,
            loop_starts: self.loop_starts.clone(),
            indices: self.indices.iter().map(|&v| remap[v as usize]).collect(),
        }
    }
}

/// Twice the vector area of a closed loop of points (Newell's method): its direction is the loop's
/// normal and its length twice the loop's area, for planar loops of any convexity.
// One pass, inlined: the exporters take the normal of every face (millions for a tube).
#[inline]
pub fn newell(mut points: impl Iterator<Item = DVec3>) -> DVec3 {
    let Some(first) = points.next() else {
        return DVec3::ZERO;
    };
    // Relative to the first corner, so large coordinates do not swamp small faces. The first
    // corner's own `first - first` is kept (NaN for a non-finite corner, as it should be).
    let local = |p: DVec3| p - first;
    let mut previous = local(first);
    let mut sum = DVec3::ZERO;
    for p in points {
        let local = local(p);
        sum += previous.cross(local);
        previous = local;
    }
    sum + previous.cross(DVec3::ZERO)
}

/// [`newell`] of the quad `a b c d`, bit for bit (the same operations in the same order),
/// without an iterator or an array: the exporters take it for every side face of a tube, and
/// an array of corners went through the stack.
#[inline(always)]
pub fn newell_quad(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> DVec3 {
    // `a - a` as in `newell`: NaN for a corner that is not finite.
    #[allow(clippy::eq_op, reason = "zero or NaN, as newell has it")]
    let (la, lb, lc, ld) = (a - a, b - a, c - a, d - a);
    let mut sum = DVec3::ZERO;
    sum += la.cross(lb);
    sum += lb.cross(lc);
    sum += lc.cross(ld);
    sum + ld.cross(DVec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quad_normal_is_newells_bit_for_bit() {
        let mut state = 0x853c_49e6_748f_ea9b_u64;
        let mut random = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        for k in 0..10_000 {
            let offset = [0.0, 1e3, -7e8, 1e300][k % 4];
            let quad: [DVec3; 4] = std::array::from_fn(|_| {
                DVec3::new(random(), random(), random()) * [1.0, 1e-9][k % 2] + offset
            });
            let [a, b, c, d] = quad;
            assert_eq!(
                bits(newell_quad(a, b, c, d)),
                bits(newell(quad.into_iter()))
            );
        }
        for odd in [f64::NAN, f64::INFINITY, -0.0] {
            let quad = [DVec3::ZERO, DVec3::X, DVec3::splat(odd), DVec3::Y];
            let [a, b, c, d] = quad;
            assert_eq!(
                bits(newell_quad(a, b, c, d)),
                bits(newell(quad.into_iter()))
            );
        }
    }
    use crate::primitives;

    #[test]
    fn cube_corners_point_along_their_diagonals() {
        let cube = primitives::cuboid(DVec3::ONE);
        let normals = cube.vertex_normals();
        assert_eq!(normals.len(), cube.vertex_count());
        let centre = DVec3::splat(0.5);
        for (p, n) in cube.positions().iter().zip(&normals) {
            let diagonal = (*p - centre).normalize();
            assert!((*n - diagonal).length() < 1e-12, "{p} has {n}");
        }
    }

    #[test]
    fn larger_faces_weigh_more() {
        // A vertex shared by a 2x1 face in the xy-plane and a 1x1 face in the yz-plane.
        let positions = vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(0.0, 1.0, -1.0),
        ];
        let mesh = Mesh::from_faces(positions, [[0u32, 1, 2, 3], [0, 3, 5, 4]]);
        let normals = mesh.vertex_normals();
        let expected = DVec3::new(-1.0, 0.0, 2.0).normalize();
        assert!((normals[0] - expected).length() < 1e-12, "{}", normals[0]);
        assert_eq!(normals[1], DVec3::Z);
        assert_eq!(normals[4], DVec3::NEG_X);
    }

    #[test]
    fn cancelling_unused_and_degenerate_vertices_get_unit_normals() {
        // Two copies of a triangle facing opposite ways, a degenerate sliver and an unused vertex.
        let positions = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Z,
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(6.0, 0.0, 0.0),
            DVec3::new(7.0, 0.0, 0.0),
            DVec3::new(9.0, 9.0, 9.0),
        ];
        let mesh = Mesh::from_faces(positions, [[0u32, 1, 2], [0, 2, 1], [3, 4, 5]]);
        let normals = mesh.vertex_normals();
        assert_eq!(normals[0], DVec3::NEG_Y);
        assert_eq!(normals[3], DVec3::Y);
        assert_eq!(normals[6], DVec3::Y);
        assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-12));
    }
}
