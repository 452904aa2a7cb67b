//! A primitive's accessors as bytes: each attribute and the indices of its vertices ([`View`]),
//! encoded as the file's [`GlbEncoding`] asks (float, quantised, or quantised and compressed),
//! with what the accessor and its buffer view need to describe them.

use gltf_json as json;
use json::accessor::{ComponentType, Type};
use json::mesh::Semantic;
use serde_json::Value;

use super::compact::View;
use super::compress::{self, Mode};
use super::quantize::{self, Grid};
use crate::GlbEncoding;

/// One accessor's data and description.
pub(crate) struct Stream {
    /// The attribute it holds; `None` for indices.
    pub(crate) semantic: Option<Semantic>,
    pub(crate) count: usize,
    /// Bytes from one element to the next (the element's size, padded to 4 bytes for vertex
    /// attributes).
    pub(crate) stride: usize,
    pub(crate) component: ComponentType,
    pub(crate) kind: Type,
    pub(crate) normalized: bool,
    /// `min` and `max`, for POSITION.
    pub(crate) bounds: Option<(Value, Value)>,
    /// What goes into the BIN chunk: the data, or its compressed form.
    pub(crate) bytes: Vec<u8>,
    /// For compressed data: the codec's mode and the length of the data decoded.
    pub(crate) compressed: Option<(Mode, usize)>,
}

impl Stream {
    /// A vertex attribute's stream, without bounds.
    fn attribute(
        semantic: Semantic,
        (component, kind): (ComponentType, Type),
        count: usize,
        stride: usize,
        bytes: Vec<u8>,
    ) -> Self {
        let normalized = matches!(semantic, Semantic::Normals | Semantic::TexCoords(_))
            && component != ComponentType::F32
            || matches!(semantic, Semantic::Weights(_));
        Self {
            semantic: Some(semantic),
            count,
            stride,
            component,
            kind,
            normalized,
            bounds: None,
            bytes,
            compressed: None,
        }
    }

    /// Whether its buffer view states a stride: vertex attributes padded or compressed.
    pub(crate) fn strided(&self) -> bool {
        let element = self.component_size() * self.kind.multiplicity();
        self.semantic.is_some() && (self.stride != element || self.compressed.is_some())
    }

    /// Whether it is a position, normal or uv in integers, which glTF allows only with
    /// KHR_mesh_quantization.
    pub(crate) fn quantized(&self) -> bool {
        matches!(
            self.semantic,
            Some(Semantic::Positions | Semantic::Normals | Semantic::TexCoords(_))
        ) && self.component != ComponentType::F32
    }

    /// Replaces the data with its EXT_meshopt_compression encoding: vertex attributes as
    /// ATTRIBUTES, indices as TRIANGLES (INDICES for `lines`).
    pub(crate) fn compress(&mut self, lines: bool) {
        let mode = match self.semantic {
            Some(_) => Mode::Attributes,
            None if lines => Mode::Indices,
            None => Mode::Triangles,
        };
        let encoded = compress::encode(&self.bytes, self.count, self.stride, mode);
        self.compressed = Some((mode, self.bytes.len()));
        self.bytes = encoded;
    }

    fn component_size(&self) -> usize {
        match self.component {
            ComponentType::I8 | ComponentType::U8 => 1,
            ComponentType::I16 | ComponentType::U16 => 2,
            ComponentType::U32 | ComponentType::F32 => 4,
        }
    }
}

/// How a primitive's vertices name their joints, for a skinned primitive.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Joints {
    /// Whether the skin needs u16 joint indices.
    pub(crate) wide: bool,
}

/// The streams of a primitive's `vertices`, in the order they are written: POSITION, NORMAL,
/// TEXCOORD_0, TANGENT, JOINTS_0, WEIGHTS_0, indices. `grid` quantises positions (the mesh's
/// node undoes it); `None` keeps them float, as skinned meshes need (skinning ignores the
/// node's transformation).
pub(crate) fn streams(
    vertices: View<'_>,
    lines: bool,
    joints: Option<Joints>,
    encoding: GlbEncoding,
    grid: Option<&Grid>,
) -> Vec<Stream> {
    let quantized = encoding != GlbEncoding::Float;
    let count = vertices.len();
    let mut streams = Vec::with_capacity(7);
    streams.push(position_stream(vertices.positions, grid));
    let mut attribute = |semantic, format, stride, bytes| {
        streams.push(Stream::attribute(semantic, format, count, stride, bytes));
    };
    if !vertices.normals.is_empty() {
        if quantized {
            let bytes = vertices
                .normals
                .iter()
                .flat_map(|&n| {
                    let [x, y, z] = quantize::normal(n);
                    [x, y, z, 0].map(|b| b as u8)
                })
                .collect();
            attribute(Semantic::Normals, (ComponentType::I8, Type::Vec3), 4, bytes);
        } else {
            let bytes = floats(vertices.normals);
            attribute(
                Semantic::Normals,
                (ComponentType::F32, Type::Vec3),
                12,
                bytes,
            );
        }
    }
    if !vertices.uvs.is_empty() {
        if quantized && quantize::fits_unorm(vertices.uvs) {
            let bytes = vertices
                .uvs
                .iter()
                .flat_map(|&uv| quantize::uv(uv))
                .flat_map(u16::to_le_bytes)
                .collect();
            attribute(
                Semantic::TexCoords(0),
                (ComponentType::U16, Type::Vec2),
                4,
                bytes,
            );
        } else {
            let bytes = floats(vertices.uvs);
            attribute(
                Semantic::TexCoords(0),
                (ComponentType::F32, Type::Vec2),
                8,
                bytes,
            );
        }
    }
    if !vertices.tangents.is_empty() {
        let bytes = floats(vertices.tangents);
        attribute(
            Semantic::Tangents,
            (ComponentType::F32, Type::Vec4),
            16,
            bytes,
        );
    }
    if let Some(Joints { wide }) = joints {
        let (bytes, component, stride) = if wide {
            let bytes = vertices
                .joints
                .iter()
                .flat_map(|&j| [j, 0, 0, 0])
                .flat_map(u16::to_le_bytes)
                .collect();
            (bytes, ComponentType::U16, 8)
        } else {
            let bytes = vertices
                .joints
                .iter()
                .flat_map(|&j| [j as u8, 0, 0, 0])
                .collect();
            (bytes, ComponentType::U8, 4)
        };
        attribute(Semantic::Joints(0), (component, Type::Vec4), stride, bytes);
        // Weight 1 for the first joint, as normalized u8.
        let weights = [u8::MAX, 0, 0, 0].repeat(count);
        attribute(
            Semantic::Weights(0),
            (ComponentType::U8, Type::Vec4),
            4,
            weights,
        );
    }
    streams.push(index_stream(vertices.indices, vertices.base, count));
    if encoding == GlbEncoding::Compressed {
        for stream in &mut streams {
            stream.compress(lines);
        }
    }
    streams
}

/// The POSITION stream of `positions`, with its bounds: on `grid` as i16 triples (padded to 8
/// bytes) when given, floats otherwise.
pub(crate) fn position_stream(positions: &[[f32; 3]], grid: Option<&Grid>) -> Stream {
    let count = positions.len();
    match grid {
        Some(grid) => {
            let quantized: Vec<[i16; 3]> = positions.iter().map(|&p| grid.quantize(p)).collect();
            let bytes = quantized
                .iter()
                .flat_map(|q| [q[0], q[1], q[2], 0])
                .flat_map(i16::to_le_bytes)
                .collect();
            let mut stream = Stream::attribute(
                Semantic::Positions,
                (ComponentType::I16, Type::Vec3),
                count,
                8,
                bytes,
            );
            stream.bounds = Some(bounds(&quantized, Value::from));
            stream
        }
        None => {
            let mut stream = Stream::attribute(
                Semantic::Positions,
                (ComponentType::F32, Type::Vec3),
                count,
                12,
                floats(positions),
            );
            stream.bounds = Some(bounds(positions, Value::from));
            stream
        }
    }
}

/// The stream of `indices` less `base` into `vertex_count` vertices: u16 when they fit, u32
/// otherwise.
pub(crate) fn index_stream(indices: &[u32], base: u32, vertex_count: usize) -> Stream {
    // The largest u16 is reserved (primitive restart), hence `>=`.
    let (component, stride, bytes) = if vertex_count >= usize::from(u16::MAX) {
        let mut bytes = Vec::with_capacity(4 * indices.len());
        indices
            .iter()
            .for_each(|i| bytes.extend_from_slice(&(i - base).to_le_bytes()));
        (ComponentType::U32, 4, bytes)
    } else {
        let mut bytes = Vec::with_capacity(2 * indices.len());
        indices
            .iter()
            .for_each(|&i| bytes.extend_from_slice(&((i - base) as u16).to_le_bytes()));
        (ComponentType::U16, 2, bytes)
    };
    Stream {
        semantic: None,
        count: indices.len(),
        stride,
        component,
        kind: Type::Scalar,
        normalized: false,
        bounds: None,
        bytes,
        compressed: None,
    }
}

/// Little-endian bytes of f32 vectors, in a buffer sized once: collecting a flattened iterator
/// grows it by doubling, which for the hundreds of megabytes of a big mesh means copies and
/// page faults several times over.
fn floats<const N: usize>(values: &[[f32; N]]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(values.len() * N * 4);
    for v in values {
        for x in v {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    bytes
}

/// Component-wise min and max of `values`, exactly as written (the spec requires them on
/// POSITION and validators compare them bit for bit).
fn bounds<T: Copy + PartialOrd>(values: &[[T; 3]], json: impl Fn(T) -> Value) -> (Value, Value) {
    let mut min = values[0];
    let mut max = values[0];
    for v in values {
        for k in 0..3 {
            if v[k] < min[k] {
                min[k] = v[k];
            }
            if v[k] > max[k] {
                max[k] = v[k];
            }
        }
    }
    let array = |v: [T; 3]| Value::Array(v.into_iter().map(&json).collect());
    (array(min), array(max))
}
