//! Implicit solids, CSG, morphing and procedural caves: the SG+M system of Zawadzki, Nikiel and
//! Warszawski ("Hybrid of shape grammar and morphing for procedural modeling of 3D caves").
//!
//! - [`Solid`]: expression trees over points of R³ with the paper's sign convention (positive
//!   inside, zero on the surface, negative outside), primitives, transforms, sum, difference,
//!   intersection, morphing and smooth variants.
//! - [`mesh`]: sparse, parallel marching cubes producing a closed, consistently oriented
//!   [`shapegram_geom::Mesh`].

pub mod bond;
pub mod cave;
pub mod error;
pub mod mesher;
pub mod metrics;
pub mod normals;
pub mod primitive;
pub mod rng;
pub mod shape;
pub mod solid;
pub mod table;
pub mod tape;
pub mod text;

pub use bond::{Bond, Label};
pub use cave::{Attach, Cave, CaveBuilder, CaveParams, Direction, Operation, generate, grow};
pub use error::{ImplicitError, Result};
pub use mesher::{Grid, MeshOptions, Meshing, mesh, mesh_until, mesh_with_progress};
pub use metrics::{Convexity, Metrics};
pub use normals::{surface_normals, surface_normals_with_progress};
pub use primitive::Primitive;
pub use shape::Shape;
pub use solid::{Node, Solid};
pub use text::{CaveProgram, TextError};
