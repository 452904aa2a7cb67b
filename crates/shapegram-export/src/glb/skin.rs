//! Kinematic skeletons as glTF skins: per skeleton an "Armature" node with the joint nodes
//! under it, the skin, and its inverse bind matrices.
//!
//! Joint nodes carry the posed transformation relative to their parent
//! ([`Skeleton::local`]), the inverse bind matrices the rest pose (`rest⁻¹`), and each joint's
//! limits, pose and rest transformation go into its `extras` under `shapegram.joint`. The
//! layout and the schema are documented in `docs/kinematics.md`.

use std::collections::{BTreeMap, BTreeSet};
use std::io;

use gltf_json as json;
use serde_json::json;
use shapegram_geom::kinematics::{Frame, Range, Section, SectionId, Skeleton};

/// Most joints a skin can address: `JOINTS_0` holds u16 indices at best.
const MAX_JOINTS: usize = 1 << 16;

/// Most joints whose indices fit the u8 form of `JOINTS_0`.
const MAX_NARROW_JOINTS: usize = 1 << 8;

/// Longest joint name in bytes: Blender keeps 63 bytes of a bone's name.
const MAX_NAME_LEN: usize = 63;

/// One skeleton about to be written as a skin.
pub(super) struct Skin<'a> {
    skeleton: &'a Skeleton,
    /// The skeleton's index in the model, which numbers its names.
    index: usize,
    /// Sections in joint order: parents before children.
    order: Vec<SectionId>,
    /// Joint index by section index.
    joint_of: Vec<u16>,
    /// Joint names, in joint order.
    names: Vec<String>,
}

impl<'a> Skin<'a> {
    /// The skin of model skeleton `index`; an error when the skeleton is no tree or has more
    /// sections than a skin can address.
    pub fn new(skeleton: &'a Skeleton, index: usize) -> io::Result<Self> {
        let invalid = |message: String| io::Error::new(io::ErrorKind::InvalidInput, message);
        if skeleton.len() > MAX_JOINTS {
            return Err(invalid(format!(
                "skeleton {index} has {} sections, more than the {MAX_JOINTS} joints a glTF skin can address",
                skeleton.len()
            )));
        }
        if !skeleton.is_tree() {
            return Err(invalid(format!(
                "skeleton {index} is not one tree of sections"
            )));
        }
        let order = skeleton.order();
        let mut joint_of = vec![0; skeleton.len()];
        for (joint, id) in order.iter().enumerate() {
            joint_of[id.index()] = joint as u16;
        }
        let names = unique_names(
            order
                .iter()
                .map(|&id| skeleton.section(id).name().to_string()),
        );
        Ok(Self {
            skeleton,
            index,
            order,
            joint_of,
            names,
        })
    }

    /// The skeleton this skin writes.
    pub fn skeleton(&self) -> &'a Skeleton {
        self.skeleton
    }

    /// Sections in joint order: parents before children.
    pub fn order(&self) -> &[SectionId] {
        &self.order
    }

    /// The joint index of a section.
    pub fn joint(&self, section: SectionId) -> u16 {
        self.joint_of[section.index()]
    }

    /// Whether `JOINTS_0` needs u16 components (more joints than u8 can number).
    pub fn wide(&self) -> bool {
        self.order.len() > MAX_NARROW_JOINTS
    }

    /// The name of the skin and its armature node: "Armature", then "Armature.001"… by
    /// skeleton index, as Blender numbers duplicates.
    pub fn armature_name(&self) -> String {
        numbered("Armature", self.index)
    }

    /// The name of the merged mesh node that this skin deforms: "skinned", "skinned.001"….
    pub fn mesh_name(&self) -> String {
        numbered("skinned", self.index)
    }

    /// Adds the armature node, the joint nodes under it and the inverse bind matrices'
    /// accessor (its data comes after everything added before), then the skin; returns the
    /// armature node, a child of the root, and the joint nodes in joint order.
    pub fn push(
        &self,
        builder: &mut super::Builder,
    ) -> (json::Index<json::Node>, Vec<json::Index<json::Node>>) {
        let armature = builder.root.push(json::Node {
            name: Some(self.armature_name()),
            ..Default::default()
        });
        // Parents come before children in `order`, so each joint's node index is known by the
        // time its children are added.
        let mut nodes: Vec<json::Index<json::Node>> = Vec::with_capacity(self.order.len());
        for (&id, name) in self.order.iter().zip(&self.names) {
            let section = self.skeleton.section(id);
            let (translation, rotation) = trs(&self.skeleton.local(id));
            let node = builder.root.push(json::Node {
                name: Some(name.clone()),
                translation,
                rotation,
                extras: Some(joint_extras(section, &self.skeleton.joint(id))),
                ..Default::default()
            });
            let parent = match section.parent() {
                Some(parent) => nodes[usize::from(self.joint(parent))],
                None => armature,
            };
            builder.root.nodes[parent.value()]
                .children
                .get_or_insert_with(Vec::new)
                .push(node);
            nodes.push(node);
        }
        let matrices = builder.data_accessor(
            self.order.len(),
            64,
            None,
            (
                json::accessor::ComponentType::F32,
                json::accessor::Type::Mat4,
            ),
            None,
        );
        builder.root.push(json::Skin {
            extensions: None,
            extras: Default::default(),
            inverse_bind_matrices: Some(matrices),
            joints: nodes.clone(),
            name: Some(self.armature_name()),
            skeleton: Some(armature),
        });
        (armature, nodes)
    }

    /// Calls `visit` with each joint's inverse bind matrix, in joint order.
    pub fn inverse_bind_matrices(&self, mut visit: impl FnMut([f32; 16])) {
        for &id in &self.order {
            visit(inverse_bind_matrix(&self.skeleton.section(id).rest()));
        }
    }
}

/// `base`, or `base.001`… for later indices.
fn numbered(base: &str, index: usize) -> String {
    if index == 0 {
        base.to_owned()
    } else {
        format!("{base}.{index:03}")
    }
}

/// A section name as a joint name that Blender, Godot and three.js all keep as it is: ASCII
/// letters, digits, `_`, `-` and `.`, every other character replaced by `_` (so no `/` or `:`,
/// which Godot rewrites), at most 63 bytes, "joint" when empty.
fn joint_name(name: &str) -> String {
    let mut clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .take(MAX_NAME_LEN)
        .collect();
    if clean.is_empty() {
        clean.push_str("joint");
    }
    clean
}

/// Joint names made unique in order: a name already taken gets `_2`, `_3`… (the name cut short
/// to leave room), the first keeps it as it is.
fn unique_names(names: impl Iterator<Item = String>) -> Vec<String> {
    let mut taken = BTreeSet::new();
    // The next suffix to try per name, so that many equal names take linear time.
    let mut next: BTreeMap<String, usize> = BTreeMap::new();
    names
        .map(|name| {
            let base = joint_name(&name);
            if taken.insert(base.clone()) {
                return base;
            }
            let n = next.entry(base.clone()).or_insert(2);
            loop {
                let suffix = format!("_{n}");
                *n += 1;
                // The name is ASCII, so any byte length is a character boundary.
                let keep = base.len().min(MAX_NAME_LEN - suffix.len());
                let unique = format!("{}{suffix}", &base[..keep]);
                if taken.insert(unique.clone()) {
                    return unique;
                }
            }
        })
        .collect()
}

/// A joint's transformation as an f32 translation and unit quaternion (x, y, z, w), as joint
/// nodes and pose keyframes write it.
pub(super) fn f32_trs(frame: &Frame) -> ([f32; 3], [f32; 4]) {
    // `+ 0.0` turns -0 into 0, so equal transformations print the same.
    let translation = frame.translation.as_vec3().to_array().map(|x| x + 0.0);
    let rotation = frame
        .rotation
        .normalize()
        .as_quat()
        .to_array()
        .map(|x| x + 0.0);
    (translation, rotation)
}

/// A joint node's translation and rotation in f32, each left out when it is the identity.
fn trs(frame: &Frame) -> (Option<[f32; 3]>, Option<json::scene::UnitQuaternion>) {
    let (translation, rotation) = f32_trs(frame);
    (
        (translation != [0.0; 3]).then_some(translation),
        (rotation != [0.0, 0.0, 0.0, 1.0]).then_some(json::scene::UnitQuaternion(rotation)),
    )
}

/// The inverse of a rest frame as a column-major f32 matrix whose last row is exactly
/// 0, 0, 0, 1, as the validator requires of inverse bind matrices.
fn inverse_bind_matrix(rest: &Frame) -> [f32; 16] {
    let inverse = rest.inverse().to_affine();
    let m = inverse.matrix3;
    let t = inverse.translation;
    [
        m.x_axis.x, m.x_axis.y, m.x_axis.z, 0.0, //
        m.y_axis.x, m.y_axis.y, m.y_axis.z, 0.0, //
        m.z_axis.x, m.z_axis.y, m.z_axis.z, 0.0, //
        t.x, t.y, t.z, 1.0,
    ]
    .map(|x| x as f32 + 0.0)
}

/// The joint's metadata, read by the studio and the Blender and Godot runtimes: the section's
/// own name, its rest transformation relative to its parent, its limits and its pose. Keys and
/// units are documented in `docs/kinematics.md` and stay stable.
fn joint_extras(section: Section<'_>, rest: &Frame) -> Box<json::extras::RawValue> {
    let tidy = |x: f64| x + 0.0;
    let ranges = |r: &[Range; 3]| r.map(|r| [tidy(r.min), tidy(r.max)]);
    let value = json!({
        "shapegram": {
            "joint": {
                "section": section.name().to_string(),
                "rest_translation_m": rest.translation.to_array().map(tidy),
                "rest_rotation_xyzw": rest.rotation.to_array().map(tidy),
                "rotation_limits_deg": ranges(&section.limits().rotation),
                "translation_limits_m": ranges(&section.limits().translation),
                "pose_rotation_deg": section.pose().rotation.to_array().map(tidy),
                "pose_translation_m": section.pose().translation.to_array().map(tidy),
            }
        }
    });
    serde_json::value::to_raw_value(&value).expect("a JSON value always serialises")
}
