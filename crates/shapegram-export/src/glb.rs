//! Binary glTF 2.0 (GLB) writer: `gltf-json` types serialised by serde_json, framed by hand.
//!
//! Layout: one root node "shapegram" (scene 0) whose children carry the meshes. Shading is flat:
//! every face gets its own vertices (shared by the face's triangles) with the face normal. Each
//! accessor has its own tightly packed buffer view, 4-byte aligned, in one buffer.

use std::collections::BTreeMap;

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use shapegram_geom::{Color, Model};

use crate::ExportOptions;
use crate::flat::{Palette, flat_faces};

/// GLB framing constants from the glTF 2.0 specification, section "Binary glTF Layout".
pub(crate) const MAGIC: &[u8; 4] = b"glTF";
pub(crate) const CHUNK_JSON: u32 = 0x4E4F_534A;
pub(crate) const CHUNK_BIN: u32 = 0x004E_4942;

/// The triangles of one primitive, flat-shaded.
#[derive(Default)]
struct Geometry {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    indices: Vec<u32>,
}

impl Geometry {
    fn add_mesh(&mut self, mesh: &shapegram_geom::Mesh) {
        flat_faces(mesh, |face| {
            let base = self.positions.len() as u32;
            self.positions.extend_from_slice(face.corners);
            self.normals
                .extend(std::iter::repeat_n(face.normal, face.corners.len()));
            self.indices
                .extend(face.triangles.iter().flatten().map(|&c| base + c));
        });
    }
}

/// A glTF mesh to be: node/mesh name and its primitives as (material, geometry).
struct Group {
    name: String,
    primitives: Vec<(usize, Geometry)>,
}

/// The model as GLB bytes; see the module docs for the layout.
pub fn write_glb(model: &Model, options: &ExportOptions) -> Vec<u8> {
    let mut palette = Palette::default();
    let mut groups: Vec<Group> = Vec::new();
    // Material index -> primitive slot in the single merged group.
    let mut merged: BTreeMap<usize, usize> = BTreeMap::new();
    for part in &model.parts {
        let mut geometry = Geometry::default();
        geometry.add_mesh(&part.mesh);
        if geometry.indices.is_empty() {
            continue;
        }
        let material = palette.material(part.color);
        if options.group_by_part {
            groups.push(Group {
                name: part.name.clone(),
                primitives: vec![(material, geometry)],
            });
            continue;
        }
        if groups.is_empty() {
            groups.push(Group {
                name: "model".to_owned(),
                primitives: Vec::new(),
            });
        }
        let primitives = &mut groups[0].primitives;
        let slot = *merged.entry(material).or_insert_with(|| {
            primitives.push((material, Geometry::default()));
            primitives.len() - 1
        });
        let target = &mut primitives[slot].1;
        if target.indices.is_empty() {
            // The first part of a colour: its lists become the primitive's, uncopied.
            *target = geometry;
            continue;
        }
        let base = target.positions.len() as u32;
        target.positions.extend(geometry.positions);
        target.normals.extend(geometry.normals);
        target
            .indices
            .extend(geometry.indices.iter().map(|i| base + i));
    }

    let mut builder = Builder::default();
    // The root goes first so that it is node 0; its children are filled in by `finish`.
    builder.root.push(json::Node {
        name: Some("shapegram".to_owned()),
        ..Default::default()
    });
    for (&[r, g, b, a], name) in palette.colors().iter().zip(palette.hex_names()) {
        // The palette holds sRGB, as written in grammars; glTF wants linear light.
        builder
            .root
            .push(material(Color { r, g, b, a }.to_linear(), name));
    }
    let mut children = Vec::new();
    for group in &groups {
        let primitives = group
            .primitives
            .iter()
            .map(|(material, geometry)| builder.primitive(*material, geometry))
            .collect();
        let mesh = builder.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(group.name.clone()),
            primitives,
            weights: None,
        });
        children.push(builder.root.push(json::Node {
            mesh: Some(mesh),
            name: Some(group.name.clone()),
            ..Default::default()
        }));
    }
    builder.finish(children)
}

fn material(rgba: [f32; 4], name: String) -> json::Material {
    json::Material {
        name: Some(name),
        alpha_mode: Valid(if rgba[3] < 1.0 {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        double_sided: false,
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(rgba),
            metallic_factor: json::material::StrengthFactor(0.0),
            // Matte: procedural models are mostly buildings and props, not polished metal.
            roughness_factor: json::material::StrengthFactor(0.9),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The JSON document and the BIN chunk being filled.
#[derive(Default)]
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
}

impl Builder {
    fn primitive(&mut self, material: usize, geometry: &Geometry) -> json::mesh::Primitive {
        let (min, max) = bounds(&geometry.positions);
        let positions = self.accessor(
            &geometry.positions,
            json::buffer::Target::ArrayBuffer,
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            Some((min.to_vec().into(), max.to_vec().into())),
        );
        let normals = self.accessor(
            &geometry.normals,
            json::buffer::Target::ArrayBuffer,
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            None,
        );
        // The largest value of the index type is reserved (primitive restart), hence `<`.
        let indices = if geometry.positions.len() < usize::from(u16::MAX) {
            let small: Vec<u16> = geometry.indices.iter().map(|&i| i as u16).collect();
            self.accessor(
                &small,
                json::buffer::Target::ElementArrayBuffer,
                json::accessor::ComponentType::U16,
                json::accessor::Type::Scalar,
                None,
            )
        } else {
            self.accessor(
                &geometry.indices,
                json::buffer::Target::ElementArrayBuffer,
                json::accessor::ComponentType::U32,
                json::accessor::Type::Scalar,
                None,
            )
        };
        json::mesh::Primitive {
            attributes: BTreeMap::from([
                (Valid(json::mesh::Semantic::Positions), positions),
                (Valid(json::mesh::Semantic::Normals), normals),
            ]),
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: Some(json::Index::new(material as u32)),
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        }
    }

    /// Appends the elements as a buffer view of their own and returns an accessor over it.
    fn accessor<T: Element>(
        &mut self,
        elements: &[T],
        target: json::buffer::Target,
        component: json::accessor::ComponentType,
        kind: json::accessor::Type,
        min_max: Option<(serde_json::Value, serde_json::Value)>,
    ) -> json::Index<json::Accessor> {
        let offset = self.bin.len();
        // Reserved up front: large models would otherwise copy the buffer as it grows.
        self.bin.reserve(std::mem::size_of_val(elements) + 3);
        for element in elements {
            element.write_le(&mut self.bin);
        }
        let length = self.bin.len() - offset;
        // Every view starts on a 4-byte boundary, as f32 and u32 accessors require.
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let view = self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: Some(Valid(target)),
        });
        let (min, max) = min_max.unzip();
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(elements.len()),
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

    /// Adds the root node, scene and buffer, and frames JSON and BIN as GLB.
    fn finish(mut self, children: Vec<json::Index<json::Node>>) -> Vec<u8> {
        self.root.nodes[0].children = (!children.is_empty()).then_some(children);
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes: vec![json::Index::new(0)],
        });
        self.root.scene = Some(scene);
        self.root.asset.generator = Some(format!("shapegram {}", env!("CARGO_PKG_VERSION")));
        if !self.bin.is_empty() {
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                extensions: None,
                extras: Default::default(),
                name: None,
                uri: None,
            });
        }
        let mut text = serde_json::to_vec(&self.root)
            .expect("gltf-json types always serialise (no maps with non-string keys)");
        text.resize(text.len().next_multiple_of(4), b' ');

        let bin_chunk = if self.bin.is_empty() {
            0
        } else {
            8 + self.bin.len()
        };
        let total = 12 + 8 + text.len() + bin_chunk;
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
        out.extend_from_slice(&text);
        if !self.bin.is_empty() {
            out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
            out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
            out.extend_from_slice(&self.bin);
        }
        out
    }
}

/// Component-wise min and max of the f32 positions exactly as written (the spec requires them
/// on POSITION and validators compare them bit for bit).
fn bounds(positions: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in positions {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    (min, max)
}

/// Values that go into the BIN chunk, little-endian as glTF requires.
trait Element {
    fn write_le(&self, out: &mut Vec<u8>);
}

impl Element for [f32; 3] {
    fn write_le(&self, out: &mut Vec<u8>) {
        for v in self {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
}

impl Element for u16 {
    fn write_le(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Element for u32 {
    fn write_le(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}
