//! A skeleton's named poses as glTF animations: one animation per pose name, named after it,
//! with one keyframe (time 0, LINEAR) per free joint of every skin whose skeleton has that
//! pose — a translation and a rotation channel on the joint node, whose values are the joint's
//! local transformation in the pose ([`Skeleton::local_in`]).
//!
//! Like the skins, the JSON is declared first ([`Animation::push`]) and the data streamed later
//! in the same order ([`Animation::data`]): the input time, then per channel pair the
//! translation and the rotation, each in a buffer view of its own.

use gltf_json as json;
use json::validation::Checked::Valid;

use super::skin::{Skin, f32_trs};

/// One named pose about to be written as an animation.
pub(super) struct Animation {
    name: String,
    /// Per free joint: its skin, its joint index, and its translation and rotation in the pose.
    keys: Vec<Key>,
}

/// One joint's keyframe.
struct Key {
    skin: usize,
    joint: u16,
    translation: [f32; 3],
    rotation: [f32; 4],
}

impl Animation {
    /// The animations of the skins' named poses, by name in order of first appearance (skin by
    /// skin); names whose skins have no free joint make none (an animation needs a channel).
    pub fn of_skins(skins: &[Skin<'_>]) -> Vec<Self> {
        let mut names: Vec<&str> = Vec::new();
        for skin in skins {
            for named in skin.skeleton().named_poses() {
                if !names.contains(&named.name.as_str()) {
                    names.push(&named.name);
                }
            }
        }
        names
            .into_iter()
            .map(|name| {
                let mut keys = Vec::new();
                for (index, skin) in skins.iter().enumerate() {
                    let skeleton = skin.skeleton();
                    let Some(named) = skeleton.named_pose(name) else {
                        continue;
                    };
                    for &id in skin.order() {
                        if !skeleton.section(id).limits().is_free() {
                            continue;
                        }
                        let (translation, rotation) =
                            f32_trs(&skeleton.local_in(id, &named.pose(id)));
                        keys.push(Key {
                            skin: index,
                            joint: skin.joint(id),
                            translation,
                            rotation,
                        });
                    }
                }
                Self {
                    name: name.to_owned(),
                    keys,
                }
            })
            .filter(|a| !a.keys.is_empty())
            .collect()
    }

    /// Adds the animation and its accessors (their data comes after everything added before);
    /// `joints` holds each skin's joint nodes in joint order.
    pub fn push(&self, builder: &mut super::Builder, joints: &[Vec<json::Index<json::Node>>]) {
        use json::accessor::{ComponentType, Type};
        let input = builder.data_accessor(
            1,
            4,
            None,
            (ComponentType::F32, Type::Scalar),
            Some((serde_json::json!([0.0]), serde_json::json!([0.0]))),
        );
        let mut samplers = Vec::with_capacity(2 * self.keys.len());
        let mut channels = Vec::with_capacity(2 * self.keys.len());
        for key in &self.keys {
            let node = joints[key.skin][usize::from(key.joint)];
            for (size, kind, path) in [
                (12, Type::Vec3, json::animation::Property::Translation),
                (16, Type::Vec4, json::animation::Property::Rotation),
            ] {
                let output = builder.data_accessor(1, size, None, (ComponentType::F32, kind), None);
                let sampler = json::Index::new(samplers.len() as u32);
                samplers.push(json::animation::Sampler {
                    extensions: None,
                    extras: Default::default(),
                    input,
                    interpolation: Valid(json::animation::Interpolation::Linear),
                    output,
                });
                channels.push(json::animation::Channel {
                    sampler,
                    target: json::animation::Target {
                        extensions: None,
                        extras: Default::default(),
                        node,
                        path: Valid(path),
                    },
                    extensions: None,
                    extras: Default::default(),
                });
            }
        }
        builder.root.push(json::Animation {
            extensions: None,
            extras: Default::default(),
            channels,
            name: Some(self.name.clone()),
            samplers,
        });
    }

    /// Calls `visit` with the animation's data as f32 values, in the order [`Animation::push`]
    /// declared its accessors: the time 0, then each joint's translation and rotation.
    pub fn data(&self, mut visit: impl FnMut(&[f32])) {
        visit(&[0.0]);
        for key in &self.keys {
            visit(&key.translation);
            visit(&key.rotation);
        }
    }
}
