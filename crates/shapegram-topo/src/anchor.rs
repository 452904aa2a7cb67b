//! Anchors and the canonical vertex order (thesis 3.1.5).
//!
//! An anchor is a directed edge on a face: a face and one of its corners, the anchor running from
//! that corner to the next one counter-clockwise. From it, the vertices are numbered by a
//! breadth-first traversal of the dual graph (the faces):
//! - the anchor's face is visited first, entered through the anchor;
//! - a face entered through half-edge `e` numbers its unnumbered corners clockwise (seen from
//!   outside) starting at the origin of `e`, then queues its unvisited neighbours clockwise,
//!   starting with the neighbour across `e`; each neighbour is entered through the twin of the
//!   shared half-edge, so its first corner is the end of that edge as seen from this face;
//! - a face is queued once, when it is first met.
//!
//! Every step is determined by the anchor, so the order is unique per (topology, anchor), and
//! moving the anchor moves the order with it. Two shapes have the same topology under their
//! anchors when their face loops, written with these numbers in traversal order, are equal.

use serde::{Deserialize, Serialize};

use crate::polyhedron::{Index, Polyhedron};

/// A directed edge on a face: from `corner` of `face` (counting counter-clockwise from the face's
/// first corner) to the next corner counter-clockwise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Anchor {
    /// The face.
    pub face: Index,
    /// The corner of the face the anchor leaves.
    pub corner: Index,
}

impl Anchor {
    /// The anchor on `face` leaving its `corner`.
    pub const fn new(face: Index, corner: Index) -> Self {
        Self { face, corner }
    }

    /// The half-edge of `shape` this anchor names, if the face and corner exist.
    pub fn half_edge(&self, shape: &Polyhedron) -> Option<Index> {
        shape.corner_edge(self.face, self.corner)
    }

    /// The anchor on half-edge `h` of `shape`.
    pub fn at(shape: &Polyhedron, h: Index) -> Self {
        let (face, corner) = shape.edge_corner(h);
        Self { face, corner }
    }

    /// The anchor moved one corner clockwise on its face (the thesis's "." key).
    pub fn clockwise(&self, shape: &Polyhedron) -> Option<Self> {
        let h = self.half_edge(shape)?;
        Some(Self::at(shape, shape.prev(h)))
    }

    /// The anchor moved one corner counter-clockwise on its face (the thesis's "," key).
    pub fn counter_clockwise(&self, shape: &Polyhedron) -> Option<Self> {
        let h = self.half_edge(shape)?;
        Some(Self::at(shape, shape.next(h)))
    }
}

/// Connectivity written with canonical vertex numbers: what "same topology" compares.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Topology {
    /// Number of vertices.
    pub vertex_count: usize,
    /// Face loops in traversal order, each counter-clockwise seen from outside and starting at
    /// the corner the face was entered at.
    pub faces: Vec<Vec<Index>>,
}

/// The canonical numbering of a shape's vertices under an anchor.
#[derive(Clone, Debug, PartialEq)]
pub struct CanonicalOrder {
    /// Vertex of the shape for each canonical number.
    pub vertices: Vec<Index>,
    /// Canonical number of each vertex of the shape.
    pub rank: Vec<Index>,
    /// The shape's topology in canonical numbers.
    pub topology: Topology,
    /// Face of the shape for each face of `topology`, in traversal order.
    pub faces: Vec<Index>,
}

/// Numbers the vertices of `shape` from `anchor`; `None` when the anchor names no half-edge.
pub fn canonical_order(shape: &Polyhedron, anchor: Anchor) -> Option<CanonicalOrder> {
    let start = anchor.half_edge(shape)?;
    let mut rank = vec![Index::MAX; shape.vertex_count()];
    let mut vertices = Vec::with_capacity(shape.vertex_count());
    let mut queued = vec![false; shape.face_count() as usize];
    let mut queue = std::collections::VecDeque::with_capacity(queued.len());
    let mut entered = Vec::with_capacity(queued.len());
    queued[shape.face_of(start) as usize] = true;
    queue.push_back(start);
    while let Some(entry) = queue.pop_front() {
        entered.push(entry);
        for h in shape.face_half_edges_cw(entry) {
            let v = shape.origin(h) as usize;
            if rank[v] == Index::MAX {
                rank[v] = vertices.len() as Index;
                vertices.push(v as Index);
            }
            let across = shape.twin(h);
            let neighbour = shape.face_of(across) as usize;
            if !queued[neighbour] {
                queued[neighbour] = true;
                queue.push_back(across);
            }
        }
    }
    let loops = entered
        .iter()
        .map(|&entry| {
            std::iter::successors(Some(entry), |&h| {
                Some(shape.next(h)).filter(|&n| n != entry)
            })
            .map(|h| rank[shape.origin(h) as usize])
            .collect()
        })
        .collect();
    Some(CanonicalOrder {
        faces: entered.iter().map(|&h| shape.face_of(h)).collect(),
        vertices,
        rank,
        topology: Topology {
            vertex_count: shape.vertex_count(),
            faces: loops,
        },
    })
}

/// Every anchor of `shape`, face by face, corners counter-clockwise.
pub fn all_anchors(shape: &Polyhedron) -> impl Iterator<Item = Anchor> + '_ {
    (0..shape.face_count())
        .flat_map(move |f| (0..shape.face_len(f) as Index).map(move |c| Anchor::new(f, c)))
}

#[cfg(test)]
mod tests {
    use shapegram_geom::{DQuat, DVec3};

    use super::*;

    /// The unit cube centred on the origin.
    fn cube() -> Polyhedron {
        Polyhedron::cuboid(DVec3::splat(-0.5), DVec3::ONE).unwrap()
    }

    fn ordered_positions(shape: &Polyhedron, anchor: Anchor) -> Vec<DVec3> {
        let order = canonical_order(shape, anchor).unwrap();
        order.vertices.iter().map(|&v| shape.position(v)).collect()
    }

    #[test]
    fn the_anchor_face_is_numbered_clockwise_from_the_anchor() {
        let shape = cube();
        // Top face [2, 6, 7, 3]; the anchor leaves corner 1 (vertex 6) towards vertex 7.
        let order = canonical_order(&shape, Anchor::new(3, 1)).unwrap();
        assert_eq!(&order.vertices[..4], &[6, 2, 3, 7]);
        assert_eq!(order.vertices.len(), 8);
        assert_eq!(order.topology.faces.len(), 6);
        assert_eq!(order.topology.faces[0], [0, 3, 2, 1]);
        for (k, &v) in order.vertices.iter().enumerate() {
            assert_eq!(order.rank[v as usize], k as Index);
        }
    }

    #[test]
    fn every_anchor_of_a_cube_gives_the_same_topology() {
        let shape = cube();
        let reference = canonical_order(&shape, Anchor::new(0, 0)).unwrap().topology;
        assert_eq!(all_anchors(&shape).count(), 24);
        for anchor in all_anchors(&shape) {
            assert_eq!(canonical_order(&shape, anchor).unwrap().topology, reference);
        }
    }

    #[test]
    fn rotating_the_anchor_rotates_the_order() {
        let shape = cube();
        let anchor = Anchor::new(3, 0);
        let turned = anchor.clockwise(&shape).unwrap();
        assert_eq!(turned.counter_clockwise(&shape), Some(anchor));
        let before = ordered_positions(&shape, anchor);
        let after = ordered_positions(&shape, turned);
        // Moving the anchor a quarter turn clockwise on the top face (seen from above) numbers
        // the cube as if it had been turned a quarter turn clockwise about the vertical axis.
        let quarter = DQuat::from_rotation_y(-std::f64::consts::FRAC_PI_2);
        for (b, a) in before.iter().zip(&after) {
            assert!((quarter * *b - *a).length() < 1e-12, "{b} → {a}");
        }
    }

    /// `shape` with vertices renumbered by `permutation` (old → new), faces listed in another
    /// order and every loop starting at another corner.
    fn reindexed(shape: &Polyhedron, permutation: &[Index], turn: usize) -> Polyhedron {
        let mut positions = vec![DVec3::ZERO; shape.vertex_count()];
        for (old, &new) in permutation.iter().enumerate() {
            positions[new as usize] = shape.position(old as Index);
        }
        let mut faces: Vec<Vec<Index>> = shape
            .face_loops()
            .iter()
            .enumerate()
            .map(|(f, l)| {
                let mut l: Vec<Index> = l.iter().map(|&v| permutation[v as usize]).collect();
                let start = (f + turn) % l.len();
                l.rotate_left(start);
                l
            })
            .collect();
        let start = turn % faces.len();
        faces.rotate_left(start);
        Polyhedron::from_faces(positions, &faces).unwrap()
    }

    /// Checks that every anchor numbers `shape` and its renumbered copy alike.
    fn assert_same_orders(shape: &Polyhedron, permutation: &[Index], turn: usize) {
        let other = reindexed(shape, permutation, turn);
        for anchor in all_anchors(shape) {
            let h = anchor.half_edge(shape).unwrap();
            let (from, to) = (
                permutation[shape.origin(h) as usize],
                permutation[shape.destination(h) as usize],
            );
            let same = (0..other.half_edge_count() as Index)
                .find(|&e| other.origin(e) == from && other.destination(e) == to)
                .unwrap();
            let same = Anchor::at(&other, same);
            assert_eq!(
                ordered_positions(shape, anchor),
                ordered_positions(&other, same)
            );
            assert_eq!(
                canonical_order(shape, anchor).unwrap().topology,
                canonical_order(&other, same).unwrap().topology
            );
        }
    }

    #[test]
    fn the_order_ignores_how_the_input_was_indexed() {
        let reversed: Vec<Index> = (0..8).rev().collect();
        assert_same_orders(&cube(), &reversed, 2);
    }

    mod properties {
        use proptest::prelude::*;

        use super::*;
        use crate::cut::{CutPlane, cut};

        proptest! {
            #[test]
            fn the_order_ignores_indexing_on_random_convex_solids(
                planes in proptest::collection::vec(
                    ((-0.4..0.4f64, -0.4..0.4f64, -0.4..0.4f64), (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)),
                    1..5,
                ),
                shuffle in proptest::collection::vec(any::<u32>(), 64),
                turn in 0usize..7,
            ) {
                let mut shape = cube();
                for ((x, y, z), (a, b, c)) in planes {
                    let plane = CutPlane::new(DVec3::new(x, y, z), DVec3::new(a, b, c));
                    if let Ok(parts) = cut(&shape, &plane) {
                        shape = if parts.below.shape.volume() >= parts.above.shape.volume() {
                            parts.below.shape
                        } else {
                            parts.above.shape
                        };
                    }
                }
                // Fisher–Yates with the drawn numbers.
                let n = shape.vertex_count();
                let mut permutation: Vec<Index> = (0..n as Index).collect();
                for i in (1..n).rev() {
                    permutation.swap(i, shuffle[i % shuffle.len()] as usize % (i + 1));
                }
                assert_same_orders(&shape, &permutation, turn);
            }
        }
    }

    #[test]
    fn different_shapes_have_different_topologies() {
        let tetra = Polyhedron::from_faces(
            vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
        .unwrap();
        let a = canonical_order(&tetra, Anchor::new(0, 0)).unwrap().topology;
        let b = canonical_order(&cube(), Anchor::new(0, 0))
            .unwrap()
            .topology;
        assert_ne!(a, b);
        assert_eq!(canonical_order(&tetra, Anchor::new(4, 0)), None);
        assert_eq!(canonical_order(&tetra, Anchor::new(0, 3)), None);
    }
}
