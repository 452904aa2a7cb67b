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
    /// Texture coordinates as glTF has them (v down), `2 * vertex_count` floats when some
    /// part is textured (0, 0 for the others' vertices); empty when none is.
    uvs: Py<PyAny>,
    /// The images the textured parts use (`Part.texture` indexes them).
    textures: Py<PyTuple>,
    /// The skeletons' joints, parents before their children; empty without a skeleton.
    joints: Py<PyTuple>,
    /// Per vertex when some part hangs from a joint: its joint's index in `joints`,
    /// `NO_JOINT` for a vertex that hangs from none; empty when no part hangs from a joint.
    vertex_joints: Py<PyAny>,
}

/// An image a textured part is drawn with.
#[pyclass(module = "shapegram", frozen, get_all)]
pub struct Texture {
    /// Its path as the grammar named it.
    path: String,
    /// The image file's bytes (PNG or JPEG, undecoded).
    data: Py<PyBytes>,
}

/// A joint of a skeleton (see `docs/runtimes.md`): the vertices are in the derived pose, so
/// posing joint `j` anew moves the vertices hanging from it by `world_new(j) · world(j)⁻¹`,
/// `world` multiplying the `translation`/`rotation` frames from the root down.
#[pyclass(module = "shapegram", frozen, get_all)]
pub struct Joint {
    /// The section's name, the same when derived again (`Boom_5d7b45`).
    name: String,
    /// The skeleton it belongs to.
    skeleton: u32,
    /// Its parent's index in `Mesh.joints`; `None` for a root.
    parent: Option<u32>,
    /// Translation relative to the parent in the derived pose, metres.
    translation: (f32, f32, f32),
    /// Rotation relative to the parent in the derived pose, a quaternion `(x, y, z, w)`.
    rotation: (f32, f32, f32, f32),
    /// Translation relative to the parent at rest.
    rest_translation: (f32, f32, f32),
    /// Rotation relative to the parent at rest, `(x, y, z, w)`.
    rest_rotation: (f32, f32, f32, f32),
    /// The pose: degrees about x, then y, then z (fixed axes).
    pose_rotation_deg: (f32, f32, f32),
    /// The pose's translation along the joint's axes, metres.
    pose_translation_m: (f32, f32, f32),
    /// Per axis: `(least, greatest)` rotation in degrees.
    rotation_limits_deg: ((f32, f32), (f32, f32), (f32, f32)),
    /// Per axis: `(least, greatest)` translation in metres.
    translation_limits_m: ((f32, f32), (f32, f32), (f32, f32)),
}

#[pymethods]
impl Joint {
    fn __repr__(&self) -> String {
        format!("Joint(name={:?}, parent={:?})", self.name, self.parent)
    }
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
    /// Its colour map's index in `Mesh.textures`, `None` when it has none.
    texture: Option<u32>,
    /// The material's name the grammar set (`set(material.name, …)`), `None` when it set none.
    material: Option<String>,
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
    /// The Python objects of `buffers`, whose parts have the names and material names `names`.
    pub fn new(
        py: Python<'_>,
        buffers: &Buffers,
        names: Vec<(String, Option<String>)>,
    ) -> PyResult<Self> {
        let parts = buffers
            .parts
            .iter()
            .zip(names)
            .map(|(p, (name, material))| {
                let [r, g, b, a] = p.color;
                Part {
                    name,
                    color: (r, g, b, a),
                    color_hex: Color { r, g, b, a }.to_hex(),
                    first_vertex: p.first_vertex,
                    vertex_count: p.vertex_count,
                    first_index: p.first_index,
                    index_count: p.index_count,
                    texture: p.texture,
                    material,
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
            uvs: view(py, buffers.uvs.as_flattened(), "f", f32::to_ne_bytes)?,
            textures: PyTuple::new(
                py,
                buffers
                    .textures
                    .iter()
                    .map(|t| {
                        let data = PyBytes::new(py, t.image.as_deref().unwrap_or_default());
                        Py::new(
                            py,
                            Texture {
                                path: t.path.to_string(),
                                data: data.unbind(),
                            },
                        )
                    })
                    .collect::<PyResult<Vec<_>>>()?,
            )?
            .unbind(),
            joints: PyTuple::new(
                py,
                buffers
                    .joints
                    .iter()
                    .map(|j| Py::new(py, Joint::of(j)))
                    .collect::<PyResult<Vec<_>>>()?,
            )?
            .unbind(),
            vertex_joints: view(py, &buffers.vertex_joints, "I", u32::to_ne_bytes)?,
        })
    }
}

impl Joint {
    /// The Python object of a buffers' joint.
    fn of(j: &shapegram_export::BufferJoint) -> Self {
        let pair = |[a, b]: [f32; 2]| (a, b);
        let three = |[x, y, z]: [f32; 3]| (x, y, z);
        let four = |[x, y, z, w]: [f32; 4]| (x, y, z, w);
        let limits = |[x, y, z]: [[f32; 2]; 3]| (pair(x), pair(y), pair(z));
        Self {
            name: j.name.clone(),
            skeleton: j.skeleton,
            parent: j.parent,
            translation: three(j.translation),
            rotation: four(j.rotation),
            rest_translation: three(j.rest_translation),
            rest_rotation: four(j.rest_rotation),
            pose_rotation_deg: three(j.pose_rotation_deg),
            pose_translation_m: three(j.pose_translation_m),
            rotation_limits_deg: limits(j.rotation_limits_deg),
            translation_limits_m: limits(j.translation_limits_m),
        }
    }
}
