//! `shapegram.Mesh` and `shapegram.Part`: a derivation's buffers as Python objects.

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};
use shapegram_export::Buffers;
use shapegram_geom::Color;

/// The mesh buffers of a derivation: flat `array.array`s (`positions` and `normals` of type
/// `"f"`, three floats per vertex, y up; `indices` of type `"I"`, three per triangle, counted
/// from the first vertex) and the parts with their ranges. Blender's `foreach_set` copies them
/// in one go, `numpy.frombuffer` views them; each is the caller's own copy.
#[pyclass(module = "shapegram", frozen, get_all)]
pub struct Mesh {
    /// Vertex positions, `3 * vertex_count` floats.
    positions: Py<PyAny>,
    /// Unit vertex normals, `3 * vertex_count` floats.
    normals: Py<PyAny>,
    /// Triangle indices, `3 * triangle_count` unsigned 32-bit integers.
    indices: Py<PyAny>,
    /// The parts, in model order.
    parts: Py<PyTuple>,
    /// Number of vertices.
    vertex_count: usize,
    /// Number of triangles.
    triangle_count: usize,
}

/// One part of a mesh: its name, colour and ranges in the buffers.
#[pyclass(module = "shapegram", frozen, get_all)]
pub struct Part {
    /// The rule or symbol that made it.
    name: String,
    /// sRGB colour with straight alpha, `(r, g, b, a)` in 0..1.
    color: (f32, f32, f32, f32),
    /// The colour as the grammar writes it: `#rrggbb`, or `#rrggbbaa` when not opaque.
    color_hex: String,
    /// Its first vertex.
    first_vertex: u32,
    /// How many vertices it has.
    vertex_count: u32,
    /// Its first index.
    first_index: u32,
    /// How many indices it has (three per triangle).
    index_count: u32,
}

#[pymethods]
impl Part {
    fn __repr__(&self) -> String {
        format!(
            "Part(name={:?}, color_hex={:?}, vertices={}..{}, indices={}..{})",
            self.name,
            self.color_hex,
            self.first_vertex,
            self.first_vertex + self.vertex_count,
            self.first_index,
            self.first_index + self.index_count
        )
    }
}

#[pymethods]
impl Mesh {
    fn __repr__(&self) -> String {
        format!(
            "Mesh({} vertices, {} triangles)",
            self.vertex_count, self.triangle_count
        )
    }
}

/// `values` as an `array.array` of `typecode`. An array, not a memoryview: Blender's
/// `foreach_set` asks for the buffer without its format, which a memoryview of floats refuses.
fn view<'py, T: Copy, const N: usize>(
    py: Python<'py>,
    values: &[T],
    typecode: &str,
    to_bytes: impl Fn(T) -> [u8; N],
) -> PyResult<Py<PyAny>> {
    let bytes = PyBytes::new_with(py, values.len() * N, |out| {
        for (chunk, &value) in out.chunks_exact_mut(N).zip(values) {
            chunk.copy_from_slice(&to_bytes(value));
        }
        Ok(())
    })?;
    let array = py.import("array")?.getattr("array")?;
    Ok(array.call1((typecode, bytes))?.unbind())
}

impl Mesh {
    /// The Python objects of `buffers`, whose parts are named `names`.
    pub fn new(py: Python<'_>, buffers: &Buffers, names: Vec<String>) -> PyResult<Self> {
        let parts = buffers
            .parts
            .iter()
            .zip(names)
            .map(|(p, name)| {
                let [r, g, b, a] = p.color;
                Part {
                    name,
                    color: (r, g, b, a),
                    color_hex: Color { r, g, b, a }.to_hex(),
                    first_vertex: p.first_vertex,
                    vertex_count: p.vertex_count,
                    first_index: p.first_index,
                    index_count: p.index_count,
                }
            })
            .map(|part| Py::new(py, part))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(Self {
            positions: view(py, buffers.positions.as_flattened(), "f", f32::to_ne_bytes)?,
            normals: view(py, buffers.normals.as_flattened(), "f", f32::to_ne_bytes)?,
            indices: view(py, &buffers.indices, "I", u32::to_ne_bytes)?,
            parts: PyTuple::new(py, parts)?.unbind(),
            vertex_count: buffers.positions.len(),
            triangle_count: buffers.indices.len() / 3,
        })
    }
}
