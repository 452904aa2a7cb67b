//! Edge adjacency: watertightness checks, boundary loops and the undirected edges of a mesh.

use rustc_hash::FxHashMap as HashMap;

use crate::Mesh;

/// How the directed edges of a mesh pair up. A mesh is watertight when every edge is used exactly
/// once in each direction, i.e. all three counts are zero.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeReport {
    /// Undirected edges of the mesh.
    pub edges: usize,
    /// Edges used by one face only.
    pub boundary: usize,
    /// Edges used by more than two faces.
    pub non_manifold: usize,
    /// Edges used by two faces that run along it in the same direction (inconsistent orientation).
    pub misoriented: usize,
}

impl EdgeReport {
    /// Whether every edge is shared by exactly two faces with opposite orientation.
    pub fn is_watertight(&self) -> bool {
        self.edges > 0 && self.boundary == 0 && self.non_manifold == 0 && self.misoriented == 0
    }
}

/// An undirected edge between vertices `a < b`, with the faces that use it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The lower vertex index.
    pub a: u32,
    /// The higher vertex index.
    pub b: u32,
    /// Faces running along the edge from `a` to `b`.
    pub forward: Vec<usize>,
    /// Faces running along the edge from `b` to `a`.
    pub backward: Vec<usize>,
}

impl Mesh {
    /// The undirected edges in order of first use (face by face, corner by corner).
    pub fn edges(&self) -> Vec<Edge> {
        let mut slot: HashMap<(u32, u32), usize> = HashMap::default();
        let mut edges: Vec<Edge> = Vec::new();
        for (f, face) in self.faces().enumerate() {
            for (i, &u) in face.iter().enumerate() {
                let v = face[(i + 1) % face.len()];
                if u == v {
                    continue;
                }
                let (a, b) = (u.min(v), u.max(v));
                let e = *slot.entry((a, b)).or_insert_with(|| {
                    edges.push(Edge {
                        a,
                        b,
                        forward: Vec::new(),
                        backward: Vec::new(),
                    });
                    edges.len() - 1
                });
                if u == a {
                    edges[e].forward.push(f);
                } else {
                    edges[e].backward.push(f);
                }
            }
        }
        edges
    }

    /// Counts how the edges pair up; see [`EdgeReport`]. Vertices are matched by index, so weld
    /// meshes read from per-corner formats first ([`Mesh::welded`]).
    pub fn edge_report(&self) -> EdgeReport {
        let mut report = EdgeReport::default();
        for e in self.edges() {
            report.edges += 1;
            match (e.forward.len(), e.backward.len()) {
                (1, 1) => {}
                (f, b) if f + b == 1 => report.boundary += 1,
                (f, b) if f + b > 2 => report.non_manifold += 1,
                _ => report.misoriented += 1,
            }
        }
        report
    }

    /// Whether every edge is shared by exactly two faces with opposite orientation.
    pub fn is_watertight(&self) -> bool {
        self.edge_report().is_watertight()
    }

    /// Directed edges `(from, to)` that no face uses in the opposite direction, in face order.
    pub fn boundary_edges(&self) -> Vec<(u32, u32)> {
        let key = |u: u32, v: u32| (u64::from(u) << 32) | u64::from(v);
        let mut count: HashMap<u64, i32> = HashMap::default();
        count.reserve(self.indices_len());
        for (u, v) in self.directed_edges() {
            *count.entry(key(u, v)).or_default() += 1;
        }
        self.directed_edges()
            .filter(|&(u, v)| count.get(&key(v, u)).copied().unwrap_or(0) < count[&key(u, v)])
            .collect()
    }

    /// Every corner's outgoing edge `(corner, next corner)`, face by face.
    fn directed_edges(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.faces().flat_map(|face| {
            face.iter()
                .zip(face.iter().cycle().skip(1))
                .map(|(&u, &v)| (u, v))
        })
    }
}
