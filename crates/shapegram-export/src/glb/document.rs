//! The JSON chunk: materials, meshes, nodes, skins, animations, images and the accessors over
//! the BIN chunk's views, in the order [`super::Plan::write`] writes their data.

use std::collections::BTreeMap;

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use shapegram_geom::{Color, Texture};

use super::animation::Animation;
use super::compress;
use super::features::{MESH_FEATURES, PropertyTable, STRUCTURAL_METADATA};
use super::instance;
use super::material::{self, material, textured, with_surface};
use super::metadata::{LotNodes, metadata_extras};
use super::plan::{Group, Placement, Primitive};
use super::quantize;
use super::skin::Skin;
use super::streams::Stream;
use crate::flat::Palette;

/// A primitive of triangles over a piece of a vertex pool: its positions and its indices.
pub(super) fn pooled_primitive(
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
pub(super) fn document(
    palette: &Palette,
    textures: &[&Texture],
    groups: &[Group<'_>],
    skins: &[Skin<'_>],
    animations: &[Animation],
    table: Option<&PropertyTable>,
) -> (Vec<u8>, usize) {
    let mut builder = Builder::default();
    // The property table's views come first (see `Plan::write`).
    if let Some(table) = table {
        builder.property_table(table);
    }
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
            for (run, streams) in primitive.streams.iter().enumerate() {
                let features = primitive.feature_counts.get(run).copied();
                primitives.push(builder.primitive(primitive, streams, features));
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
pub(super) struct Builder {
    pub(super) root: json::Root,
    pub(super) bin_len: usize,
    /// The length of the fallback buffer behind compressed views (0: there are none).
    pub(super) fallback_len: usize,
    /// Whether some position, normal or uv is stored in integers (KHR_mesh_quantization).
    pub(super) quantized: bool,
}

/// A view of `length` bytes of the BIN chunk from `offset`, without a stride.
fn bin_view(
    offset: usize,
    length: usize,
    target: Option<json::buffer::Target>,
) -> json::buffer::View {
    json::buffer::View {
        buffer: json::Index::new(0),
        byte_length: USize64::from(length),
        byte_offset: Some(USize64::from(offset)),
        byte_stride: None,
        extensions: None,
        extras: Default::default(),
        name: None,
        target: target.map(Valid),
    }
}

impl Builder {
    /// The root's `EXT_structural_metadata` and the views of its property table, which start
    /// the BIN chunk (each a multiple of 8 bytes long).
    fn property_table(&mut self, table: &PropertyTable) {
        let first = self.root.buffer_views.len() as u32;
        for view in &table.views {
            let offset = self.bin_len;
            self.bin_len += view.len();
            self.root.push(bin_view(offset, view.len(), None));
        }
        let mut others = serde_json::Map::new();
        others.insert(STRUCTURAL_METADATA.to_owned(), table.extension(first));
        self.root.extensions = Some(json::extensions::root::Root { others });
        self.root
            .extensions_used
            .extend([MESH_FEATURES, STRUCTURAL_METADATA].map(str::to_owned));
    }

    /// The primitive's accessors, in the order [`Plan::write`] writes their data; with
    /// `features` (how many distinct ones its `_FEATURE_ID_0` holds), its `EXT_mesh_features`.
    pub(super) fn primitive(
        &mut self,
        primitive: &Primitive<'_>,
        streams: &[Stream],
        features: Option<usize>,
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
        let extensions = features.map(|count| {
            let mut others = serde_json::Map::new();
            let ids = serde_json::json!({
                "featureIds": [{ "featureCount": count, "attribute": 0, "propertyTable": 0 }],
            });
            others.insert(MESH_FEATURES.to_owned(), ids);
            json::extensions::mesh::Primitive { others }
        });
        json::mesh::Primitive {
            attributes,
            extensions,
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
    pub(super) fn image(&mut self, texture: &Texture) {
        let bytes = texture.image.as_deref().unwrap_or_default();
        let offset = self.bin_len;
        self.bin_len = (offset + bytes.len()).next_multiple_of(4);
        let view = self.root.push(bin_view(offset, bytes.len(), None));
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
    pub(super) fn accessor(&mut self, stream: &Stream) -> json::Index<json::Accessor> {
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
    pub(super) fn data_accessor(
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
        let view = self.root.push(bin_view(offset, length, target));
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
    pub(super) fn require(&mut self, extension: &str) {
        self.root.extensions_used.push(extension.to_owned());
        self.root.extensions_required.push(extension.to_owned());
    }

    /// Adds the root's children, the scene with its root nodes and the buffer; returns the
    /// padded JSON text and the BIN chunk's length.
    pub(super) fn finish(
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
