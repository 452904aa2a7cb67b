//! Readers for GLB, OBJ and STL. Input is untrusted: every problem is an `Err`, never a panic.
//!
//! Meshes come back with the vertices as the file stores them (GLB and STL: one per corner or
//! per flat-shaded face); weld with [`Mesh::welded`] to recover connectivity. Parts without faces
//! are dropped, as the writers drop them.

use std::borrow::Cow;
use std::io::Cursor;
use std::path::Path;

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use shapegram_geom::{Color, DAffine3, DVec3, Mesh, Model, Part};

use crate::glb::{CHUNK_BIN, CHUNK_JSON, MAGIC};
use crate::{Error, Format};

/// Reads a GLB file (binary glTF 2.0): triangle primitives of the default scene, in world
/// coordinates, one part per primitive named after its node, coloured by `baseColorFactor`.
/// Points and lines are skipped; strips and fans become triangles.
pub fn read_glb(bytes: &[u8]) -> Result<Model, Error> {
    let broken = |message: String| Error::broken(Format::Glb, message);
    let (json, bin) = split_glb(bytes).map_err(broken)?;
    let root: gltf::json::Root =
        serde_json::from_slice(json).map_err(|e| broken(format!("invalid JSON chunk: {e}")))?;
    // gltf 1.4's validation indexes `accessors` with the POSITION index before checking it.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &primitive.attributes {
                if accessor.value() >= root.accessors.len() {
                    return Err(broken(format!(
                        "mesh {m} primitive {p}: attribute {} refers to missing accessor {}",
                        semantic.to_string(),
                        accessor.value()
                    )));
                }
            }
        }
    }
    // Our own framing above replaces `Gltf::from_slice`, whose header check underflows on
    // lengths below 12; the document is the same. gltf's message already starts with
    // "invalid glTF:" and ends every problem with ';'.
    let document = gltf::Document::from_json(root)
        .map_err(|e| broken(e.to_string().trim_end_matches(';').to_owned()))?;
    let blob = bin.unwrap_or_default();
    let mut parts = Vec::new();
    for (node, world) in scene_nodes(&document).map_err(broken)? {
        let Some(mesh) = node.mesh() else {
            continue;
        };
        let name = node
            .name()
            .or(mesh.name())
            .map_or_else(|| format!("node{}", node.index()), str::to_owned);
        for primitive in mesh.primitives() {
            let context = |e: String| {
                broken(format!(
                    "mesh {} primitive {}: {e}",
                    mesh.index(),
                    primitive.index()
                ))
            };
            let Some(mut part_mesh) = read_primitive(&primitive, blob).map_err(context)? else {
                continue;
            };
            part_mesh.transform(&world);
            // glTF colour factors are linear light; our colours are sRGB.
            let factor = primitive
                .material()
                .pbr_metallic_roughness()
                .base_color_factor();
            push_part(
                &mut parts,
                name.clone(),
                Color::from_linear(factor),
                part_mesh,
            );
        }
    }
    Ok(Model {
        parts,
        lines: Vec::new(),
    })
}

/// Splits GLB bytes into the JSON chunk and the optional BIN chunk, checking every length.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        let b = bytes.get(at..at.checked_add(4)?)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    if bytes.len() < 12 {
        return Err(format!(
            "{} bytes is too short for a GLB header",
            bytes.len()
        ));
    }
    if &bytes[..4] != MAGIC {
        return Err("not a GLB file (it does not start with 'glTF')".to_owned());
    }
    let version = word(4).unwrap_or_default();
    if version != 2 {
        return Err(format!("GLB version {version} is not supported (only 2)"));
    }
    let length = word(8).unwrap_or_default() as usize;
    if length > bytes.len() {
        return Err(format!(
            "truncated: the header says {length} bytes but there are {}",
            bytes.len()
        ));
    }
    let mut at = 12;
    let mut chunk = || -> Result<Option<(u32, &[u8])>, String> {
        if at >= length {
            return Ok(None);
        }
        let (Some(size), Some(kind)) = (word(at), word(at + 4)) else {
            return Err(format!("truncated chunk header at byte {at}"));
        };
        let start = at + 8;
        let end = start
            .checked_add(size as usize)
            .filter(|&end| end <= length)
            .ok_or_else(|| format!("truncated: chunk at byte {at} runs past the end"))?;
        at = end;
        Ok(Some((kind, &bytes[start..end])))
    };
    let json = match chunk()? {
        Some((CHUNK_JSON, json)) => json,
        _ => return Err("the first chunk is not JSON".to_owned()),
    };
    // The spec allows further chunks of unknown types after BIN; readers ignore them.
    let bin = match chunk()? {
        Some((CHUNK_BIN, bin)) => Some(bin),
        _ => None,
    };
    Ok((json, bin))
}

/// Nodes of the default scene (or the first, or, without scenes, every root) in depth-first
/// order with their world transforms.
fn scene_nodes(document: &gltf::Document) -> Result<Vec<(gltf::Node<'_>, DAffine3)>, String> {
    let roots: Vec<gltf::Node<'_>> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; document.nodes().len()];
            for node in document.nodes() {
                for child in node.children() {
                    is_child[child.index()] = true;
                }
            }
            document.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut seen = vec![false; document.nodes().len()];
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node<'_>, DAffine3)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DAffine3::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        // A node reached twice means a cycle or a shared child; the spec requires a tree.
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(format!(
                "node {} appears twice in the hierarchy",
                node.index()
            ));
        }
        let m = node.transform().matrix();
        let column = |c: usize| DVec3::new(m[c][0].into(), m[c][1].into(), m[c][2].into());
        let world = parent * DAffine3::from_cols(column(0), column(1), column(2), column(3));
        let children: Vec<_> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
        out.push((node, world));
    }
    Ok(out)
}

/// The triangles of a primitive as a mesh in node space, or `None` for points and lines.
fn read_primitive(primitive: &gltf::Primitive<'_>, blob: &[u8]) -> Result<Option<Mesh>, String> {
    if matches!(
        primitive.mode(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
    ) {
        return Ok(None);
    }
    let position = primitive
        .get(&gltf::Semantic::Positions)
        .ok_or("no POSITION attribute")?;
    check_accessor(&position, blob, &[DataType::F32], Dimensions::Vec3)
        .map_err(|e| format!("POSITION: {e}"))?;
    if let Some(indices) = primitive.indices() {
        check_accessor(
            &indices,
            blob,
            &[DataType::U8, DataType::U16, DataType::U32],
            Dimensions::Scalar,
        )
        .map_err(|e| format!("indices: {e}"))?;
    }
    let reader = primitive.reader(|buffer| match buffer.source() {
        gltf::buffer::Source::Bin => Some(blob),
        gltf::buffer::Source::Uri(_) => None,
    });
    let positions: Vec<DVec3> = reader
        .read_positions()
        .ok_or("POSITION data is unreadable")?
        .map(|p| DVec3::from(p.map(f64::from)))
        .collect();
    let order: Vec<u32> = match reader.read_indices() {
        Some(indices) => indices.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    if let Some(&bad) = order.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(format!(
            "index {bad} is out of range ({} vertices)",
            positions.len()
        ));
    }
    let n = order.len();
    let triangles: Vec<[u32; 3]> = match primitive.mode() {
        Mode::TriangleStrip => (2..n)
            .map(|i| {
                // Every other strip triangle is reversed to keep the winding consistent.
                if i % 2 == 0 {
                    [order[i - 2], order[i - 1], order[i]]
                } else {
                    [order[i - 1], order[i - 2], order[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..n).map(|i| [order[0], order[i - 1], order[i]]).collect(),
        _ => {
            if n % 3 != 0 {
                return Err(format!("{n} corners is not a whole number of triangles"));
            }
            order.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
    };
    Ok(Some(Mesh::from_faces(positions, triangles)))
}

/// Makes sure gltf's accessor reader will neither panic nor read past the data: gltf 1.4 only
/// `debug_assert`s element sizes and computes the byte range without overflow checks.
fn check_accessor(
    accessor: &gltf::Accessor<'_>,
    blob: &[u8],
    types: &[DataType],
    dimensions: Dimensions,
) -> Result<(), String> {
    if accessor.sparse().is_some() {
        return Err("sparse accessors are not supported".to_owned());
    }
    if !types.contains(&accessor.data_type()) || accessor.dimensions() != dimensions {
        return Err(format!(
            "unexpected type {:?} {:?}",
            accessor.data_type(),
            accessor.dimensions()
        ));
    }
    let view = accessor.view().ok_or("no buffer view")?;
    if !matches!(view.buffer().source(), gltf::buffer::Source::Bin) {
        return Err("external buffers are not supported".to_owned());
    }
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "byte stride {stride} is less than the element size {size}"
        ));
    }
    let count = accessor.count();
    let last = count.checked_sub(1).ok_or("the accessor has no elements")?;
    let needed = last
        .checked_mul(stride)
        .and_then(|b| b.checked_add(size))
        .and_then(|b| b.checked_add(accessor.offset()));
    if needed.is_none_or(|needed| needed > view.length()) {
        return Err(format!("{count} elements do not fit in their buffer view"));
    }
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|end| end > blob.len())
    {
        return Err("the buffer view runs past the BIN chunk".to_owned());
    }
    Ok(())
}

/// Reads a Wavefront OBJ text. Each `o`/`g` group becomes a part (split further where `usemtl`
/// changes between materials found in `mtllib`); faces stay polygons. Without an MTL the colour
/// is the default one.
pub fn read_obj(text: &str) -> Result<Model, Error> {
    read_obj_with(text, |_| Err(tobj::LoadError::OpenFileFailed))
}

/// [`read_obj`] with a loader for the MTL files named by `mtllib`; Kd and d give the colours.
pub(crate) fn read_obj_with(
    text: &str,
    load_mtl: impl Fn(&Path) -> tobj::MTLLoadResult,
) -> Result<Model, Error> {
    let broken = |message: String| Error::broken(Format::Obj, message);
    // Other tobj features add fields; the update keeps this compiling when one is enabled.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, load_mtl)
        .map_err(|e| broken(e.to_string()))?;
    // A missing or broken MTL only costs the colours.
    let materials = materials.unwrap_or_default();
    let mut parts = Vec::new();
    for model in models {
        let m = &model.mesh;
        let color = m
            .material_id
            .and_then(|id| materials.get(id))
            .and_then(|mat| {
                let [r, g, b] = mat.diffuse?.map(|c| c as f32);
                Some(Color {
                    r,
                    g,
                    b,
                    a: mat.dissolve.map_or(1.0, |d| d as f32),
                })
            })
            .unwrap_or_default();
        let positions: Vec<DVec3> = m
            .positions
            .chunks_exact(3)
            .map(|p| DVec3::new(p[0], p[1], p[2]))
            .collect();
        // tobj leaves `face_arities` empty when every face is a triangle.
        let arities: Cow<'_, [u32]> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3].into()
        } else {
            m.face_arities.as_slice().into()
        };
        let mut faces = Vec::with_capacity(arities.len());
        let mut rest = m.indices.as_slice();
        for &arity in arities.iter() {
            let Some((face, tail)) = rest.split_at_checked(arity as usize) else {
                return Err(broken(format!("faces of '{}' are cut short", model.name)));
            };
            if face.iter().any(|&i| i as usize >= positions.len()) {
                return Err(broken(format!(
                    "a face of '{}' refers to a missing vertex",
                    model.name
                )));
            }
            faces.push(face);
            rest = tail;
        }
        push_part(
            &mut parts,
            model.name,
            color,
            Mesh::from_faces(positions, faces),
        );
    }
    Ok(Model {
        parts,
        lines: Vec::new(),
    })
}

/// Reads an STL file, binary or ASCII, as one part named "stl".
pub fn read_stl(bytes: &[u8]) -> Result<Model, Error> {
    let broken = |message: String| Error::broken(Format::Stl, message);
    let mut data = Cow::Borrowed(bytes);
    // Many exporters start binary headers with "solid", which stl_io takes for ASCII; a size
    // that matches the triangle count exactly identifies binary STL.
    if bytes.starts_with(b"solid") && bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if count.checked_mul(50).and_then(|n| n.checked_add(84)) == Some(bytes.len()) {
            data.to_mut()[..5].copy_from_slice(b"SOLID");
        }
    }
    let stl = stl_io::read_stl(&mut Cursor::new(&data[..])).map_err(|e| {
        broken(match e.kind() {
            std::io::ErrorKind::UnexpectedEof => "the file ends early".to_owned(),
            _ => e.to_string(),
        })
    })?;
    let positions: Vec<DVec3> = stl
        .vertices
        .iter()
        .map(|v| DVec3::from(v.0.map(f64::from)))
        .collect();
    let mut faces = Vec::with_capacity(stl.faces.len());
    for face in &stl.faces {
        let mut triangle = [0u32; 3];
        for (slot, &v) in triangle.iter_mut().zip(&face.vertices) {
            *slot = u32::try_from(v)
                .ok()
                .filter(|&v| (v as usize) < positions.len())
                .ok_or_else(|| broken("a triangle refers to a missing vertex".to_owned()))?;
        }
        faces.push(triangle);
    }
    let mut parts = Vec::new();
    push_part(
        &mut parts,
        "stl".to_owned(),
        Color::default(),
        Mesh::from_faces(positions, faces),
    );
    Ok(Model {
        parts,
        lines: Vec::new(),
    })
}

fn push_part(parts: &mut Vec<Part>, name: String, color: Color, mesh: Mesh) {
    if !mesh.is_empty() {
        parts.push(Part {
            name,
            color,
            mesh,
            normals: Vec::new(),
        });
    }
}
