//! The geometry kernel of Shapegram.
//!
//! Everything here is `f64` and free of I/O: oriented [`Scope`]s, polygon [`Mesh`]es whose faces are
//! vertex loops, [`primitives`], plane cuts with capping ([`split`]), extrusion, inset, component
//! extraction and face classification ([`component`]), roofs ([`roof`]), occlusion tests
//! ([`occlusion`]) with a bounding-volume hierarchy ([`bvh`]), offsets of convex and
//! non-convex polygons ([`offset`]), fitting assets into scopes ([`fit`]), taper, twist and shear
//! ([`deform`]), convex pieces ([`convex`]), largest inner rectangles ([`inner_rectangle`]),
//! envelopes ([`envelope`]), perimeter splits ([`perimeter`]), clean-up ([`cleanup`]), footprints ([`footprint`]) and random points ([`scatter`]) of meshes,
//! triangulation and mesh metrics.
//!
//! Conventions shared by every crate of the workspace:
//! - y is up in world space (the glTF convention); lots and footprints lie in the xz-plane facing +y.
//! - Faces are counter-clockwise when seen from outside, so Newell normals point outward.
//! - A [`Scope`] is an oriented box with its origin at a corner; local coordinates run from 0 to
//!   `size` along each axis, and primitives are built to fill the box `[0, size]`.

pub mod aabb;
pub mod bvh;
pub mod cleanup;
pub mod component;
pub mod convex;
pub mod deform;
pub mod envelope;
pub mod extrude;
pub mod fit;
pub mod footprint;
pub mod inner_rectangle;
pub mod material;
mod merge;
pub mod mesh;
pub mod model;
pub mod occlusion;
pub mod offset;
pub mod perimeter;
mod planar;
pub mod plane;
pub mod primitives;
pub mod rectangle;
pub mod roof;
pub mod scatter;
pub mod scope;
pub mod shape_metrics;
mod skeleton;
pub mod split;
pub mod topology;
pub mod triangulate;

pub use aabb::Aabb;
pub use bvh::Bvh;
pub use component::{Component, ComponentKind, FaceClass};
pub use glam::{DAffine3, DMat3, DQuat, DVec2, DVec3};
pub use material::{AlphaMode, Finish, MapTransform, Maps, Surface, SurfaceKey};
pub use mesh::Mesh;
pub use model::{
    Bone, Color, Instance, InstanceSetKey, Lines, MetaValue, Metadata, Model, Part, Texture,
};
pub use plane::Plane;
pub use scope::{Pivot, Scope};
pub use shapegram_kinematics as kinematics;
pub use topology::EdgeReport;

/// Relative tolerance used to decide that a point lies on a plane or that two points coincide.
///
/// It is scaled by the size of the geometry at hand (see [`Aabb::tolerance`]), so models in
/// millimetres and in kilometres behave alike.
pub const RELATIVE_EPSILON: f64 = 1e-9;
