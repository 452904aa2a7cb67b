//! The topological split grammar of the Shape Grammar Editor (Plans): convex polyhedra in a
//! half-edge structure, plane cuts that remember how they made each vertex, anchors and the
//! canonical vertex order, symbols and rules as cut trees, the compiler to a lean [`Grammar`],
//! the generation-by-generation interpreter and the editor's project model.

pub mod anchor;
pub mod cut;
pub mod polyhedron;

pub use anchor::{Anchor, CanonicalOrder, Topology, all_anchors, canonical_order};
pub use cut::{Cut, CutError, CutPlane, Part, VertexSource, cut};
pub use polyhedron::{Index, Polyhedron, PolyhedronError};
