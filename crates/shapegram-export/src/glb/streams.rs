//! A primitive's accessors: each attribute and the indices of its vertices ([`View`]), encoded
//! as the file's [`GlbEncoding`] asks (float, quantised, or quantised and compressed), with what
//! the accessor and its buffer view need to describe them. Float and quantised data are encoded
//! from the vertices while the file is written, a block of a few kilobytes at a time, instead of
//! being held as another copy of the vertices until then (hundreds of megabytes for a big tube
//! model); compressed data is encoded when planned, since the JSON needs its length.

use gltf_json as json;
use json::accessor::{ComponentType, Type};
use json::mesh::Semantic;
use serde_json::Value;

use super::compact::View;
use super::compress::{self, Mode};
use super::quantize::{self, Grid};
use super::triples::{Triples, point};
use crate::GlbEncoding;
use crate::flat::unit;

/// The feature id attribute, `_FEATURE_ID_0` (gltf-json adds the underscore).
pub(crate) const FEATURE_ID: &str = "FEATURE_ID_0";

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
    /// What goes into the BIN chunk.
    data: Data,
    /// For compressed data: the codec's mode and the length of the data decoded.
    pub(crate) compressed: Option<(Mode, usize)>,
}

/// A stream's bytes in the BIN chunk.
enum Data {
    /// Encoded from the vertices of the stream's view when written.
    Deferred(Encoding),
    /// Encoded already: compressed, or a vertex pool's (small pieces whose vertices are let
    /// go: see [`Stream::encode`]).
    Bytes(Vec<u8>),
}

/// How a stream's elements are made from its view's vertices.
#[derive(Clone, Copy, Debug)]
enum Encoding {
    /// f32 triples, or i16 triples on the grid padded to 8 bytes.
    Positions(Option<Grid>),
    /// f32 triples, or normalised i8 triples padded to 4 bytes.
    Normals { quantized: bool },
    /// f32 pairs, or normalised u16 pairs.
    Uvs { quantized: bool },
    /// f32 quadruples.
    Tangents,
    /// The vertex's joint and three zeros, in u16 when `wide`, u8 otherwise.
    Joints { wide: bool },
    /// Weight 1 for the first joint, as normalized u8.
    Weights,
    /// The vertex's feature id in the component given, padded to 4 bytes.
    Features(ComponentType),
    /// The indices less the view's base, in u32 when `wide`, u16 otherwise.
    Indices { wide: bool },
}

impl Stream {
    /// A vertex attribute's stream, without bounds.
    fn attribute(
        semantic: Semantic,
        (component, kind): (ComponentType, Type),
        count: usize,
        stride: usize,
        encoding: Encoding,
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
            data: Data::Deferred(encoding),
            compressed: None,
        }
    }

    /// How many bytes it puts into the BIN chunk (before padding).
    pub(crate) fn len(&self) -> usize {
        match &self.data {
            Data::Deferred(_) => self.count * self.stride,
            Data::Bytes(bytes) => bytes.len(),
        }
    }

    /// Puts its bytes, made from `view` (the vertices it was planned from) unless they are
    /// made already.
    pub(crate) fn write(&self, view: &View<'_>, put: &mut impl FnMut(&[u8])) {
        match &self.data {
            Data::Deferred(encoding) => encoding.write(view, put),
            Data::Bytes(bytes) => put(bytes),
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

    /// Its data, made from `view`.
    fn encoded(&self, view: &View<'_>) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(self.len());
        self.write(view, &mut |b: &[u8]| bytes.extend_from_slice(b));
        bytes
    }

    /// Makes its data from `view` now, for a stream that outlives its vertices.
    pub(crate) fn encode(&mut self, view: &View<'_>) {
        self.data = Data::Bytes(self.encoded(view));
    }

    /// Replaces the data (made from `view`) with its EXT_meshopt_compression encoding: vertex
    /// attributes as ATTRIBUTES, indices as TRIANGLES (INDICES for `lines`).
    pub(crate) fn compress(&mut self, view: &View<'_>, lines: bool) {
        let mode = match self.semantic {
            Some(_) => Mode::Attributes,
            None if lines => Mode::Indices,
            None => Mode::Triangles,
        };
        let bytes = self.encoded(view);
        let encoded = compress::encode(&bytes, self.count, self.stride, mode);
        self.compressed = Some((mode, bytes.len()));
        self.data = Data::Bytes(encoded);
    }

    fn component_size(&self) -> usize {
        match self.component {
            ComponentType::I8 | ComponentType::U8 => 1,
            ComponentType::I16 | ComponentType::U16 => 2,
            ComponentType::U32 | ComponentType::F32 => 4,
        }
    }
}

impl Encoding {
    /// Puts the elements it makes of `view`'s vertices (or indices).
    fn write(self, view: &View<'_>, put: &mut impl FnMut(&[u8])) {
        match self {
            Self::Positions(None) => triple_blocks(view.positions, put, |p| floats::<3, 12>(&p)),
            Self::Positions(Some(grid)) => triple_blocks(view.positions, put, |p| {
                let [x, y, z] = grid.quantize(p).map(i16::to_le_bytes);
                [x[0], x[1], y[0], y[1], z[0], z[1], 0, 0]
            }),
            Self::Normals { quantized: false } => {
                triple_blocks(view.normals, put, |n| floats::<3, 12>(&n))
            }
            Self::Normals { quantized: true } => triple_blocks(view.normals, put, |n| {
                let [x, y, z] = quantize::normal(n);
                [x, y, z, 0].map(|b| b as u8)
            }),
            Self::Uvs { quantized: false } => blocks(view.uvs, put, floats::<2, 8>),
            Self::Uvs { quantized: true } => blocks(view.uvs, put, |&uv| {
                let [u, v] = quantize::uv(uv).map(u16::to_le_bytes);
                [u[0], u[1], v[0], v[1]]
            }),
            Self::Tangents => blocks(view.tangents, put, floats::<4, 16>),
            Self::Joints { wide: true } => blocks(view.joints, put, |&j| {
                let [a, b] = j.to_le_bytes();
                [a, b, 0, 0, 0, 0, 0, 0]
            }),
            Self::Joints { wide: false } => blocks(view.joints, put, |&j| [j as u8, 0, 0, 0]),
            Self::Weights => triple_blocks(view.positions, put, |_| [u8::MAX, 0, 0, 0]),
            Self::Features(ComponentType::U8) => {
                blocks(view.features, put, |&id| [id as u8, 0, 0, 0])
            }
            Self::Features(ComponentType::U16) => blocks(view.features, put, |&id| {
                let [a, b] = (id as u16).to_le_bytes();
                [a, b, 0, 0]
            }),
            Self::Features(_) => blocks(view.features, put, |&id| id.to_le_bytes()),
            Self::Indices { wide: true } => {
                blocks(view.indices, put, |&i| (i - view.base).to_le_bytes())
            }
            Self::Indices { wide: false } => blocks(view.indices, put, |&i| {
                ((i - view.base) as u16).to_le_bytes()
            }),
        }
    }
}

/// Puts `encode` of each of `values`, gathered in blocks of a few kilobytes: a call per
/// element would cost more than the encoding, and one buffer for all of them would be another
/// copy of the data.
fn blocks<T, const SIZE: usize>(
    values: &[T],
    put: &mut impl FnMut(&[u8]),
    encode: impl Fn(&T) -> [u8; SIZE],
) {
    let mut block = [0; 1 << 14];
    for part in values.chunks(block.len() / SIZE) {
        for (value, slot) in part.iter().zip(block.chunks_exact_mut(SIZE)) {
            slot.copy_from_slice(&encode(value));
        }
        put(&block[..part.len() * SIZE]);
    }
}

/// [`blocks`] of three-component values, each read as written (rounded to f32 from the
/// model's f64 where it is the model's).
fn triple_blocks<const SIZE: usize>(
    values: Triples<'_>,
    put: &mut impl FnMut(&[u8]),
    encode: impl Fn([f32; 3]) -> [u8; SIZE],
) {
    match values {
        Triples::F32(values) => blocks(values, put, |&v| encode(v)),
        Triples::Points(values) => blocks(values, put, |&p| encode(point(p))),
        Triples::Normals(values) => blocks(values, put, |&n| encode(unit(n))),
    }
}

/// Little-endian bytes of an f32 vector of `N` components (`M` = 4 `N` bytes).
fn floats<const N: usize, const M: usize>(v: &[f32; N]) -> [u8; M] {
    let mut bytes = [0; M];
    for (slot, x) in bytes.chunks_exact_mut(4).zip(v) {
        slot.copy_from_slice(&x.to_le_bytes());
    }
    bytes
}

/// How a primitive's vertices name their joints, for a skinned primitive.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Joints {
    /// Whether the skin needs u16 joint indices.
    pub(crate) wide: bool,
}

/// The streams of a primitive's `vertices`, in the order they are written: POSITION, NORMAL,
/// TEXCOORD_0, TANGENT, JOINTS_0, WEIGHTS_0, _FEATURE_ID_0 (in `feature_ids`' component, when
/// given), indices. `grid` quantises positions (the mesh's
/// node undoes it); `None` keeps them float, as skinned meshes need (skinning ignores the
/// node's transformation). Each stream's data is made from `vertices` when it is written
/// ([`Stream::write`]), except compressed data, made here.
pub(crate) fn streams(
    vertices: View<'_>,
    lines: bool,
    joints: Option<Joints>,
    feature_ids: Option<ComponentType>,
    encoding: GlbEncoding,
    grid: Option<&Grid>,
) -> Vec<Stream> {
    let quantized = encoding != GlbEncoding::Float;
    let count = vertices.len();
    let mut streams = Vec::with_capacity(7);
    streams.push(position_stream(vertices.positions, grid));
    let mut attribute = |semantic, format, stride, encoding| {
        streams.push(Stream::attribute(semantic, format, count, stride, encoding));
    };
    if !vertices.normals.is_empty() {
        let encoding = Encoding::Normals { quantized };
        if quantized {
            attribute(
                Semantic::Normals,
                (ComponentType::I8, Type::Vec3),
                4,
                encoding,
            );
        } else {
            attribute(
                Semantic::Normals,
                (ComponentType::F32, Type::Vec3),
                12,
                encoding,
            );
        }
    }
    if !vertices.uvs.is_empty() {
        let semantic = Semantic::TexCoords(0);
        if quantized && quantize::fits_unorm(vertices.uvs) {
            let encoding = Encoding::Uvs { quantized: true };
            attribute(semantic, (ComponentType::U16, Type::Vec2), 4, encoding);
        } else {
            let encoding = Encoding::Uvs { quantized: false };
            attribute(semantic, (ComponentType::F32, Type::Vec2), 8, encoding);
        }
    }
    if !vertices.tangents.is_empty() {
        let format = (ComponentType::F32, Type::Vec4);
        attribute(Semantic::Tangents, format, 16, Encoding::Tangents);
    }
    if let Some(Joints { wide }) = joints {
        let (component, stride) = if wide {
            (ComponentType::U16, 8)
        } else {
            (ComponentType::U8, 4)
        };
        let format = (component, Type::Vec4);
        attribute(
            Semantic::Joints(0),
            format,
            stride,
            Encoding::Joints { wide },
        );
        let format = (ComponentType::U8, Type::Vec4);
        attribute(Semantic::Weights(0), format, 4, Encoding::Weights);
    }
    if let Some(component) = feature_ids {
        let semantic = Semantic::Extras(FEATURE_ID.to_owned());
        let format = (component, Type::Scalar);
        attribute(semantic, format, 4, Encoding::Features(component));
    }
    streams.push(index_stream(vertices.indices, count));
    if encoding == GlbEncoding::Compressed {
        for stream in &mut streams {
            stream.compress(&vertices, lines);
        }
    }
    streams
}

/// The POSITION stream of `positions`, with its bounds: on `grid` as i16 triples (padded to 8
/// bytes) when given, floats otherwise.
pub(crate) fn position_stream(positions: Triples<'_>, grid: Option<&Grid>) -> Stream {
    let count = positions.len();
    let (min, max) = float_bounds(positions);
    // Putting a coordinate on the grid keeps its order (rounding and clamping are monotone),
    // so the bounds on the grid are the float bounds' points: no second pass.
    let (format, stride, bounds) = match grid {
        Some(grid) => (
            (ComponentType::I16, Type::Vec3),
            8,
            bounds(grid.quantize(min), grid.quantize(max)),
        ),
        None => ((ComponentType::F32, Type::Vec3), 12, bounds(min, max)),
    };
    let encoding = Encoding::Positions(grid.copied());
    let mut stream = Stream::attribute(Semantic::Positions, format, count, stride, encoding);
    stream.bounds = Some(bounds);
    stream
}

/// The stream of `indices` (less their view's base) into `vertex_count` vertices: u16 when
/// they fit, u32 otherwise.
pub(crate) fn index_stream(indices: &[u32], vertex_count: usize) -> Stream {
    // The largest u16 is reserved (primitive restart), hence `>=`.
    let wide = vertex_count >= usize::from(u16::MAX);
    let (component, stride) = if wide {
        (ComponentType::U32, 4)
    } else {
        (ComponentType::U16, 2)
    };
    Stream {
        semantic: None,
        count: indices.len(),
        stride,
        component,
        kind: Type::Scalar,
        normalized: false,
        bounds: None,
        data: Data::Deferred(Encoding::Indices { wide }),
        compressed: None,
    }
}

/// Component-wise min and max of `positions` (at least one), exactly as written (the spec
/// requires them on POSITION and validators compare them bit for bit).
fn float_bounds(positions: Triples<'_>) -> ([f32; 3], [f32; 3]) {
    assert!(!positions.is_empty(), "a stream of positions has one");
    let first = positions.get(0);
    let (mut min, mut max) = (first, first);
    positions.for_each(|v| {
        for k in 0..3 {
            if v[k] < min[k] {
                min[k] = v[k];
            }
            if v[k] > max[k] {
                max[k] = v[k];
            }
        }
    });
    (min, max)
}

/// `min` and `max` as the accessor's JSON arrays.
fn bounds<T: Into<Value>>(min: [T; 3], max: [T; 3]) -> (Value, Value) {
    let array = |v: [T; 3]| Value::Array(v.into_iter().map(Into::into).collect());
    (array(min), array(max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_on_the_grid_are_those_of_the_positions_put_on_it() {
        // Scattered points, with extremes on different points per axis and a -0.0 beside 0.0.
        let positions: Vec<[f32; 3]> = (0..500)
            .map(|i| {
                let t = i as f32;
                [
                    (t * 0.37).sin() * 9.5,
                    (t * 1.3).cos() * 0.01 - 4.0,
                    (t * 0.11).tan(),
                ]
            })
            .chain([[0.0, -0.0, 1e-3], [-0.0, 0.0, -1e-3]])
            .collect();
        let grid = Grid::spanning([-9.5, -4.1, -40.0], [9.5, -3.9, 40.0]);
        let stream = position_stream(Triples::F32(&positions), Some(&grid));
        let quantized: Vec<[i16; 3]> = positions.iter().map(|&p| grid.quantize(p)).collect();
        let extreme = |pick: fn(i16, i16) -> i16| {
            std::array::from_fn::<i16, 3, _>(|k| {
                quantized.iter().map(|q| q[k]).reduce(pick).unwrap()
            })
        };
        let (min, max) = stream.bounds.expect("positions have bounds");
        assert_eq!(min, serde_json::json!(extreme(i16::min)));
        assert_eq!(max, serde_json::json!(extreme(i16::max)));
        let floats = position_stream(Triples::F32(&positions), None);
        let (min, _) = floats.bounds.unwrap();
        let lowest = positions.iter().map(|p| p[0]).reduce(f32::min).unwrap();
        assert_eq!(min[0], serde_json::json!(lowest));
    }
}
