//! Convex polyhedra in a half-edge structure held in arrays (the thesis's winged-edge variant).
//!
//! The thesis (3.1.2) stores every geometrical edge as two topological edges, one per face, so
//! that every face is cycled by its own directed edges; that is a half-edge structure. Each
//! half-edge knows its origin vertex, its face, its twin (the same edge seen from the other face)
//! and the next and previous half-edges of its face, all as indices into arrays, so every
//! adjacency query is constant time. The winged-edge fields map onto it directly: destination =
//! origin of `next`, left face = `face`, right face = face of `twin`, the wings = `next`/`prev` of
//! the half-edge and of its twin.
//!
//! Face loops run counter-clockwise seen from outside (the workspace convention, so Newell normals
//! point outward); the thesis's clockwise traversals walk `prev`.

use std::fmt;

use rustc_hash::FxHashMap;
use shapegram_geom::{DVec3, Mesh};

/// Index of a vertex, half-edge or face.
pub type Index = u32;

/// Relative tolerance of the geometric checks (planarity, convexity), times the bounding
/// diagonal. Looser than the cut's classification tolerance so that cut results always pass.
const CHECK_EPSILON: f64 = 1e-7;

/// Most vertices a polyhedron may have: rules are hand-made, so more is a corrupt input.
pub const MAX_VERTICES: usize = 1 << 20;

/// A closed, convex polyhedron with planar, convex faces.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyhedron {
    positions: Vec<DVec3>,
    /// One half-edge leaving each vertex.
    vertex_edge: Vec<Index>,
    origin: Vec<Index>,
    twin: Vec<Index>,
    next: Vec<Index>,
    prev: Vec<Index>,
    face: Vec<Index>,
    /// The half-edge leaving the first vertex of each face's loop.
    face_edge: Vec<Index>,
}

/// Why vertex and face data do not make a closed convex polyhedron.
#[derive(Clone, Debug, PartialEq)]
pub enum PolyhedronError {
    /// Fewer than four vertices or faces, or too many vertices.
    Size(String),
    /// A position is NaN or infinite.
    NonFinite {
        /// The vertex.
        vertex: usize,
    },
    /// A face has fewer than three corners, a corner out of range or a repeated corner.
    BadFace {
        /// The face.
        face: usize,
        /// What is wrong.
        reason: String,
    },
    /// Two faces run along the same edge in the same direction, or an edge has one face only.
    NotClosed {
        /// The edge's vertices.
        edge: (Index, Index),
        /// What is wrong.
        reason: &'static str,
    },
    /// A vertex is used by no face, or its faces do not form one fan.
    BadVertex {
        /// The vertex.
        vertex: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// The surface is not a sphere (V − E + F ≠ 2).
    Euler {
        /// V − E + F.
        characteristic: i64,
    },
    /// A face is not planar, not convex, or has no area; or the solid is not convex or is inside
    /// out.
    Geometry(String),
}

impl fmt::Display for PolyhedronError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Size(reason) => write!(f, "{reason}"),
            Self::NonFinite { vertex } => write!(f, "vertex {vertex} is not a finite point"),
            Self::BadFace { face, reason } => write!(f, "face {face}: {reason}"),
            Self::NotClosed { edge, reason } => {
                write!(f, "edge {} → {}: {reason}", edge.0, edge.1)
            }
            Self::BadVertex { vertex, reason } => write!(f, "vertex {vertex}: {reason}"),
            Self::Euler { characteristic } => write!(
                f,
                "the surface is not a closed sphere (V − E + F = {characteristic}, expected 2)"
            ),
            Self::Geometry(reason) => write!(f, "{reason}"),
        }
    }
}

impl std::error::Error for PolyhedronError {}

impl Polyhedron {
    /// The box `[min, min + size]`. Vertex `i` is the corner with offsets `(i & 1, i >> 1 & 1,
    /// i >> 2 & 1)` times the size; faces are −x, +x, −y, +y, −z, +z in that order.
    pub fn cuboid(min: DVec3, size: DVec3) -> Result<Self, PolyhedronError> {
        let positions = (0..8)
            .map(|i| {
                let corner = DVec3::new(
                    f64::from(i & 1),
                    f64::from((i >> 1) & 1),
                    f64::from((i >> 2) & 1),
                );
                min + corner * size
            })
            .collect();
        let faces: [[Index; 4]; 6] = [
            [0, 4, 6, 2],
            [1, 3, 7, 5],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 2, 3, 1],
            [4, 5, 7, 6],
        ];
        Self::from_faces(positions, &faces)
    }

    /// A polyhedron from positions and face loops (counter-clockwise seen from outside), after
    /// checking that they form a closed, convex, outward-facing solid with convex planar faces.
    pub fn from_faces<F: AsRef<[Index]>>(
        positions: Vec<DVec3>,
        faces: &[F],
    ) -> Result<Self, PolyhedronError> {
        let shape = Self::from_faces_topology(positions, faces)?;
        shape.check_geometry()?;
        Ok(shape)
    }

    /// Builds the arrays and checks the topology only.
    fn from_faces_topology<F: AsRef<[Index]>>(
        positions: Vec<DVec3>,
        faces: &[F],
    ) -> Result<Self, PolyhedronError> {
        let n = positions.len();
        if !(4..=MAX_VERTICES).contains(&n) {
            return Err(PolyhedronError::Size(format!(
                "a polyhedron needs 4 to {MAX_VERTICES} vertices, got {n}"
            )));
        }
        if faces.len() < 4 {
            return Err(PolyhedronError::Size(format!(
                "a polyhedron needs at least 4 faces, got {}",
                faces.len()
            )));
        }
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(PolyhedronError::NonFinite { vertex });
        }
        let mut shape = Self {
            positions,
            vertex_edge: vec![Index::MAX; n],
            origin: Vec::new(),
            twin: Vec::new(),
            next: Vec::new(),
            prev: Vec::new(),
            face: Vec::new(),
            face_edge: Vec::with_capacity(faces.len()),
        };
        let mut edge_of: FxHashMap<(Index, Index), Index> = FxHashMap::default();
        // The last face (plus one) that used each vertex: finds repeated corners in one pass,
        // so a face of a million corners costs a million steps, not half a trillion.
        let mut used_by = vec![0usize; n];
        for (f, face) in faces.iter().enumerate() {
            let face = face.as_ref();
            let bad = |reason: String| PolyhedronError::BadFace { face: f, reason };
            if face.len() < 3 {
                return Err(bad(format!("{} corners, expected at least 3", face.len())));
            }
            if let Some(&v) = face.iter().find(|&&v| v as usize >= n) {
                return Err(bad(format!("corner {v} is not a vertex (there are {n})")));
            }
            for &v in face {
                if used_by[v as usize] == f + 1 {
                    return Err(bad(format!("vertex {v} appears twice")));
                }
                used_by[v as usize] = f + 1;
            }
            let first = shape.origin.len() as Index;
            let len = face.len() as Index;
            shape.face_edge.push(first);
            for (k, &v) in face.iter().enumerate() {
                let h = first + k as Index;
                let to = face[(k + 1) % face.len()];
                if edge_of.insert((v, to), h).is_some() {
                    return Err(PolyhedronError::NotClosed {
                        edge: (v, to),
                        reason: "two faces run along it in the same direction",
                    });
                }
                shape.origin.push(v);
                shape.face.push(f as Index);
                shape.next.push(first + (k as Index + 1) % len);
                shape.prev.push(first + (k as Index + len - 1) % len);
                shape.vertex_edge[v as usize] = h;
            }
        }
        shape.twin = vec![Index::MAX; shape.origin.len()];
        for h in 0..shape.origin.len() {
            let from = shape.origin[h];
            let to = shape.origin[shape.next[h] as usize];
            match edge_of.get(&(to, from)) {
                Some(&t) => shape.twin[h] = t,
                None => {
                    return Err(PolyhedronError::NotClosed {
                        edge: (from, to),
                        reason: "only one face runs along it (the surface has a hole)",
                    });
                }
            }
        }
        let mut outgoing = vec![0usize; n];
        for &o in &shape.origin {
            outgoing[o as usize] += 1;
        }
        for (v, &count) in outgoing.iter().enumerate() {
            if shape.vertex_edge[v] == Index::MAX {
                return Err(PolyhedronError::BadVertex {
                    vertex: v,
                    reason: "no face uses it",
                });
            }
            if shape.vertex_fan(v as Index).count() != count {
                return Err(PolyhedronError::BadVertex {
                    vertex: v,
                    reason: "its faces form more than one fan (two solids touch there)",
                });
            }
        }
        let characteristic =
            n as i64 - (shape.origin.len() / 2) as i64 + shape.face_edge.len() as i64;
        if characteristic != 2 {
            return Err(PolyhedronError::Euler { characteristic });
        }
        Ok(shape)
    }

    /// Checks planarity and convexity of the faces, convexity and orientation of the solid.
    fn check_geometry(&self) -> Result<(), PolyhedronError> {
        let eps = CHECK_EPSILON * self.diagonal();
        if eps <= 0.0 {
            return Err(PolyhedronError::Geometry("all vertices coincide".into()));
        }
        if self.volume() <= 0.0 {
            return Err(PolyhedronError::Geometry(
                "the faces are clockwise seen from outside (the solid is inside out)".into(),
            ));
        }
        for f in 0..self.face_count() {
            let normal = self.face_normal(f);
            if normal == DVec3::ZERO {
                return Err(PolyhedronError::Geometry(format!("face {f} has no area")));
            }
            let anchor = self.position(self.origin[self.face_edge[f as usize] as usize]);
            for h in self.face_half_edges(f) {
                let a = self.position(self.origin[h as usize]);
                let b = self.position(self.destination(h));
                let c = self.position(self.destination(self.next[h as usize]));
                if (a - anchor).dot(normal).abs() > eps {
                    return Err(PolyhedronError::Geometry(format!("face {f} is not planar")));
                }
                if (b - a).length() <= eps {
                    return Err(PolyhedronError::Geometry(format!(
                        "face {f} has an edge of no length"
                    )));
                }
                if (b - a).cross(c - b).dot(normal) < -eps * (c - b).length() {
                    return Err(PolyhedronError::Geometry(format!("face {f} is not convex")));
                }
            }
            if let Some(v) =
                (0..self.positions.len()).find(|&v| (self.positions[v] - anchor).dot(normal) > eps)
            {
                return Err(PolyhedronError::Geometry(format!(
                    "the solid is not convex: vertex {v} lies outside the plane of face {f}"
                )));
            }
        }
        Ok(())
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> Index {
        self.face_edge.len() as Index
    }

    /// Number of half-edges (twice the number of edges).
    pub fn half_edge_count(&self) -> usize {
        self.origin.len()
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Position of vertex `v`.
    pub fn position(&self, v: Index) -> DVec3 {
        self.positions[v as usize]
    }

    /// The vertex half-edge `h` leaves.
    pub fn origin(&self, h: Index) -> Index {
        self.origin[h as usize]
    }

    /// The vertex half-edge `h` arrives at.
    pub fn destination(&self, h: Index) -> Index {
        self.origin[self.next[h as usize] as usize]
    }

    /// The same edge in the neighbouring face, running the other way.
    pub fn twin(&self, h: Index) -> Index {
        self.twin[h as usize]
    }

    /// The next half-edge of the face, counter-clockwise seen from outside.
    pub fn next(&self, h: Index) -> Index {
        self.next[h as usize]
    }

    /// The previous half-edge of the face: the next one clockwise seen from outside.
    pub fn prev(&self, h: Index) -> Index {
        self.prev[h as usize]
    }

    /// The face half-edge `h` belongs to.
    pub fn face_of(&self, h: Index) -> Index {
        self.face[h as usize]
    }

    /// The half-edge leaving the first corner of face `f`.
    pub fn face_edge(&self, f: Index) -> Index {
        self.face_edge[f as usize]
    }

    /// The half-edges of face `f`, counter-clockwise from its first corner.
    pub fn face_half_edges(&self, f: Index) -> impl Iterator<Item = Index> + '_ {
        self.cycle(self.face_edge[f as usize], |h| self.next[h as usize])
    }

    /// The half-edges of a face clockwise (seen from outside), starting at `h`.
    pub fn face_half_edges_cw(&self, h: Index) -> impl Iterator<Item = Index> + '_ {
        self.cycle(h, |h| self.prev[h as usize])
    }

    /// The corners of face `f`, counter-clockwise seen from outside.
    pub fn face_loop(&self, f: Index) -> impl Iterator<Item = Index> + '_ {
        self.face_half_edges(f).map(|h| self.origin[h as usize])
    }

    /// Number of corners of face `f`.
    pub fn face_len(&self, f: Index) -> usize {
        self.face_half_edges(f).count()
    }

    /// The half-edges leaving vertex `v`, clockwise seen from outside (its vertex fan).
    pub fn vertex_fan(&self, v: Index) -> impl Iterator<Item = Index> + '_ {
        self.cycle(self.vertex_edge[v as usize], |h| {
            self.next[self.twin[h as usize] as usize]
        })
    }

    /// The faces around vertex `v`, clockwise seen from outside.
    pub fn vertex_faces(&self, v: Index) -> impl Iterator<Item = Index> + '_ {
        self.vertex_fan(v).map(|h| self.face[h as usize])
    }

    /// The dual graph: the faces sharing an edge with face `f`, clockwise around `f`.
    pub fn face_neighbours(&self, f: Index) -> impl Iterator<Item = Index> + '_ {
        self.face_half_edges_cw(self.face_edge[f as usize])
            .map(|h| self.face[self.twin[h as usize] as usize])
    }

    /// Follows `step` from `start` until it comes back, guarding against broken links.
    fn cycle(&self, start: Index, step: impl Fn(Index) -> Index) -> impl Iterator<Item = Index> {
        let limit = self.origin.len();
        let mut current = Some(start);
        let mut count = 0;
        std::iter::from_fn(move || {
            let h = current?;
            count += 1;
            let after = step(h);
            current = (after != start && count < limit).then_some(after);
            Some(h)
        })
    }

    /// The half-edge of face `f` leaving its `corner`-th corner (counted counter-clockwise from
    /// the first), if the face has that many corners.
    pub fn corner_edge(&self, f: Index, corner: Index) -> Option<Index> {
        if f >= self.face_count() {
            return None;
        }
        self.face_half_edges(f).nth(corner as usize)
    }

    /// Where half-edge `h` sits: its face and the corner it leaves (the inverse of
    /// [`Polyhedron::corner_edge`]).
    pub fn edge_corner(&self, h: Index) -> (Index, Index) {
        let f = self.face[h as usize];
        let corner = self.face_half_edges(f).position(|e| e == h).unwrap_or(0);
        (f, corner as Index)
    }

    /// Outward unit normal of face `f` (Newell's method).
    pub fn face_normal(&self, f: Index) -> DVec3 {
        self.newell(f).normalize_or_zero()
    }

    /// Twice the vector area of face `f` (Newell's method), relative to its first corner so it
    /// stays accurate far from the origin.
    fn newell(&self, f: Index) -> DVec3 {
        let mut corners = self.face_loop(f).map(|v| self.position(v));
        let Some(first) = corners.next() else {
            return DVec3::ZERO;
        };
        let mut sum = DVec3::ZERO;
        let mut previous = DVec3::ZERO;
        for p in corners {
            let p = p - first;
            sum += previous.cross(p);
            previous = p;
        }
        sum
    }

    /// Mean of the corners of face `f`.
    pub fn face_centroid(&self, f: Index) -> DVec3 {
        let (sum, n) = self.face_loop(f).fold((DVec3::ZERO, 0.0), |(s, n), v| {
            (s + self.position(v), n + 1.0)
        });
        sum / n
    }

    /// Area of face `f`.
    pub fn face_area(&self, f: Index) -> f64 {
        0.5 * self.newell(f).length()
    }

    /// Mean of the vertices (inside the solid, since it is convex).
    pub fn center(&self) -> DVec3 {
        self.positions.iter().sum::<DVec3>() / self.positions.len() as f64
    }

    /// Length of the diagonal of the bounding box.
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        (hi - lo).length()
    }

    /// Enclosed volume (positive: faces point outward).
    pub fn volume(&self) -> f64 {
        let reference = self.center();
        let sum: f64 = (0..self.face_count())
            .map(|f| self.newell(f).dot(self.face_centroid(f) - reference) * 0.5)
            .sum();
        sum / 3.0
    }

    /// The face loops as lists of vertex indices, counter-clockwise seen from outside.
    pub fn face_loops(&self) -> Vec<Vec<Index>> {
        (0..self.face_count())
            .map(|f| self.face_loop(f).collect())
            .collect()
    }

    /// The same solid with vertices moved to `positions` (one per vertex), if the result is still
    /// a valid convex polyhedron.
    pub fn with_positions(&self, positions: Vec<DVec3>) -> Result<Self, PolyhedronError> {
        Self::from_faces(positions, &self.face_loops())
    }

    /// The polygon mesh of the surface (same vertex indices).
    pub fn to_mesh(&self) -> Mesh {
        Mesh::from_faces(self.positions.clone(), self.face_loops())
    }
}

/// Checks that `faces` over `vertex_count` vertices form a closed surface of genus 0, without
/// looking at any geometry.
pub(crate) fn check_topology<F: AsRef<[Index]>>(
    vertex_count: usize,
    faces: &[F],
) -> Result<(), PolyhedronError> {
    if vertex_count > MAX_VERTICES {
        return Err(PolyhedronError::Size(format!(
            "a polyhedron needs 4 to {MAX_VERTICES} vertices, got {vertex_count}"
        )));
    }
    Polyhedron::from_faces_topology(vec![DVec3::ZERO; vertex_count], faces).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_cube() -> Polyhedron {
        Polyhedron::cuboid(DVec3::ZERO, DVec3::ONE).unwrap()
    }

    fn tetrahedron() -> Polyhedron {
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        Polyhedron::from_faces(positions, &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]).unwrap()
    }

    #[test]
    fn the_cube_has_the_counts_and_volume_of_a_box() {
        let cube =
            Polyhedron::cuboid(DVec3::new(1.0, 2.0, 3.0), DVec3::new(2.0, 3.0, 4.0)).unwrap();
        assert_eq!(cube.vertex_count(), 8);
        assert_eq!(cube.face_count(), 6);
        assert_eq!(cube.half_edge_count(), 24);
        assert!((cube.volume() - 24.0).abs() < 1e-12);
        assert_eq!(cube.face_normal(3), DVec3::Y);
        assert_eq!(cube.face_normal(4), -DVec3::Z);
    }

    #[test]
    fn adjacency_is_consistent() {
        for shape in [unit_cube(), tetrahedron()] {
            for h in 0..shape.half_edge_count() as Index {
                assert_eq!(shape.twin(shape.twin(h)), h);
                assert_eq!(shape.next(shape.prev(h)), h);
                assert_eq!(shape.origin(shape.twin(h)), shape.destination(h));
                assert_ne!(shape.face_of(h), shape.face_of(shape.twin(h)));
            }
        }
    }

    #[test]
    fn clockwise_face_traversal_reverses_the_loop() {
        let cube = unit_cube();
        let top = cube.face_edge(3);
        let cw: Vec<_> = cube
            .face_half_edges_cw(top)
            .map(|h| cube.origin(h))
            .collect();
        assert_eq!(cw, [2, 3, 7, 6]);
        assert_eq!(cube.face_loop(3).collect::<Vec<_>>(), [2, 6, 7, 3]);
    }

    #[test]
    fn vertex_fans_go_clockwise_around_the_vertex() {
        let cube = unit_cube();
        // Around corner 7 (+x, +y, +z) seen from outside, clockwise: +x, +z, +y in some rotation.
        let faces: Vec<_> = cube.vertex_faces(7).collect();
        assert_eq!(faces.len(), 3);
        let normals: Vec<_> = faces.iter().map(|&f| cube.face_normal(f)).collect();
        // Clockwise seen from outside means the triple product of consecutive normals is negative.
        assert!(normals[0].cross(normals[1]).dot(normals[2]) < 0.0);
        for v in 0..8 {
            assert_eq!(cube.vertex_fan(v).count(), 3);
            assert!(cube.vertex_fan(v).all(|h| cube.origin(h) == v));
        }
    }

    #[test]
    fn the_dual_of_the_cube_is_the_octahedron() {
        let cube = unit_cube();
        for f in 0..6 {
            let neighbours: Vec<_> = cube.face_neighbours(f).collect();
            assert_eq!(neighbours.len(), 4);
            // Every face touches all faces but itself and the opposite one.
            let opposite = f ^ 1;
            assert!(!neighbours.contains(&f) && !neighbours.contains(&opposite));
        }
    }

    #[test]
    fn corners_and_edges_convert_both_ways() {
        let cube = unit_cube();
        for h in 0..24 {
            let (f, c) = cube.edge_corner(h);
            assert_eq!(cube.corner_edge(f, c), Some(h));
        }
        assert_eq!(cube.corner_edge(6, 0), None);
        assert_eq!(cube.corner_edge(0, 4), None);
    }

    #[test]
    fn broken_inputs_are_reported() {
        let cube = unit_cube();
        let positions = cube.positions().to_vec();
        let mut faces = cube.face_loops();
        faces.pop();
        assert_eq!(
            Polyhedron::from_faces(positions.clone(), &faces).unwrap_err(),
            PolyhedronError::NotClosed {
                edge: (4, 6),
                reason: "only one face runs along it (the surface has a hole)"
            }
        );
        let mut flipped = cube.face_loops();
        for face in &mut flipped {
            face.reverse();
        }
        assert_eq!(
            Polyhedron::from_faces(positions.clone(), &flipped)
                .unwrap_err()
                .to_string(),
            "the faces are clockwise seen from outside (the solid is inside out)"
        );
        let mut dented = positions.clone();
        dented[7] = DVec3::splat(0.6);
        assert!(matches!(
            Polyhedron::from_faces(dented, &cube.face_loops()),
            Err(PolyhedronError::Geometry(_))
        ));
        let mut bad = cube.face_loops();
        bad[0][1] = 9;
        assert_eq!(
            Polyhedron::from_faces(positions.clone(), &bad)
                .unwrap_err()
                .to_string(),
            "face 0: corner 9 is not a vertex (there are 8)"
        );
        let mut nan = positions;
        nan[2].y = f64::NAN;
        assert_eq!(
            Polyhedron::from_faces(nan, &cube.face_loops()).unwrap_err(),
            PolyhedronError::NonFinite { vertex: 2 }
        );
    }
}
