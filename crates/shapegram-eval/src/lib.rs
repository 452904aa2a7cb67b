//! The derivation engine of Shapegram: compiles a parsed grammar into a [`Program`] and derives
//! models from it.
//!
//! ```text
//! grammar text ──parse──▶ ast::Grammar ──Program::compile──▶ Program ──derive──▶ Derivation
//! ```
//!
//! A derivation is deterministic: the same program, initial shapes, seed and attribute values give
//! the same leaves, in the same order, whatever the number of threads (see [`rng`]).

mod annotations;
mod arrays;
mod asset_faces;
pub mod asset_look;
mod asset_queries;
mod booleans;
mod builtins;
mod color_ramps;
mod colors;
mod context;
mod convert;
mod engine;
mod error;
mod expr;
mod face_sets;
mod fingerprint;
mod goals;
mod imports;
mod library;
mod named_poses;
mod ops;
mod program;
mod reports;
pub mod rng;
mod rule_keys;
mod selectors;
mod shape;
mod snapshot;
mod solids;
mod tables;
mod tag_queries;
pub mod tags;
mod text;
pub mod texturing;
mod trim;
mod uv_queries;
mod value;

pub use annotations::{AttrAnnotations, AttrRange, Unit, attr_annotations};
pub use builtins::{functions, queries};
pub use engine::{
    ASSET_VARIANTS, Asset, AssetLoader, AssetNaming, AttrValue, Derivation, DeriveControl,
    DeriveOptions, InitialShape, InstanceCandidates, Leaf, LeafFaces, MetadataScope, ModelOptions,
    Paint, PaintId, Rederivation, Stats, Symbol, Trace, TreeNode, attr_values, derive,
    derive_again,
};
pub use error::DeriveError;
pub use goals::{GoalQuery, LeafSemantics};
pub use imports::ImportGraph;
pub use library::LibraryOptions;
pub use ops::{Support, operations};
pub use program::{Program, RuleId, Sym};
pub use reports::summarise_reports;
pub use rule_keys::RuleKeys;
pub use shape::{Csg, CsgOp, Geometry, Implicit};
pub use value::Value;
