//! The topological split grammar of the Shape Grammar Editor (Plans): convex polyhedra in a
//! half-edge structure, plane cuts that remember how they made each vertex, anchors and the
//! canonical vertex order, symbols and rules as cut trees with an authoring API and undo, the
//! compiler to a lean [`Grammar`] and its `.grammar` file, the generation-by-generation
//! interpreter, triangle meshes (with tiled materials) for export, and project files.
//!
//! ```
//! use shapegram_topo::{Assignment, GrammarMesh, GrammarState, Project, compile};
//! use shapegram_geom::DVec3;
//!
//! let mut project = Project::new();
//! let a = project.add_box_symbol("A", DVec3::new(4.0, 1.0, 4.0)).unwrap();
//! let rule = project.add_rule(a, "halve", 1.0).unwrap();
//! // Cut a 0.25 slice off the top face (face 3) and drop it.
//! let [slice, _rest] = project.face_cut(rule, 0, 3, 0.25).unwrap();
//! project.assign(rule, slice, Assignment::Epsilon).unwrap();
//! let grammar = compile(&project).unwrap();
//! let mut state = GrammarState::new(&grammar, "A").unwrap().with_generations(1);
//! state.generate_all().unwrap();
//! assert_eq!(state.terminals().len(), 1);
//! assert_eq!(GrammarMesh::new(&state).triangle_count(), 12);
//! ```

pub mod anchor;
pub mod compile;
pub mod cut;
pub mod demos;
pub mod editor;
pub mod grammar;
mod grammar_file;
pub mod interpret;
mod json;
pub mod material;
pub mod mesh;
pub mod polyhedron;
pub mod project;
mod project_file;
mod rng;
mod tools;

pub use anchor::{Anchor, CanonicalOrder, Topology, all_anchors, canonical_order};
pub use compile::{CompileError, compile};
pub use cut::{Cut, CutError, CutPlane, Part, VertexSource, cut};
pub use editor::Editor;
pub use grammar::{
    GRAMMAR_FORMAT, GRAMMAR_VERSION, GRAMMAR_VERSION_PLAIN, Grammar, GrammarError, GrammarRule,
    GrammarShape, GrammarSymbol, OffsetCut, SubShape, VirtualVertex,
};
pub use interpret::{
    DEFAULT_MAX_SHAPES, DEFAULT_MAX_VERTICES, GenerateError, GrammarState, SEED_MASK, ShapeList,
};
pub use material::{Material, face_axes, planar_uv};
pub use mesh::{GrammarMesh, MeshPart};
pub use polyhedron::{Index, Polyhedron, PolyhedronError};
pub use project::{
    Assignment, EditError, FaceOffset, Node, NodeId, NodeKind, Project, Rule, RuleTree, Symbol,
};
pub use project_file::{PROJECT_FORMAT, PROJECT_VERSION, ProjectError};
