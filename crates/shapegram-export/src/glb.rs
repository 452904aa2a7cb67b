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
//! The file is planned first (the compacted vertices of every primitive, their accessors, the
//! JSON chunk) and then streamed: each accessor's bytes are encoded from the compacted vertices
//! as they are written (compressed ones excepted, see [`streams`]); each primitive's data from
//! the model is let go once compacted. A smooth part alone in its primitive with positions and
//! normals only (an L-system tube) is not compacted: its accessors are encoded from the
//! model's f64 vertices, rounded as they are read (see [`triples`]), without an f32 copy.
//! Planning runs on rayon's threads (the parts' data, the
//! meshes, a mesh's primitives, the pieces of its vertex pool); every result is made as on one
//! thread and kept in order, so the bytes are the same on any number of threads.

use std::collections::BTreeMap;
use std::io::{self, Write};

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use rayon::prelude::*;
use shapegram_geom::{Color, Metadata, Model, Part, Texture};

use crate::flat::{FaceSplitter, Palette, check_bones, drawable};
use crate::{ExportOptions, FlatNormals, GlbEncoding};

mod aligned;
mod animation;
mod chunk;
mod compact;
pub(crate) mod compress;
mod coplanar;
mod instance;
mod material;
mod metadata;
mod pool;
mod quantize;
mod skin;
mod streams;
mod tangents;
mod triples;

use animation::Animation;
pub(crate) use chunk::{Chunk, gltf_uv};
use compact::{Compaction, Run, Vertices, View};
pub(crate) use instance::GPU_INSTANCING;
pub use instance::Instancing;
use instance::{InstanceSets, Role};
use material::{gltf_textures, material, textured, with_surface};
use metadata::{LotNodes, metadata_extras};
use quantize::Grid;
use skin::Skin;
use streams::{Joints, Stream, index_stream, position_stream, streams};
use triples::Triples;

/// GLB framing constants from the glTF 2.0 specification, section "Binary glTF Layout".
pub(crate) const MAGIC: &[u8; 4] = b"glTF";
pub(crate) const CHUNK_JSON: u32 = 0x4E4F_534A;
pub(crate) const CHUNK_BIN: u32 = 0x004E_4942;

/// One glTF primitive to be: its material, its mode, its skinning and the chunks whose data it
/// concatenates.
struct Primitive<'a> {
    material: usize,
    lines: bool,
    /// Whether its vertices carry uvs (TEXCOORD_0): its material is textured.
    textured: bool,
    /// Whether its vertices carry tangents: its material has a normal map.
    tangents: bool,
    /// Whether its vertices carry normals (NORMAL): its parts are smooth or normal-mapped, or
    /// flat normals are asked for ([`FlatNormals::Written`]).
    normals: bool,
    skinned: Option<Skinned>,
    /// The data of the model's parts, until [`Plan::new`] has compacted them into `streams`.
    chunks: Vec<Chunk<'a>>,
    /// The model part each chunk holds (`None`: a line set).
    sources: Vec<Option<usize>>,
    /// Its vertices compacted, from which its streams' data is made as the file is written
    /// (none when they went into its mesh's pool).
    vertices: Vertices<'a>,
    /// The glTF primitives it becomes: one, or several of fewer than 65,535 vertices each.
    runs: Vec<Run>,
    /// Each run's accessors, in the order they are written.
    streams: Vec<Vec<Stream>>,
}

impl Primitive<'_> {
    /// Whether its vertices are positions and nothing else, which primitives of other
    /// materials can share (see [`pool`]).
    fn is_bare(&self) -> bool {
        !self.lines && !self.textured && !self.tangents && !self.normals && self.skinned.is_none()
    }
}

/// One piece of a mesh's vertex pool, encoded: the POSITION data its primitives share and, per
/// primitive of the mesh with triangles in it, the primitive's index and those indices. Pieces
/// are small and their u16 indices take half the memory of the pool's, so their data is made
/// when planned rather than as written (see [`Stream::encode`]).
struct PooledPiece {
    positions: Stream,
    primitives: Vec<(usize, Stream)>,
}

/// How a skinned primitive's vertices name their joints.
struct Skinned {
    /// Whether the skin needs u16 joint indices.
    wide: bool,
    /// The joint of each chunk, which all its vertices follow rigidly.
    joints: Vec<u16>,
}

/// A glTF mesh to be: node/mesh name, the skin (index into [`Plan::skins`]) that deforms it,
/// and its primitives.
struct Group<'a> {
    name: String,
    skin: Option<usize>,
    primitives: Vec<Primitive<'a>>,
    /// The part's metadata, written as the node's extras.
    metadata: Option<&'a Metadata>,
    /// Where the mesh is drawn.
    placement: Placement<'a>,
    /// The grid its quantised positions lie on, which its node's transformation undoes.
    grid: Option<Grid>,
    /// The vertex pool of its bare primitives, when it has some; its data goes before the other
    /// primitives'.
    pool: Vec<PooledPiece>,
}

impl<'a> Group<'a> {
    /// Compacts each primitive's chunks into the streams to write (and lets the chunks go),
    /// quantising positions on one grid for the whole mesh when `encoding` asks for it and
    /// the mesh is neither skinned nor instanced.
    fn encode(&mut self, encoding: GlbEncoding, compaction: Compaction) {
        // Bare primitives pool their vertices where triangles may be reordered (the pool also
        // keeps a face's back apart from it, for one primitive too).
        let bare: Vec<bool> = self
            .primitives
            .iter()
            .map(|p| compaction.reorder && p.is_bare())
            .collect();
        let vertices: Vec<Vertices<'a>> = self
            .primitives
            .par_iter_mut()
            .zip(&bare)
            .map(|(primitive, &bare)| Vertices::of_primitive(primitive, compaction, bare))
            .collect();
        // An instanced mesh's nodes carry the instances' transformations, so its positions
        // stay floats rather than take a grid that a node would have to undo.
        let placed_once = matches!(self.placement, Placement::Own);
        if encoding != GlbEncoding::Float && self.skin.is_none() && placed_once {
            let mut min = [f32::INFINITY; 3];
            let mut max = [f32::NEG_INFINITY; 3];
            for v in &vertices {
                v.view().positions.for_each(|p| {
                    for k in 0..3 {
                        min[k] = min[k].min(p[k]);
                        max[k] = max[k].max(p[k]);
                    }
                });
            }
            self.grid = Some(Grid::spanning(min, max));
        }
        let mut members = Vec::new();
        // The primitive each member of the pool is.
        let mut member_of = Vec::new();
        let primitives = self.primitives.iter_mut().enumerate();
        for ((index, primitive), (vertices, bare)) in primitives.zip(vertices.into_iter().zip(bare))
        {
            if bare {
                members.push(vertices);
                member_of.push(index);
                primitive.chunks = Vec::new();
                continue;
            }
            let joints = primitive.skinned.as_ref().map(|s| Joints { wide: s.wide });
            // Split where triangles may be reordered: pieces with u16 indices.
            let runs = if compaction.reorder && !primitive.lines {
                vertices.split(usize::from(u16::MAX) - 1)
            } else {
                vec![Run::Whole]
            };
            primitive.streams = runs
                .iter()
                .map(|run| {
                    let view = run.view(&vertices);
                    streams(view, primitive.lines, joints, encoding, self.grid.as_ref())
                })
                .collect();
            primitive.runs = runs;
            primitive.vertices = vertices;
            primitive.chunks = Vec::new();
        }
        if members.is_empty() {
            return;
        }
        let compressed = encoding == GlbEncoding::Compressed;
        let pieces = pool::pool(&members, usize::from(u16::MAX) - 1);
        drop(members);
        self.pool = pieces
            .into_par_iter()
            .map(|piece| {
                let points = Triples::F32(&piece.positions);
                let mut positions = position_stream(points, self.grid.as_ref());
                let count = piece.positions.len();
                let mut primitives: Vec<(usize, Stream)> = piece
                    .members
                    .iter()
                    .map(|(member, indices)| (member_of[*member], index_stream(indices, count)))
                    .collect();
                let streams = std::iter::once((&mut positions, &[][..]));
                let indices = primitives.iter_mut().zip(&piece.members);
                let streams = streams.chain(indices.map(|((_, s), (_, i))| (s, &i[..])));
                for (stream, indices) in streams {
                    let view = View::bare(&piece.positions, indices);
                    if compressed {
                        stream.compress(&view, false);
                    } else {
                        stream.encode(&view);
                    }
                }
                PooledPiece {
                    positions,
                    primitives,
                }
            })
            .collect();
    }
}

/// Where a glTF mesh is drawn.
enum Placement<'a> {
    /// By a node of its own, without a transformation.
    Own,
    /// By a node per part of an instance set, each with the part's transformation.
    Nodes(Vec<&'a Part>),
    /// By one node that draws it at the transformation of every part of an instance set.
    Gpu(Vec<&'a Part>),
}

/// The model as GLB bytes; see the module docs for the layout.
///
/// # Panics
/// On the errors [`write_glb_to`] reports: a file over 4 GiB, or skeletons that cannot be
/// written.
pub fn write_glb(model: &Model, options: &ExportOptions) -> Vec<u8> {
    let sets = InstanceSets::find(model, options.instancing);
    let written = Plan::new(model, &sets, options, REORDER).and_then(|plan| {
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
    Plan::new(model, &sets, options, REORDER)?.write(out)
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
    let plan = Plan::new(model, &sets, options, Compaction { reorder: false })?;
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

/// The file laid out: the JSON chunk, the primitives and skins whose data fill the BIN chunk.
struct Plan<'a> {
    json: Vec<u8>,
    groups: Vec<Group<'a>>,
    skins: Vec<Skin<'a>>,
    /// The skeletons' named poses, written after the skins.
    animations: Vec<Animation>,
    /// The images of textured parts, written last.
    textures: Vec<&'a Texture>,
    bin_len: usize,
}

impl<'a> Plan<'a> {
    fn new(
        model: &'a Model,
        sets: &'a InstanceSets,
        options: &ExportOptions,
        compaction: Compaction,
    ) -> io::Result<Self> {
        check_bones(model)?;
        // An instance set's mesh is its prototype's, written where the set is first used.
        let parts: Vec<(usize, &Part, Chunk<'a>)> = model
            .parts
            .par_iter()
            .enumerate()
            .filter_map(|(i, part)| {
                let chunk = match sets.role(i) {
                    Role::Own => Chunk::of_part(part)?,
                    Role::First(set) => Chunk::of_part(&sets.sets[set].prototype)?,
                    Role::Repeat => return None,
                };
                Some((i, part, chunk))
            })
            .collect();
        // A skin per skeleton that some written part hangs from, in skeleton order.
        let mut used = vec![false; model.skeletons.len()];
        for bone in parts.iter().filter_map(|(_, part, _)| part.bone) {
            used[bone.skeleton as usize] = true;
        }
        let mut skins = Vec::new();
        let mut skin_of = vec![None; model.skeletons.len()];
        for (index, _) in used.iter().enumerate().filter(|(_, used)| **used) {
            skin_of[index] = Some(skins.len());
            skins.push(Skin::new(&model.skeletons[index], index)?);
        }
        let chunks = parts.into_iter().map(|(index, part, chunk)| {
            let joint = part.bone.map(|bone| {
                let skin =
                    skin_of[bone.skeleton as usize].expect("every bound skeleton has a skin");
                (skin, skins[skin].joint(bone.section))
            });
            (
                &part.name,
                part.color,
                Some(index),
                joint,
                chunk,
                part.metadata.as_deref(),
            )
        });
        let line_chunks = model.lines.iter().filter_map(|lines| {
            Some((
                &lines.name,
                lines.color,
                None,
                None,
                Chunk::of_lines(lines)?,
                None,
            ))
        });
        let mut palette = Palette::default();
        // The distinct images, by path, in order of first use.
        let mut textures: Vec<&'a Texture> = Vec::new();
        let mut groups: Vec<Group<'a>> = Vec::new();
        // (skin or none, smooth apart) -> merged group, so skinned and unskinned parts and the
        // parts of two skins never share a mesh; nor do parts with normals and parts without,
        // when flat parts leave theirs to the reader: Blender's importer (3.4) makes one object
        // of a mesh and gives the corners of its primitives without normals wrong normals when
        // another primitive has some.
        let mut merged_groups: BTreeMap<(Option<usize>, bool), usize> = BTreeMap::new();
        // (group, material, lines, normals) -> primitive slot in that group; triangles and
        // lines of one colour stay apart since a primitive has one mode, and parts with normals
        // apart from those without, since a primitive's vertices all have them or none does.
        let mut merged: BTreeMap<(usize, usize, bool, bool), usize> = BTreeMap::new();
        for (name, color, source, joint, chunk, metadata) in chunks.chain(line_chunks) {
            let lines = source.is_none();
            let part = source.map(|i| &model.parts[i]);
            let textured = chunk.has_uvs();
            let tangents = chunk.has_tangents();
            // Readers shade a primitive without normals flat: only smooth and normal-mapped
            // parts need theirs (tangents are ignored without normals). Skinned parts keep
            // them, as skinned meshes mix smooth and flat parts (see `smooth_apart`).
            let computed = options.flat_normals == FlatNormals::Computed;
            let normals = !lines && (chunk.is_smooth() || tangents || !computed || joint.is_some());
            for t in part.into_iter().flat_map(gltf_textures) {
                if !textures.iter().any(|known| known.path == t.path) {
                    textures.push(t);
                }
            }
            let texture = part
                .and_then(|p| p.texture.as_deref())
                .filter(|t| textured && drawable(t))
                .and_then(|t| textures.iter().position(|known| known.path == t.path));
            let named = part.and_then(|p| p.material.as_ref());
            let surface = part.and_then(|p| p.surface.as_ref());
            let material = palette.material(color, texture, named, surface, textured);
            let skin = joint.map(|(skin, _)| skin);
            let skinned = |joints| Skinned {
                wide: skins[skin.expect("only skinned chunks have joints")].wide(),
                joints,
            };
            if let Some(Role::First(set)) = source.map(|i| sets.role(i)) {
                let set = &sets.sets[set];
                let uses = set.members.iter().map(|&m| &model.parts[m]).collect();
                groups.push(Group {
                    name: name.clone(),
                    metadata: None,
                    skin: None,
                    primitives: vec![Primitive {
                        material,
                        lines,
                        textured,
                        tangents,
                        normals,
                        skinned: None,
                        chunks: vec![chunk],
                        sources: vec![source],
                        vertices: Vertices::default(),
                        runs: Vec::new(),
                        streams: Vec::new(),
                    }],
                    grid: None,
                    pool: Vec::new(),
                    placement: if set.gpu {
                        Placement::Gpu(uses)
                    } else {
                        Placement::Nodes(uses)
                    },
                });
                continue;
            }
            // A part with metadata keeps its node, which carries them.
            if options.group_by_part || metadata.is_some() {
                groups.push(Group {
                    name: name.clone(),
                    metadata,
                    skin,
                    placement: Placement::Own,
                    grid: None,
                    pool: Vec::new(),
                    primitives: vec![Primitive {
                        material,
                        lines,
                        textured,
                        tangents,
                        normals,
                        skinned: joint.map(|(_, j)| skinned(vec![j])),
                        chunks: vec![chunk],
                        sources: vec![source],
                        vertices: Vertices::default(),
                        runs: Vec::new(),
                        streams: Vec::new(),
                    }],
                });
                continue;
            }
            let smooth_apart = skin.is_none() && normals && computed;
            // The first merged mesh is "model"; one beside it says how it differs.
            let beside = merged_groups.contains_key(&(skin, !smooth_apart));
            let name = match skin {
                Some(s) => skins[s].mesh_name(),
                None if !beside => "model".to_owned(),
                None if smooth_apart => "model-smooth".to_owned(),
                None => "model-flat".to_owned(),
            };
            let group = *merged_groups
                .entry((skin, smooth_apart))
                .or_insert_with(|| {
                    groups.push(Group {
                        name,
                        metadata: None,
                        skin,
                        grid: None,
                        pool: Vec::new(),
                        primitives: Vec::new(),
                        placement: Placement::Own,
                    });
                    groups.len() - 1
                });
            let primitives = &mut groups[group].primitives;
            let key = (group, material, lines, normals);
            let slot = *merged.entry(key).or_insert_with(|| {
                primitives.push(Primitive {
                    material,
                    lines,
                    textured,
                    tangents,
                    normals,
                    skinned: joint.map(|_| skinned(Vec::new())),
                    chunks: Vec::new(),
                    sources: Vec::new(),
                    vertices: Vertices::default(),
                    runs: Vec::new(),
                    streams: Vec::new(),
                });
                primitives.len() - 1
            });
            let primitive = &mut primitives[slot];
            primitive.chunks.push(chunk);
            primitive.sources.push(source);
            if let (Some(skinned), Some((_, j))) = (&mut primitive.skinned, joint) {
                skinned.joints.push(j);
            }
        }
        // Meshes are independent: planned on as many threads as there are, each the same on
        // any number of them.
        groups
            .par_iter_mut()
            .for_each(|group| group.encode(options.encoding, compaction));
        let animations = Animation::of_skins(&skins);
        let (json, bin_len) = document(&palette, &textures, &groups, &skins, &animations);
        Ok(Self {
            json,
            groups,
            skins,
            animations,
            textures,
            bin_len,
        })
    }

    /// The size of the file in bytes.
    fn len(&self) -> usize {
        let bin_chunk = if self.bin_len == 0 {
            0
        } else {
            8 + self.bin_len
        };
        12 + 8 + self.json.len() + bin_chunk
    }

    fn write(&self, out: &mut impl Write) -> io::Result<()> {
        if u32::try_from(self.len()).is_err() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "the GLB file would have {} bytes, over the 4 GiB the format allows",
                    self.len()
                ),
            ));
        }
        let word = |v: usize| (v as u32).to_le_bytes();
        out.write_all(MAGIC)?;
        out.write_all(&2u32.to_le_bytes())?;
        out.write_all(&word(self.len()))?;
        out.write_all(&word(self.json.len()))?;
        out.write_all(&CHUNK_JSON.to_le_bytes())?;
        out.write_all(&self.json)?;
        if self.bin_len == 0 {
            return Ok(());
        }
        out.write_all(&word(self.bin_len))?;
        out.write_all(&CHUNK_BIN.to_le_bytes())?;
        let mut result = Ok(());
        // Collects the first error of the per-element writes, which cannot return early.
        let mut put = |bytes: &[u8]| {
            if result.is_ok() {
                result = out.write_all(bytes);
            }
        };
        let mut stream_of = |view: &View<'_>, stream: &Stream| {
            stream.write(view, &mut put);
            put(&[0; 3][..stream.len().next_multiple_of(4) - stream.len()]);
        };
        for group in &self.groups {
            // A pool's data is made already: its streams need no vertices.
            let none = View::bare(&[], &[]);
            for pooled in &group.pool {
                stream_of(&none, &pooled.positions);
                for (_, stream) in &pooled.primitives {
                    stream_of(&none, stream);
                }
            }
            for primitive in &group.primitives {
                for (run, streams) in primitive.runs.iter().zip(&primitive.streams) {
                    let view = run.view(&primitive.vertices);
                    streams.iter().for_each(|stream| stream_of(&view, stream));
                }
            }
        }
        for group in &self.groups {
            if let Placement::Gpu(uses) = &group.placement {
                instance::gpu_data(uses, &mut put);
            }
        }
        for skin in &self.skins {
            skin.inverse_bind_matrices(|matrix| {
                for x in matrix {
                    put(&x.to_le_bytes());
                }
            });
        }
        // Every animation value is 4, 12 or 16 bytes, so no view needs padding.
        for animation in &self.animations {
            animation.data(|values| {
                for x in values {
                    put(&x.to_le_bytes());
                }
            });
        }
        for texture in &self.textures {
            let image = texture.image.as_deref().unwrap_or_default();
            put(image);
            put(&[0; 3][..image.len().next_multiple_of(4) - image.len()]);
        }
        result
    }
}

/// A primitive of triangles over a piece of a vertex pool: its positions and its indices.
fn pooled_primitive(
    material: usize,
    positions: json::Index<json::Accessor>,
    indices: json::Index<json::Accessor>,
) -> json::mesh::Primitive {
    json::mesh::Primitive {
        attributes: BTreeMap::from([(Valid(json::mesh::Semantic::Positions), positions)]),
        extensions: None,
        extras: Default::default(),
        indices: Some(indices),
        material: Some(json::Index::new(material as u32)),
        mode: Valid(json::mesh::Mode::Triangles),
        targets: None,
    }
}

/// The JSON chunk (padded with spaces to 4 bytes) and the length of the BIN chunk.
fn document(
    palette: &Palette,
    textures: &[&Texture],
    groups: &[Group<'_>],
    skins: &[Skin<'_>],
    animations: &[Animation],
) -> (Vec<u8>, usize) {
    let mut builder = Builder::default();
    // The root goes first so that it is node 0; its children are filled in below.
    builder.root.push(json::Node {
        name: Some("shapegram".to_owned()),
        ..Default::default()
    });
    let colors = palette.colors().iter().zip(palette.names());
    let looks = palette.textures().iter().zip(palette.surfaces());
    for ((&[r, g, b, a], name), (&texture, surface)) in colors.zip(looks) {
        // The palette holds sRGB, as written in grammars; glTF wants linear light.
        let mut material = material(Color { r, g, b, a }.to_linear(), name);
        if let Some(texture) = texture {
            let transform = surface.as_ref().map(|s| s.transforms[0]);
            textured(
                &mut material,
                texture,
                textures[texture],
                transform.unwrap_or_default(),
            );
        }
        if let Some(surface) = surface {
            with_surface(&mut material, surface, |t| {
                textures.iter().position(|known| known.path == t.path)
            });
        }
        builder.root.push(material);
    }
    let mut children = Vec::new();
    let mut roots = vec![json::Index::new(0)];
    let mut gpu_meshes = Vec::new();
    let mut lots = LotNodes::default();
    for group in groups {
        // The pool's accessors first, as its data comes first; its primitives then take the
        // places of the primitives whose vertices went into it.
        let mut pooled = vec![Vec::new(); group.primitives.len()];
        for piece in &group.pool {
            let positions = builder.accessor(&piece.positions);
            for (primitive, indices) in &piece.primitives {
                pooled[*primitive].push((positions, builder.accessor(indices)));
            }
        }
        let mut primitives = Vec::new();
        for (primitive, pooled) in group.primitives.iter().zip(pooled) {
            for streams in &primitive.streams {
                primitives.push(builder.primitive(primitive, streams));
            }
            for (positions, indices) in pooled {
                primitives.push(pooled_primitive(primitive.material, positions, indices));
            }
        }
        let mesh = builder.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(group.name.clone()),
            primitives,
            weights: None,
        });
        match &group.placement {
            Placement::Own => {}
            Placement::Nodes(uses) => {
                for part in uses {
                    let metadata = part.metadata.as_deref();
                    let lot = lots.lot_of(&mut builder.root, metadata, &mut children);
                    let node = builder.root.push(instance::use_node(mesh, part));
                    lots.adopt(lot, node, &mut children);
                }
                continue;
            }
            // Their instances' data follows every primitive's, as their accessors do.
            Placement::Gpu(uses) => {
                gpu_meshes.push((mesh, &group.name, uses.len()));
                continue;
            }
        }
        let lot = lots.lot_of(&mut builder.root, group.metadata, &mut children);
        // Skins are added after every mesh node, in the order of `skins`.
        let node = builder.root.push(json::Node {
            mesh: Some(mesh),
            name: Some(group.name.clone()),
            translation: group.grid.map(|grid| grid.centre),
            scale: group.grid.map(|grid| [grid.step; 3]),
            skin: group.skin.map(|s| json::Index::new(s as u32)),
            extras: group.metadata.map(metadata_extras),
            ..Default::default()
        });
        // A skinned mesh node is a scene root: the validator warns when one has a parent,
        // whose transformation skinning would ignore.
        if group.skin.is_some() {
            roots.push(node);
        } else {
            lots.adopt(lot, node, &mut children);
        }
    }
    for (mesh, name, uses) in gpu_meshes {
        let node = instance::gpu_node(&mut builder, mesh, name, uses);
        children.push(builder.root.push(node));
    }
    let mut joints = Vec::with_capacity(skins.len());
    for skin in skins {
        let (armature, nodes) = skin.push(&mut builder);
        children.push(armature);
        joints.push(nodes);
    }
    for animation in animations {
        animation.push(&mut builder, &joints);
    }
    lots.finish(&mut builder.root);
    for texture in textures {
        builder.image(texture);
    }
    builder.finish(children, roots)
}

/// The JSON document being filled and the length of the BIN chunk so far.
#[derive(Default)]
struct Builder {
    root: json::Root,
    bin_len: usize,
    /// The length of the fallback buffer behind compressed views (0: there are none).
    fallback_len: usize,
    /// Whether some position, normal or uv is stored in integers (KHR_mesh_quantization).
    quantized: bool,
}

impl Builder {
    /// The primitive's accessors, in the order [`Plan::write`] writes their data.
    fn primitive(
        &mut self,
        primitive: &Primitive<'_>,
        streams: &[Stream],
    ) -> json::mesh::Primitive {
        let mut attributes = BTreeMap::new();
        let mut indices = None;
        for stream in streams {
            let accessor = self.accessor(stream);
            match stream.semantic.clone() {
                Some(semantic) => {
                    attributes.insert(Valid(semantic), accessor);
                }
                None => indices = Some(accessor),
            }
        }
        json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices,
            material: Some(json::Index::new(primitive.material as u32)),
            mode: Valid(if primitive.lines {
                json::mesh::Mode::Lines
            } else {
                json::mesh::Mode::Triangles
            }),
            targets: None,
        }
    }

    /// A texture of its own for an image embedded in the BIN chunk (in [`Plan::write`]'s
    /// order), sampled with glTF's defaults (repeating).
    fn image(&mut self, texture: &Texture) {
        let bytes = texture.image.as_deref().unwrap_or_default();
        let offset = self.bin_len;
        self.bin_len = (offset + bytes.len()).next_multiple_of(4);
        let view = self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: None,
        });
        let name = texture.path.rsplit(['/', '\\']).next().unwrap_or_default();
        let image = self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: texture
                .mime_type()
                .map(|m| json::image::MimeType(m.to_owned())),
            name: Some(name.to_owned()),
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        self.root.push(json::Texture {
            name: None,
            sampler: None,
            source: image,
            extensions: None,
            extras: Default::default(),
        });
    }

    /// A buffer view of its own for a stream, and an accessor over it. A compressed stream's
    /// view lies in the fallback buffer (1), its extension pointing at the data in the BIN
    /// chunk.
    fn accessor(&mut self, stream: &Stream) -> json::Index<json::Accessor> {
        use json::buffer::Target;
        self.quantized |= stream.quantized();
        let offset = self.bin_len;
        // Every view starts on a 4-byte boundary, as f32 and u32 accessors require.
        self.bin_len = (offset + stream.len()).next_multiple_of(4);
        let mut view = json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(stream.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: stream
                .strided()
                .then_some(json::buffer::Stride(stream.stride)),
            extensions: None,
            extras: Default::default(),
            name: None,
            target: Some(Valid(match stream.semantic {
                Some(_) => Target::ArrayBuffer,
                None => Target::ElementArrayBuffer,
            })),
        };
        if let Some((mode, length)) = stream.compressed {
            let fallback = self.fallback_len;
            self.fallback_len = (fallback + length).next_multiple_of(4);
            view.buffer = json::Index::new(1);
            view.byte_offset = Some(USize64::from(fallback));
            view.byte_length = USize64::from(length);
            let extension =
                compress::view_extension(offset, stream.len(), stream.stride, stream.count, mode);
            let mut others = serde_json::Map::new();
            others.insert(compress::EXTENSION.to_owned(), extension);
            view.extensions = Some(json::extensions::buffer::View { others });
        }
        let view = self.root.push(view);
        let (min, max) = stream.bounds.clone().unzip();
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(stream.count),
            component_type: Valid(json::accessor::GenericComponentType(stream.component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(stream.kind),
            min,
            max,
            name: None,
            normalized: stream.normalized,
            sparse: None,
        })
    }

    /// A buffer view of its own for `count` elements of `size` bytes, and an accessor over it.
    fn data_accessor(
        &mut self,
        count: usize,
        size: usize,
        target: Option<json::buffer::Target>,
        (component, kind): (json::accessor::ComponentType, json::accessor::Type),
        min_max: Option<(serde_json::Value, serde_json::Value)>,
    ) -> json::Index<json::Accessor> {
        let offset = self.bin_len;
        let length = count * size;
        // Every view starts on a 4-byte boundary, as f32 and u32 accessors require.
        self.bin_len = (offset + length).next_multiple_of(4);
        let view = self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: target.map(Valid),
        });
        let (min, max) = min_max.unzip();
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(kind),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// Lists `extension` as used and required.
    fn require(&mut self, extension: &str) {
        self.root.extensions_used.push(extension.to_owned());
        self.root.extensions_required.push(extension.to_owned());
    }

    /// Adds the root's children, the scene with its root nodes and the buffer; returns the
    /// padded JSON text and the BIN chunk's length.
    fn finish(
        mut self,
        children: Vec<json::Index<json::Node>>,
        roots: Vec<json::Index<json::Node>>,
    ) -> (Vec<u8>, usize) {
        self.root.nodes[0].children = (!children.is_empty()).then_some(children);
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes: roots,
        });
        self.root.scene = Some(scene);
        self.root.asset.generator = Some(format!("shapegram {}", env!("CARGO_PKG_VERSION")));
        if material::uses_texture_transform(&self.root.materials) {
            self.root
                .extensions_used
                .push(material::TEXTURE_TRANSFORM.to_owned());
        }
        if self.bin_len > 0 {
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.bin_len),
                extensions: None,
                extras: Default::default(),
                name: None,
                uri: None,
            });
        }
        if self.quantized {
            self.require(quantize::EXTENSION);
        }
        if self.fallback_len > 0 {
            // The fallback buffer has no data, so readers must decode: the extension is
            // required, not merely used.
            let mut others = serde_json::Map::new();
            others.insert(
                compress::EXTENSION.to_owned(),
                compress::fallback_extension(),
            );
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.fallback_len),
                extensions: Some(json::extensions::buffer::Buffer { others }),
                extras: Default::default(),
                name: None,
                uri: None,
            });
            self.require(compress::EXTENSION);
        }
        let mut text = serde_json::to_vec(&self.root)
            .expect("gltf-json types always serialise (no maps with non-string keys)");
        text.resize(text.len().next_multiple_of(4), b' ');
        (text, self.bin_len)
    }
}
