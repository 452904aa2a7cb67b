//! Instancing in GLB: parts that repeat a prototype ([`Part::instance`]) become one glTF mesh
//! placed many times, by a node per use (each with its translation, rotation and scale) or by
//! one node with `EXT_mesh_gpu_instancing` (per-instance TRANSLATION, ROTATION and SCALE
//! accessors), as [`Instancing`] asks.
//!
//! A prototype is split by material: the uses of one prototype in one material share a mesh.
//! Parts bound to a skeleton are never instanced (they follow their joints), nor is a
//! prototype used once. Uses whose parts carry metadata keep a node each, which carries it:
//! per-instance metadata has no place in `EXT_mesh_gpu_instancing`.

use std::collections::BTreeMap;

use gltf_json as json;
use shapegram_geom::{DAffine3, InstanceSetKey, Model, Part};

use super::Builder;
use super::chunk::Chunk;

/// The glTF extension that draws one mesh at many transforms.
pub(crate) const GPU_INSTANCING: &str = "EXT_mesh_gpu_instancing";

/// How the GLB writer writes parts that repeat a prototype.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Instancing {
    /// Every part is written with its own vertices, as if it repeated nothing.
    None,
    /// One mesh per prototype (and material), used by a node per part.
    Nodes,
    /// One mesh per prototype (and material), drawn by one node with
    /// `EXT_mesh_gpu_instancing` (uses with metadata: a node each, as [`Instancing::Nodes`]).
    Gpu,
    /// Per prototype, whichever makes the smaller file: uses with metadata a node each; others
    /// GPU instancing when that saves bytes over writing each use's vertices, else flat.
    #[default]
    Auto,
}

/// The bytes of one GPU instance: translation, rotation and scale as f32.
const GPU_INSTANCE_BYTES: usize = 40;
/// The JSON of the three accessors, views and the node GPU instancing adds, roughly.
const GPU_SET_BYTES: usize = 600;

/// The uses of one prototype in one material.
pub(crate) struct InstanceSet {
    /// The prototype's geometry (its first use, moved back into the prototype's coordinates)
    /// with that use's material.
    pub prototype: Part,
    /// The model parts that use it, in model order.
    pub members: Vec<usize>,
    /// Drawn by one node with `EXT_mesh_gpu_instancing`; otherwise a node per member.
    pub gpu: bool,
}

/// The instanced parts of a model.
#[derive(Default)]
pub(crate) struct InstanceSets {
    pub sets: Vec<InstanceSet>,
    /// For each model part, the set it belongs to.
    of_part: Vec<Option<u32>>,
}

/// What a model part is in the written file.
pub(crate) enum Role {
    /// Written with its own vertices.
    Own,
    /// The first use of instance set `.0`, which writes its mesh.
    First(usize),
    /// A later use of an instance set, written by its first use.
    Repeat,
}

impl InstanceSets {
    /// The sets of `model` as `mode` asks, in order of first use.
    pub(crate) fn find(model: &Model, mode: Instancing) -> Self {
        if mode == Instancing::None || model.parts.iter().all(|p| p.instance.is_none()) {
            return Self::default();
        }
        let mut index: BTreeMap<InstanceSetKey, usize> = BTreeMap::new();
        let mut candidates: Vec<Vec<usize>> = Vec::new();
        for (i, part) in model.parts.iter().enumerate() {
            let Some(key) = InstanceSetKey::of_part(part).filter(|_| part.bone.is_none()) else {
                continue;
            };
            let set = *index.entry(key).or_insert_with(|| {
                candidates.push(Vec::new());
                candidates.len() - 1
            });
            candidates[set].push(i);
        }
        let mut sets = Vec::new();
        let mut of_part = vec![None; model.parts.len()];
        for members in candidates.into_iter().filter(|m| m.len() > 1) {
            let first = &model.parts[members[0]];
            let Some(prototype) = prototype(first) else {
                continue;
            };
            // A prototype that writes no triangles leaves its copies flat (they may write some).
            let Some(chunk) = Chunk::of_part(&prototype) else {
                continue;
            };
            let with_metadata = members.iter().any(|&m| model.parts[m].metadata.is_some());
            let gpu = match mode {
                Instancing::None => continue,
                Instancing::Nodes => false,
                Instancing::Gpu => !with_metadata,
                Instancing::Auto if with_metadata => false,
                Instancing::Auto if gpu_wins(&chunk, members.len()) => true,
                Instancing::Auto => continue,
            };
            for &m in &members {
                of_part[m] = Some(sets.len() as u32);
            }
            sets.push(InstanceSet {
                prototype,
                members,
                gpu,
            });
        }
        Self { sets, of_part }
    }

    /// What model part `part` is in the written file.
    pub(crate) fn role(&self, part: usize) -> Role {
        match self.of_part.get(part).copied().flatten() {
            None => Role::Own,
            Some(set) if self.sets[set as usize].members[0] == part => Role::First(set as usize),
            Some(_) => Role::Repeat,
        }
    }
}

/// Whether drawing `uses` copies of `chunk` by GPU instancing takes fewer bytes than writing
/// each copy's vertices and indices.
fn gpu_wins(chunk: &Chunk<'_>, uses: usize) -> bool {
    let vertex =
        24 + if chunk.has_uvs() { 8 } else { 0 } + if chunk.has_tangents() { 16 } else { 0 };
    let index = if chunk.vertex_count() >= usize::from(u16::MAX) {
        4
    } else {
        2
    };
    let copy = chunk.vertex_count() * vertex + chunk.index_count() * index;
    uses * copy > copy + GPU_SET_BYTES + uses * GPU_INSTANCE_BYTES
}

/// The prototype of an instanced part: its geometry in the prototype's coordinates, its
/// material; `None` when its transform cannot be inverted.
fn prototype(part: &Part) -> Option<Part> {
    let transform = part.instance?.transform;
    let inverse = transform.inverse();
    if !inverse.is_finite() {
        return None;
    }
    Some(Part {
        mesh: part.mesh.transformed(&inverse),
        normals: part
            .normals
            .iter()
            .map(|&n| (transform.matrix3.transpose() * n).normalize_or_zero())
            .collect(),
        metadata: None,
        instance: None,
        ..part.clone()
    })
}

/// A transform as glTF's translation, rotation (unit quaternion, xyzw) and scale, in f32.
pub(super) fn trs(transform: &DAffine3) -> ([f32; 3], [f32; 4], [f32; 3]) {
    let (scale, rotation, translation) = transform.to_scale_rotation_translation();
    let rotation = rotation.normalize();
    (
        translation.as_vec3().to_array(),
        rotation.as_quat().to_array(),
        scale.as_vec3().to_array(),
    )
}

/// A node of its own for one use of an instanced mesh: the part's name, transform and
/// metadata (see [`super::metadata_extras`]).
pub(super) fn use_node(mesh: json::Index<json::Mesh>, part: &Part) -> json::Node {
    let (translation, rotation, scale) = trs(&part.instance.expect("instanced").transform);
    json::Node {
        mesh: Some(mesh),
        name: Some(part.name.clone()),
        translation: Some(translation),
        rotation: Some(json::scene::UnitQuaternion(rotation)),
        scale: Some(scale),
        extras: part.metadata.as_deref().map(super::metadata_extras),
        ..Default::default()
    }
}

/// The node that draws `mesh` at every transform of `members` by `EXT_mesh_gpu_instancing`,
/// with the accessors of their translations, rotations and scales (written by [`gpu_data`]).
pub(super) fn gpu_node(
    builder: &mut Builder,
    mesh: json::Index<json::Mesh>,
    name: &str,
    uses: usize,
) -> json::Node {
    use json::accessor::{ComponentType, Type};
    let mut attribute = |kind| {
        let size = if kind == Type::Vec4 { 16 } else { 12 };
        builder.data_accessor(uses, size, None, (ComponentType::F32, kind), None)
    };
    let translation = attribute(Type::Vec3);
    let rotation = attribute(Type::Vec4);
    let scale = attribute(Type::Vec3);
    let attributes = serde_json::json!({
        "attributes": {
            "TRANSLATION": translation.value(),
            "ROTATION": rotation.value(),
            "SCALE": scale.value(),
        }
    });
    if !builder
        .root
        .extensions_used
        .iter()
        .any(|e| e == GPU_INSTANCING)
    {
        builder.root.extensions_used.push(GPU_INSTANCING.to_owned());
    }
    json::Node {
        mesh: Some(mesh),
        name: Some(name.to_owned()),
        extensions: Some(json::extensions::scene::Node {
            others: serde_json::Map::from_iter([(GPU_INSTANCING.to_owned(), attributes)]),
        }),
        ..Default::default()
    }
}

/// The data of [`gpu_node`]'s accessors: every use's translation, then every rotation, then
/// every scale, as little-endian f32.
pub(super) fn gpu_data(uses: &[&Part], mut put: impl FnMut(&[u8])) {
    let placed: Vec<_> = uses
        .iter()
        .map(|part| trs(&part.instance.expect("instanced").transform))
        .collect();
    let mut floats = |values: &[f32]| {
        for v in values {
            put(&v.to_le_bytes());
        }
    };
    placed.iter().for_each(|(t, _, _)| floats(t));
    placed.iter().for_each(|(_, r, _)| floats(r));
    placed.iter().for_each(|(_, _, s)| floats(s));
}
