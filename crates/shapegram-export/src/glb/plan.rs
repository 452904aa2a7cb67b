//! The file planned: the model's parts gathered into meshes and primitives, each compacted
//! (on rayon's threads) into the streams whose bytes [`Plan::write`] puts out.

use std::collections::BTreeMap;
use std::io::{self, Write};

use gltf_json::accessor::ComponentType;
use rayon::prelude::*;
use shapegram_geom::{Metadata, Model, Part, Texture};

use super::animation::Animation;
use super::chunk::Chunk;
use super::compact::{Compaction, Run, Vertices, View};
use super::document::document;
use super::features::{Features, PropertyTable};
use super::instance::{self, InstanceSets, Role};
use super::material::gltf_textures;
use super::pool;
use super::quantize::Grid;
use super::skin::Skin;
use super::streams::{Joints, Stream, index_stream, position_stream, streams};
use super::triples::Triples;
use super::{CHUNK_BIN, CHUNK_JSON, MAGIC};
use crate::flat::{Palette, check_bones, drawable};
use crate::{ExportOptions, FlatNormals, GlbEncoding};

/// One glTF primitive to be: its material, its mode, its skinning and the chunks whose data it
/// concatenates.
pub(super) struct Primitive<'a> {
    pub(super) material: usize,
    pub(super) lines: bool,
    /// Whether its vertices carry uvs (TEXCOORD_0): its material is textured.
    pub(super) textured: bool,
    /// Whether its vertices carry tangents: its material has a normal map.
    pub(super) tangents: bool,
    /// Whether its vertices carry normals (NORMAL): its parts are smooth or normal-mapped, or
    /// flat normals are asked for ([`FlatNormals::Written`]).
    pub(super) normals: bool,
    pub(super) skinned: Option<Skinned>,
    /// The data of the model's parts, until [`Plan::new`] has compacted them into `streams`.
    pub(super) chunks: Vec<Chunk<'a>>,
    /// The model part each chunk holds (`None`: a line set).
    pub(super) sources: Vec<Option<usize>>,
    /// The feature id of each chunk, when the file has features ([`Features`]).
    pub(super) features: Option<Vec<u32>>,
    /// How many distinct features each run's vertices have (empty without features).
    pub(super) feature_counts: Vec<usize>,
    /// Its vertices compacted, from which its streams' data is made as the file is written
    /// (none when they went into its mesh's pool).
    pub(super) vertices: Vertices<'a>,
    /// The glTF primitives it becomes: one, or several of fewer than 65,535 vertices each.
    pub(super) runs: Vec<Run>,
    /// Each run's accessors, in the order they are written.
    pub(super) streams: Vec<Vec<Stream>>,
}

impl Primitive<'_> {
    /// Whether its vertices are positions and nothing else, which primitives of other
    /// materials can share (see [`pool`]).
    fn is_bare(&self) -> bool {
        !self.lines
            && !self.textured
            && !self.tangents
            && !self.normals
            && self.skinned.is_none()
            && self.features.is_none()
    }
}

/// One piece of a mesh's vertex pool, encoded: the POSITION data its primitives share and, per
/// primitive of the mesh with triangles in it, the primitive's index and those indices. Pieces
/// are small and their u16 indices take half the memory of the pool's, so their data is made
/// when planned rather than as written (see [`Stream::encode`]).
pub(super) struct PooledPiece {
    pub(super) positions: Stream,
    pub(super) primitives: Vec<(usize, Stream)>,
}

/// How a skinned primitive's vertices name their joints.
pub(super) struct Skinned {
    /// Whether the skin needs u16 joint indices.
    wide: bool,
    /// The joint of each chunk, which all its vertices follow rigidly.
    pub(super) joints: Vec<u16>,
}

/// A glTF mesh to be: node/mesh name, the skin (index into [`Plan::skins`]) that deforms it,
/// and its primitives.
pub(super) struct Group<'a> {
    pub(super) name: String,
    pub(super) skin: Option<usize>,
    pub(super) primitives: Vec<Primitive<'a>>,
    /// The part's metadata, written as the node's extras.
    pub(super) metadata: Option<&'a Metadata>,
    /// Where the mesh is drawn.
    pub(super) placement: Placement<'a>,
    /// The grid its quantised positions lie on, which its node's transformation undoes.
    pub(super) grid: Option<Grid>,
    /// The vertex pool of its bare primitives, when it has some; its data goes before the other
    /// primitives'.
    pub(super) pool: Vec<PooledPiece>,
}

impl<'a> Group<'a> {
    /// Compacts each primitive's chunks into the streams to write (and lets the chunks go),
    /// quantising positions on one grid for the whole mesh when `encoding` asks for it and
    /// the mesh is neither skinned nor instanced.
    fn encode(
        &mut self,
        encoding: GlbEncoding,
        compaction: Compaction,
        feature_ids: Option<ComponentType>,
    ) {
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
            let feature_ids = feature_ids.filter(|_| primitive.features.is_some());
            primitive.streams = runs
                .iter()
                .map(|run| {
                    let view = run.view(&vertices);
                    let grid = self.grid.as_ref();
                    streams(view, primitive.lines, joints, feature_ids, encoding, grid)
                })
                .collect();
            if feature_ids.is_some() {
                primitive.feature_counts = runs
                    .iter()
                    .map(|run| distinct(run.view(&vertices).features))
                    .collect();
            }
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
pub(super) enum Placement<'a> {
    /// By a node of its own, without a transformation.
    Own,
    /// By a node per part of an instance set, each with the part's transformation.
    Nodes(Vec<&'a Part>),
    /// By one node that draws it at the transformation of every part of an instance set.
    Gpu(Vec<&'a Part>),
}

/// How many distinct values `ids` holds.
fn distinct(ids: &[u32]) -> usize {
    let mut sorted = ids.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    sorted.len()
}

/// The file laid out: the JSON chunk, the primitives and skins whose data fill the BIN chunk.
pub(super) struct Plan<'a> {
    json: Vec<u8>,
    /// The features' property table, whose views come first in the BIN chunk.
    table: Option<PropertyTable>,
    pub(super) groups: Vec<Group<'a>>,
    skins: Vec<Skin<'a>>,
    /// The skeletons' named poses, written after the skins.
    animations: Vec<Animation>,
    /// The images of textured parts, written last.
    textures: Vec<&'a Texture>,
    bin_len: usize,
}

impl<'a> Plan<'a> {
    pub(super) fn new(
        model: &'a Model,
        sets: &'a InstanceSets,
        options: &ExportOptions,
        compaction: Compaction,
        features: Option<&Features<'_>>,
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
                features.map(|f| f.parts[index]),
            )
        });
        let line_chunks = model.lines.iter().enumerate().filter_map(|(i, lines)| {
            Some((
                &lines.name,
                lines.color,
                None,
                None,
                Chunk::of_lines(lines)?,
                None,
                features.map(|f| f.lines[i]),
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
        for (name, color, source, joint, chunk, metadata, feature) in chunks.chain(line_chunks) {
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
                        features: feature.map(|id| vec![id]),
                        feature_counts: Vec::new(),
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
                        features: feature.map(|id| vec![id]),
                        feature_counts: Vec::new(),
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
                    features: feature.map(|_| Vec::new()),
                    feature_counts: Vec::new(),
                    vertices: Vertices::default(),
                    runs: Vec::new(),
                    streams: Vec::new(),
                });
                primitives.len() - 1
            });
            let primitive = &mut primitives[slot];
            primitive.chunks.push(chunk);
            primitive.sources.push(source);
            if let (Some(ids), Some(id)) = (&mut primitive.features, feature) {
                ids.push(id);
            }
            if let (Some(skinned), Some((_, j))) = (&mut primitive.skinned, joint) {
                skinned.joints.push(j);
            }
        }
        // Meshes are independent: planned on as many threads as there are, each the same on
        // any number of them.
        let feature_ids = features.map(Features::component);
        groups
            .par_iter_mut()
            .for_each(|group| group.encode(options.encoding, compaction, feature_ids));
        let animations = Animation::of_skins(&skins);
        let table = features.map(|f| PropertyTable::new(&f.rows));
        let (json, bin_len) = document(
            &palette,
            &textures,
            &groups,
            &skins,
            &animations,
            table.as_ref(),
        );
        Ok(Self {
            json,
            table,
            groups,
            skins,
            animations,
            textures,
            bin_len,
        })
    }

    /// The size of the file in bytes.
    pub(super) fn len(&self) -> usize {
        let bin_chunk = if self.bin_len == 0 {
            0
        } else {
            8 + self.bin_len
        };
        12 + 8 + self.json.len() + bin_chunk
    }

    pub(super) fn write(&self, out: &mut impl Write) -> io::Result<()> {
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
        // The property table's views are 8-byte multiples at the start: each on an 8-byte
        // boundary, as the extension requires.
        for view in self.table.iter().flat_map(|t| &t.views) {
            out.write_all(view)?;
        }
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
