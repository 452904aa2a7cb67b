//! EXT_meshopt_compression: buffer views whose data is meshoptimizer's vertex or index codec,
//! kept in the BIN chunk, over views of a fallback buffer without data (so the extension is
//! required). Encoding for the writer, decoding for the reader.

use serde_json::{Value, json};

/// The extension's name, in `extensionsUsed` and `extensionsRequired`.
pub(crate) const EXTENSION: &str = "EXT_meshopt_compression";

/// How a view's data was encoded: the extension's `mode`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Vertex attributes (the vertex codec; stride a multiple of 4).
    Attributes,
    /// A triangle list's indices (the index codec).
    Triangles,
    /// Any other index list, such as a line list's.
    Indices,
}

impl Mode {
    fn name(self) -> &'static str {
        match self {
            Self::Attributes => "ATTRIBUTES",
            Self::Triangles => "TRIANGLES",
            Self::Indices => "INDICES",
        }
    }

    fn of_name(name: &str) -> Option<Self> {
        match name {
            "ATTRIBUTES" => Some(Self::Attributes),
            "TRIANGLES" => Some(Self::Triangles),
            "INDICES" => Some(Self::Indices),
            _ => None,
        }
    }
}

/// `data` (`count` elements of `stride` bytes) encoded in `mode`. The vertex codec is held to
/// version 0, the one EXT_meshopt_compression defines.
pub(crate) fn encode(data: &[u8], count: usize, stride: usize, mode: Mode) -> Vec<u8> {
    let encoded = match mode {
        Mode::Attributes => encode_vertices(data, stride),
        Mode::Triangles | Mode::Indices => {
            let indices = widen(data, stride);
            let vertices = indices.iter().max().map_or(0, |&i| i as usize + 1);
            if mode == Mode::Triangles {
                meshopt::encode_index_buffer(&indices, vertices)
            } else {
                meshopt::encode_index_sequence(&indices, vertices)
            }
        }
    };
    debug_assert_eq!(count * stride, data.len());
    encoded.expect("meshoptimizer encodes any data that fits its bound")
}

/// The vertex codec over elements of `stride` bytes (4 to 256, a multiple of 4).
fn encode_vertices(data: &[u8], stride: usize) -> meshopt::Result<Vec<u8>> {
    macro_rules! by_stride {
        ($($n:literal)*) => {
            match stride {
                $($n => meshopt::encode_vertex_buffer_level(as_elements::<$n>(data), 2, Some(0)),)*
                _ => unreachable!("vertex attributes are 4, 8, 12 or 16 bytes"),
            }
        };
    }
    by_stride!(4 8 12 16)
}

/// `data` as elements of `N` bytes.
fn as_elements<const N: usize>(data: &[u8]) -> &[[u8; N]] {
    let (elements, rest) = data.as_chunks::<N>();
    debug_assert!(rest.is_empty());
    elements
}

/// Little-endian indices of `size` bytes (2 or 4) as u32.
fn widen(data: &[u8], size: usize) -> Vec<u32> {
    match size {
        2 => as_elements::<2>(data)
            .iter()
            .map(|b| u32::from(u16::from_le_bytes(*b)))
            .collect(),
        _ => as_elements::<4>(data)
            .iter()
            .map(|b| u32::from_le_bytes(*b))
            .collect(),
    }
}

/// The bufferView extension object for data at `offset` in buffer 0, `length` bytes long.
pub(crate) fn view_extension(
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
) -> Value {
    json!({
        "buffer": 0,
        "byteOffset": offset,
        "byteLength": length,
        "byteStride": stride,
        "count": count,
        "mode": mode.name(),
    })
}

/// The fallback buffer's extension object: no reader needs its (absent) data.
pub(crate) fn fallback_extension() -> Value {
    json!({ "fallback": true })
}

/// Decodes every compressed buffer view of a glTF document in place: the decoded data is
/// appended to a copy of `bin`, each view points there in buffer 0 and loses its extension,
/// and fallback buffers become empty placeholders. Returns the new BIN data; errors say which
/// view is broken.
pub(crate) fn decode_views(root: &mut Value, bin: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = bin.to_vec();
    let Some(views) = root.get_mut("bufferViews").and_then(Value::as_array_mut) else {
        return Ok(out);
    };
    for (v, view) in views.iter_mut().enumerate() {
        let Some(extension) = view
            .get_mut("extensions")
            .and_then(Value::as_object_mut)
            .and_then(|e| e.remove(EXTENSION))
        else {
            continue;
        };
        let broken = |what: &str| format!("bufferView {v}: EXT_meshopt_compression {what}");
        let field = |name: &str| {
            extension
                .get(name)
                .and_then(Value::as_u64)
                .and_then(|n| usize::try_from(n).ok())
        };
        if field("buffer") != Some(0) {
            return Err(broken("data outside the BIN chunk is not supported"));
        }
        let offset = field("byteOffset").unwrap_or(0);
        let length = field("byteLength").ok_or_else(|| broken("has no byteLength"))?;
        let stride = field("byteStride").ok_or_else(|| broken("has no byteStride"))?;
        let count = field("count").ok_or_else(|| broken("has no count"))?;
        let mode = extension
            .get("mode")
            .and_then(Value::as_str)
            .and_then(Mode::of_name)
            .ok_or_else(|| broken("has no known mode"))?;
        if extension
            .get("filter")
            .and_then(Value::as_str)
            .is_some_and(|f| f != "NONE")
        {
            return Err(broken("filters are not supported"));
        }
        let data = offset
            .checked_add(length)
            .and_then(|end| bin.get(offset..end))
            .ok_or_else(|| broken("data runs past the BIN chunk"))?;
        let decoded = decode(data, count, stride, mode).map_err(|e| broken(&e))?;
        let start = out.len().next_multiple_of(4);
        out.resize(start, 0);
        out.extend_from_slice(&decoded);
        view["buffer"] = json!(0);
        view["byteOffset"] = json!(start);
        view["byteLength"] = json!(decoded.len());
    }
    Ok(out)
}

/// One view's data decoded: `count` elements of `stride` bytes.
fn decode(data: &[u8], count: usize, stride: usize, mode: Mode) -> Result<Vec<u8>, String> {
    // Decoders write `count · stride` bytes: refuse sizes no GLB could hold before allocating.
    if count
        .checked_mul(stride)
        .is_none_or(|n| n > u32::MAX as usize)
    {
        return Err(format!("{count} elements of {stride} bytes are too many"));
    }
    let failed = |e: meshopt::Error| format!("data cannot be decoded ({e})");
    match (mode, stride) {
        (Mode::Attributes, 4) => bytes(meshopt::decode_vertex_buffer::<[u8; 4]>(data, count)),
        (Mode::Attributes, 8) => bytes(meshopt::decode_vertex_buffer::<[u8; 8]>(data, count)),
        (Mode::Attributes, 12) => bytes(meshopt::decode_vertex_buffer::<[u8; 12]>(data, count)),
        (Mode::Attributes, 16) => bytes(meshopt::decode_vertex_buffer::<[u8; 16]>(data, count)),
        (Mode::Triangles, 2) => indices(meshopt::decode_index_buffer::<u16>(data, count)),
        (Mode::Triangles, 4) => indices(meshopt::decode_index_buffer::<u32>(data, count)),
        (Mode::Indices, 2) => indices(meshopt::decode_index_sequence::<u16>(data, count)),
        (Mode::Indices, 4) => indices(meshopt::decode_index_sequence::<u32>(data, count)),
        _ => return Err(format!("byteStride {stride} is not supported in this mode")),
    }
    .map_err(failed)
}

/// Decoded vertex elements as bytes.
fn bytes<const N: usize>(decoded: meshopt::Result<Vec<[u8; N]>>) -> meshopt::Result<Vec<u8>> {
    decoded.map(|elements| elements.into_flattened())
}

/// Decoded indices as little-endian bytes.
fn indices<T: IndexBytes>(decoded: meshopt::Result<Vec<T>>) -> meshopt::Result<Vec<u8>> {
    decoded.map(|indices| indices.iter().flat_map(|i| i.le_bytes()).collect())
}

/// An index type's little-endian bytes.
trait IndexBytes {
    fn le_bytes(&self) -> Vec<u8>;
}

impl IndexBytes for u16 {
    fn le_bytes(&self) -> Vec<u8> {
        self.to_le_bytes().to_vec()
    }
}

impl IndexBytes for u32 {
    fn le_bytes(&self) -> Vec<u8> {
        self.to_le_bytes().to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_and_indices_come_back_as_they_went_in() {
        let vertices: Vec<u8> = (0..48u8).collect();
        let encoded = encode(&vertices, 4, 12, Mode::Attributes);
        assert_eq!(decode(&encoded, 4, 12, Mode::Attributes).unwrap(), vertices);
        let triangles: Vec<u8> = [0u16, 1, 2, 2, 1, 3]
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let encoded = encode(&triangles, 6, 2, Mode::Triangles);
        assert_eq!(decode(&encoded, 6, 2, Mode::Triangles).unwrap(), triangles);
        let lines: Vec<u8> = [0u32, 1, 1, 2]
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let encoded = encode(&lines, 4, 4, Mode::Indices);
        assert_eq!(decode(&encoded, 4, 4, Mode::Indices).unwrap(), lines);
        assert!(decode(&encoded[..2], 4, 4, Mode::Indices).is_err());
    }
}
