//! Binary glTF 2.0 (GLB) writer: `gltf-json` types serialised by serde_json, framed by hand.
//!
//! Layout: one root node "shapegram" (scene 0) whose children carry the meshes. A flat part (no
//! `normals`) gives every face its own vertices, shared by the face's triangles, with the face
//! normal; a smooth part keeps its shared vertices with their normals; a line set becomes a
//! LINES primitive of its points (POSITION only). Each primitive is then compacted (see
//! [`compact`]): coplanar rectangles merged, flat faces' normals dropped (readers compute them,
//! as glTF requires) unless [`FlatNormals::Written`] asks for them, vertices equal in every
//! attribute left shared, triangles in vertex-cache order. Flat and smooth parts of one
//! material then go into primitives of their own, since only the smooth ones have normals. Each accessor has its own buffer view, 4-byte aligned, in one buffer;
//! [`GlbEncoding`] picks floats, KHR_mesh_quantization (see [`quantize`]; the mesh node's
//! translation and scale undo it) or that compressed with EXT_meshopt_compression (see
//! [`compress`]; the views then lie in a fallback buffer without data).
//!
//! Skeletons become glTF skins (see [`skin`]): parts with a [`Part::bone`] go into meshes of
//! their own per skin (merged: one mesh node per skin, one primitive per material; grouped: one
//! node per part), on nodes that carry `skin` and no transformation and are scene roots beside
//! "shapegram" (the validator warns about skinned mesh nodes with a parent). Their vertices
//! stay in the rest pose, as the model holds them, and follow their section's joint rigidly:
//! `JOINTS_0` = [joint, 0, 0, 0] (u8 up to 256 joints, u16 beyond) and `WEIGHTS_0` =
//! [1, 0, 0, 0] as normalized u8. The joint nodes carry the current pose, so viewers show the
//! model posed. Models without bound parts are written exactly as before skins existed.
//! A skeleton's named poses become one-keyframe animations of its free joints (see
//! [`animation`]), after the skins; without named poses there is no `animations`.
//!
//! Parts that repeat a prototype ([`Part::instance`]) become one mesh per prototype and
//! material, placed by a node per part or by `EXT_mesh_gpu_instancing`, as
//! [`ExportOptions::instancing`] asks (see [`instance`]).
//!
//! A part whose [`Metadata`] names its lot hangs under a node of that lot, a child of
//! "shapegram" without a mesh that carries the lot's metadata (see [`metadata`]).
//!
//! [`write_glb_with_features_to`] numbers features instead (a 3D Tiles tile's lots): each
//! vertex carries its part's feature id, part of its identity in compaction, and the file a
//! property table with a row per feature (see [`features`]).
//!
//! The file is planned first (the compacted vertices of every primitive, their accessors, the
//! JSON chunk) and then streamed: each accessor's bytes are encoded from the compacted vertices
//! as they are written (compressed ones excepted, see [`streams`]); each primitive's data from
//! the model is let go once compacted. A smooth part alone in its primitive with positions and
//! normals only (an L-system tube) is not compacted: its accessors are encoded from the
//! model's f64 vertices, rounded as they are read (see [`triples`]), without an f32 copy.
//! Planning runs on rayon's threads (the parts' data, the
//! meshes, a mesh's primitives, the pieces of its vertex pool); every result is made as on one
//! thread and kept in order, so the bytes are the same on any number of threads.
//!
//! [`plan`] gathers the parts into meshes and primitives and compacts them; [`document`] makes
//! the JSON chunk; this module keeps the entry points.

use std::io::{self, Write};

use shapegram_geom::{Model, Part};

use crate::ExportOptions;
use crate::flat::FaceSplitter;

mod aligned;
mod animation;
mod chunk;
mod compact;
pub(crate) mod compress;
mod coplanar;
mod document;
mod features;
mod instance;
mod material;
mod metadata;
mod plan;
mod pool;
mod quantize;
mod skin;
mod streams;
mod tangents;
mod triples;

pub(crate) use chunk::{Chunk, gltf_uv};
use compact::Compaction;
use document::Builder;
pub use features::Features;
pub(crate) use instance::GPU_INSTANCING;
use instance::InstanceSets;
pub use instance::Instancing;
use metadata::metadata_extras;
use plan::{Plan, Primitive};

/// GLB framing constants from the glTF 2.0 specification, section "Binary glTF Layout".
pub(crate) const MAGIC: &[u8; 4] = b"glTF";
pub(crate) const CHUNK_JSON: u32 = 0x4E4F_534A;
pub(crate) const CHUNK_BIN: u32 = 0x004E_4942;

/// The model as GLB bytes; see the module docs for the layout.
///
/// # Panics
/// On the errors [`write_glb_to`] reports: a file over 4 GiB, or skeletons that cannot be
/// written.
pub fn write_glb(model: &Model, options: &ExportOptions) -> Vec<u8> {
    let sets = InstanceSets::find(model, options.instancing);
    let written = Plan::new(model, &sets, options, REORDER, None).and_then(|plan| {
        let mut out = Vec::with_capacity(plan.len());
        plan.write(&mut out).map(|()| out)
    });
    written.unwrap_or_else(|e| panic!("{e}"))
}

/// Writes the model as GLB to `out` without building the file in memory (see [`write_glb`]).
/// Wrap files in a `BufWriter`: the data goes out in pieces of a dozen bytes. These are
/// `InvalidInput` errors, found before anything is written: a file over the 4 GiB that GLB
/// lengths can express, a part whose bone names a section the model does not have, and a
/// skeleton with bound parts that is no tree or has more than 65,536 sections.
pub fn write_glb_to(
    model: &Model,
    options: &ExportOptions,
    out: &mut impl Write,
) -> io::Result<()> {
    let sets = InstanceSets::find(model, options.instancing);
    Plan::new(model, &sets, options, REORDER, None)?.write(out)
}

/// [`write_glb_to`] with `features`: every primitive's vertices carry their part's (or line
/// set's) feature id (`EXT_mesh_features`) and the file a property table of the features'
/// metadata (`EXT_structural_metadata`), as `docs/tiles.md` ("Metadata") describes. Parts are
/// not instanced (a prototype would be shared by features).
///
/// # Panics
/// When `features` has no feature id for some part or line set of the model.
pub fn write_glb_with_features_to(
    model: &Model,
    options: &ExportOptions,
    features: &Features<'_>,
    out: &mut impl Write,
) -> io::Result<()> {
    let sets = InstanceSets::find(model, Instancing::None);
    Plan::new(model, &sets, options, REORDER, Some(features))?.write(out)
}

/// What the writers may do to a primitive's triangles unless a caller needs to trace them.
const REORDER: Compaction = Compaction { reorder: true };

/// Which model parts each primitive of a GLB holds: by glTF mesh, by primitive, the parts
/// whose triangles (or line sets' segments: `None`) it concatenates, in order. An instanced
/// mesh names the first part that uses it, whose triangles it holds in the prototype's
/// coordinates.
pub type GlbLayout = Vec<Vec<Vec<Option<usize>>>>;

/// [`write_glb_to`], returning which model parts each primitive holds. With
/// [`face_triangles`] this tells which triangles of a primitive came from which faces of the
/// model: this writer keeps every triangle, in face order (vertices are still shared, but no
/// faces are merged and no triangles reordered).
pub fn write_glb_with_layout(
    model: &Model,
    options: &ExportOptions,
    out: &mut impl Write,
) -> io::Result<GlbLayout> {
    let sets = InstanceSets::find(model, options.instancing);
    let plan = Plan::new(model, &sets, options, Compaction { reorder: false }, None)?;
    plan.write(out)?;
    Ok(plan
        .groups
        .iter()
        .map(|group| group.primitives.iter().map(|p| p.sources.clone()).collect())
        .collect())
}

/// How many triangles the GLB writer writes for each face of `part`, in face order: 0 for a
/// face without area or with corners not finite in f32; otherwise its triangles that keep
/// their area in f32. A part's triangles in a primitive are its faces' triangles in face order.
pub fn face_triangles(part: &Part) -> Vec<u32> {
    let mesh = &part.mesh;
    let mut splitter = FaceSplitter::default();
    let mut fan = Vec::new();
    (0..mesh.face_count())
        .map(|i| {
            fan.clear();
            splitter.split(mesh, i, &mut fan);
            fan.len() as u32
        })
        .collect()
}
