//! Kinematic skeletons (Ilčík, Fiedler, Purgathofer and Wimmer, "Procedural Skeletons:
//! Kinematic Extensions to CGA-Shape Grammars"): a tree of rigid *sections*, each joined to its
//! parent by a *joint* with per-axis *limits* and a current *pose*.
//!
//! The skeleton is plain data with its transforms, so the engine can build it while a grammar
//! derives and the exporters can write it as a glTF skin without depending on the engine.
//!
//! Sections are kept by their *rest frame* in model space: where the joint sits and how it is
//! oriented when every pose is zero. A joint, relative to its parent as the paper defines it,
//! is derived from the two rest frames, so moving a joint (the paper's joint placement rule) or
//! handing children to another section (the sequential split) never moves anything else:
//! the compensation Lemma 4.8 asks for is implicit. Geometry is derived in the rest pose; a
//! posed point is `posed(s) · rest(s)⁻¹ · p` for the section `s` it is attached to, which is
//! rigid skinning with `rest(s)⁻¹` as the inverse bind matrix.

mod frame;
mod limits;
mod name;
mod skeleton;

pub use frame::Frame;
pub use limits::{Axis, Clamped, KinematicError, Limits, Pose, Range};
pub use name::{Name, NameKey, Names, SectionName, Tagged};
pub use skeleton::{Children, NamedPose, Parts, Section, SectionId, Skeleton};
