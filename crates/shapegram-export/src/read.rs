//! Readers for GLB, OBJ and STL. Input is untrusted: every problem is an `Err`, never a panic.
//!
//! Meshes come back with the vertices as the file stores them (GLB and STL: one per corner or
//! per flat-shaded face); weld with [`Mesh::welded`] to recover connectivity. Parts without faces
//! are dropped, as the writers drop them. A part comes back smooth (with `normals`) when every
//! vertex has one normal and some vertex is shared by faces that are not coplanar, which
//! flat-shaded data never does. Line primitives (GLB) and `l` elements (OBJ) come back as line
//! sets. Skins are not applied: skinned meshes come back as stored, in the rest pose, and
//! without skeletons.

use std::borrow::Cow;
use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;
use std::sync::Arc;

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use shapegram_geom::{Color, DAffine3, DQuat, DVec2, DVec3, Lines, Mesh, Model, Part, Texture};

use crate::glb::{CHUNK_BIN, CHUNK_JSON, GPU_INSTANCING, MAGIC, compress};
use crate::{Error, Format, mtl};

/// Reads a GLB file (binary glTF 2.0): triangle primitives of the default scene, in world
/// coordinates, one part per primitive named after its node, coloured by `baseColorFactor`,
/// with its material's name, its float `TEXCOORD_0` as uvs and, with them, its embedded colour
/// texture;
/// line primitives likewise as line sets. Points are skipped; strips and fans become triangles,
/// line strips and loops segments.
pub fn read_glb(bytes: &[u8]) -> Result<Model, Error> {
    let broken = |message: String| Error::broken(Format::Glb, message);
    let (json, bin) = split_glb(bytes).map_err(broken)?;
    let mut value: serde_json::Value =
        serde_json::from_slice(json).map_err(|e| broken(format!("invalid JSON chunk: {e}")))?;
    let decoded = decompress(&mut value, bin.unwrap_or_default()).map_err(broken)?;
    let root: gltf::json::Root =
        serde_json::from_value(value).map_err(|e| broken(format!("invalid JSON chunk: {e}")))?;
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
    let blob = decoded.as_deref().or(bin).unwrap_or_default();
    let mut model = Model::default();
    for (node, world) in scene_nodes(&document).map_err(broken)? {
        let Some(mesh) = node.mesh() else {
            continue;
        };
        let name = node
            .name()
            .or(mesh.name())
            .map_or_else(|| format!("node{}", node.index()), str::to_owned);
        let placements = instances(&document, &node, blob, world).map_err(broken)?;
        for primitive in mesh.primitives() {
            let context = |e: String| {
                broken(format!(
                    "mesh {} primitive {}: {e}",
                    mesh.index(),
                    primitive.index()
                ))
            };
            // glTF colour factors are linear light; our colours are sRGB.
            let factor = primitive
                .material()
                .pbr_metallic_roughness()
                .base_color_factor();
            let color = Color::from_linear(factor);
            let read = read_primitive(&primitive, blob).map_err(context)?;
            for world in &placements {
                match &read {
                    Read::Triangles(mesh, normals, uvs) => {
                        let part_mesh = mesh.transformed(world);
                        let mut normals = normals.clone();
                        transform_normals(&mut normals, world);
                        if !part_mesh.is_empty() {
                            let material = primitive.material();
                            model.parts.push(Part {
                                texture: color_map(&material, blob).filter(|_| !uvs.is_empty()),
                                uvs: uvs.clone(),
                                material: material.name().map(Arc::from),
                                ..Part::new(name.clone(), color, part_mesh, normals)
                            });
                        }
                    }
                    Read::Lines(points, segments) => {
                        let points = points.iter().map(|&p| world.transform_point3(p)).collect();
                        push_lines(
                            &mut model.lines,
                            name.clone(),
                            color,
                            points,
                            segments.clone(),
                        );
                    }
                    Read::Nothing => {}
                }
            }
        }
    }
    Ok(model)
}

/// Where a node draws its mesh: at its world transform `world`, or, with
/// `EXT_mesh_gpu_instancing`, at each instance's transform (its TRANSLATION, ROTATION and SCALE,
/// each optional) within it.
fn instances(
    document: &gltf::Document,
    node: &gltf::Node<'_>,
    blob: &[u8],
    world: DAffine3,
) -> Result<Vec<DAffine3>, String> {
    let extension = document.as_json().nodes[node.index()]
        .extensions
        .as_ref()
        .and_then(|e| e.others.get(GPU_INSTANCING));
    let Some(extension) = extension else {
        return Ok(vec![world]);
    };
    let context = |e: String| format!("node {} {GPU_INSTANCING}: {e}", node.index());
    let attribute = |name: &str, dimensions: Dimensions| -> Result<Option<Vec<Vec<f64>>>, String> {
        let Some(index) = extension.pointer(&format!("/attributes/{name}")) else {
            return Ok(None);
        };
        let accessor = index
            .as_u64()
            .and_then(|i| document.accessors().nth(i as usize))
            .ok_or_else(|| context(format!("{name} names no accessor")))?;
        check_accessor(&accessor, blob, &[DataType::F32], dimensions)
            .map_err(|e| context(format!("{name}: {e}")))?;
        let values = match dimensions {
            Dimensions::Vec4 => gltf::accessor::Iter::<[f32; 4]>::new(accessor, |_| Some(blob))
                .map(|values| values.map(|v| v.map(f64::from).to_vec()).collect()),
            _ => gltf::accessor::Iter::<[f32; 3]>::new(accessor, |_| Some(blob))
                .map(|values| values.map(|v| v.map(f64::from).to_vec()).collect()),
        };
        values
            .map(Some)
            .ok_or_else(|| context(format!("{name} is unreadable")))
    };
    let translations = attribute("TRANSLATION", Dimensions::Vec3)?;
    let rotations = attribute("ROTATION", Dimensions::Vec4)?;
    let scales = attribute("SCALE", Dimensions::Vec3)?;
    let counts: Vec<usize> = [&translations, &rotations, &scales]
        .into_iter()
        .flatten()
        .map(Vec::len)
        .collect();
    let Some(&count) = counts.first() else {
        return Err(context("no attributes".to_owned()));
    };
    if counts.iter().any(|&c| c != count) {
        return Err(context(format!(
            "attributes of different counts {counts:?}"
        )));
    }
    let vector = |v: &Vec<f64>| DVec3::new(v[0], v[1], v[2]);
    Ok((0..count)
        .map(|i| {
            let translation = translations.as_ref().map_or(DVec3::ZERO, |t| vector(&t[i]));
            let rotation = rotations.as_ref().map_or(DQuat::IDENTITY, |r| {
                DQuat::from_xyzw(r[i][0], r[i][1], r[i][2], r[i][3]).normalize()
            });
            let scale = scales.as_ref().map_or(DVec3::ONE, |s| vector(&s[i]));
            world * DAffine3::from_scale_rotation_translation(scale, rotation, translation)
        })
        .collect())
}

/// The extension whose integer attributes [`vectors`] reads.
const QUANTIZATION: &str = "KHR_mesh_quantization";

/// Decodes EXT_meshopt_compression views, when the document has them, into new BIN data (see
/// [`compress::decode_views`]; `None`: nothing to decode), and drops the extensions this
/// reader handles from the required ones.
fn decompress(root: &mut serde_json::Value, bin: &[u8]) -> Result<Option<Vec<u8>>, String> {
    let uses = |list: &serde_json::Value| {
        list.as_array()
            .is_some_and(|l| l.iter().any(|e| e == compress::EXTENSION))
    };
    let decoded = if root.get("extensionsUsed").is_some_and(uses) {
        Some(compress::decode_views(root, bin)?)
    } else {
        None
    };
    // gltf refuses required extensions it does not know; these two this reader handles.
    if let Some(required) = root
        .get_mut("extensionsRequired")
        .and_then(serde_json::Value::as_array_mut)
    {
        required.retain(|e| e != compress::EXTENSION && e != QUANTIZATION);
    }
    Ok(decoded)
}

/// Normals under a node's transform: by the inverse transpose of its linear part, renormalised.
fn transform_normals(normals: &mut [DVec3], world: &DAffine3) {
    if *world == DAffine3::IDENTITY {
        return;
    }
    let map = world.matrix3.inverse().transpose();
    for n in normals {
        *n = (map * *n).normalize_or_zero();
    }
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

/// The colour map of a material, when it is an image embedded in the BIN chunk, named after
/// the image (or its index); its bytes are kept when they are PNG or JPEG.
fn color_map(material: &gltf::Material<'_>, blob: &[u8]) -> Option<Arc<Texture>> {
    let info = material.pbr_metallic_roughness().base_color_texture()?;
    let image = info.texture().source();
    let gltf::image::Source::View { view, .. } = image.source() else {
        return None;
    };
    let bytes = view
        .offset()
        .checked_add(view.length())
        .and_then(|end| blob.get(view.offset()..end));
    let texture = Texture {
        path: Arc::from(
            image
                .name()
                .map_or_else(|| format!("image{}", image.index()), str::to_owned),
        ),
        image: bytes.map(Arc::from),
    };
    let readable = texture.mime_type().is_some();
    Some(Arc::new(Texture {
        image: texture.image.filter(|_| readable),
        ..texture
    }))
}

/// What a primitive holds, in node space.
enum Read {
    /// Triangles, with the normals of a smooth primitive (empty for flat data) and the uvs of
    /// TEXCOORD_0 (v up, as CGA has them; empty without).
    Triangles(Mesh, Vec<DVec3>, Vec<DVec2>),
    /// Points and segments.
    Lines(Vec<DVec3>, Vec<[u32; 2]>),
    /// Points only, which a model does not hold.
    Nothing,
}

/// The triangles or segments of a primitive.
fn read_primitive(primitive: &gltf::Primitive<'_>, blob: &[u8]) -> Result<Read, String> {
    if primitive.mode() == Mode::Points {
        return Ok(Read::Nothing);
    }
    let position = primitive
        .get(&gltf::Semantic::Positions)
        .ok_or("no POSITION attribute")?;
    check_accessor(&position, blob, &VECTOR_TYPES, Dimensions::Vec3)
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
    let normal = primitive.get(&gltf::Semantic::Normals);
    if let Some(normal) = &normal {
        check_accessor(normal, blob, &VECTOR_TYPES, Dimensions::Vec3)
            .map_err(|e| format!("NORMAL: {e}"))?;
        if normal.count() != position.count() {
            return Err(format!(
                "NORMAL has {} elements for {} vertices",
                normal.count(),
                position.count()
            ));
        }
    }
    let reader = primitive.reader(|buffer| match buffer.source() {
        gltf::buffer::Source::Bin => Some(blob),
        gltf::buffer::Source::Uri(_) => None,
    });
    let positions = vectors(&position, blob);
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
        Mode::Lines | Mode::LineStrip | Mode::LineLoop => {
            return line_segments(primitive.mode(), &order)
                .map(|segments| Read::Lines(positions, segments));
        }
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
            if !n.is_multiple_of(3) {
                return Err(format!("{n} corners is not a whole number of triangles"));
            }
            order.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
    };
    let mesh = Mesh::from_faces(positions, triangles);
    let normals = match &normal {
        Some(normal) => smooth_normals(&mesh, vectors(normal, blob)),
        None => Vec::new(),
    };
    // Only float uvs are read; a set that does not fit is left out, as it changes no geometry.
    let uvs = primitive
        .get(&gltf::Semantic::TexCoords(0))
        .filter(|uvs| {
            uvs.count() == mesh.vertex_count()
                && check_accessor(uvs, blob, &UV_TYPES, Dimensions::Vec2).is_ok()
        })
        .and_then(|_| reader.read_tex_coords(0))
        .map(|uvs| {
            uvs.into_f32()
                .map(|[u, v]| DVec2::new(f64::from(u), 1.0 - f64::from(v)))
                .collect()
        })
        .unwrap_or_default();
    Ok(Read::Triangles(mesh, normals, uvs))
}

/// The segments of a line, line strip or line loop primitive.
fn line_segments(mode: Mode, order: &[u32]) -> Result<Vec<[u32; 2]>, String> {
    let n = order.len();
    Ok(match mode {
        Mode::LineStrip => order.windows(2).map(|w| [w[0], w[1]]).collect(),
        Mode::LineLoop if n >= 2 => order
            .windows(2)
            .map(|w| [w[0], w[1]])
            .chain(std::iter::once([order[n - 1], order[0]]))
            .collect(),
        Mode::LineLoop => Vec::new(),
        _ => {
            if !n.is_multiple_of(2) {
                return Err(format!("{n} ends is not a whole number of segments"));
            }
            order.chunks_exact(2).map(|s| [s[0], s[1]]).collect()
        }
    })
}

/// `normals` (one per vertex) as a part's smooth normals: kept, made unit, when they are all
/// usable and some vertex is shared by faces that are not coplanar (more than about 0.06°
/// apart); empty otherwise, since flat-shaded data repeats each face's normal at corners of its
/// own.
fn smooth_normals(mesh: &Mesh, normals: Vec<DVec3>) -> Vec<DVec3> {
    const SAME_PLANE_COS: f64 = 1.0 - 5e-7;
    if normals.len() != mesh.vertex_count() {
        return Vec::new();
    }
    let mut first = vec![DVec3::ZERO; mesh.vertex_count()];
    let mut shared = false;
    'faces: for i in 0..mesh.face_count() {
        let n = mesh.face_normal(i);
        if n == DVec3::ZERO {
            continue;
        }
        for &v in mesh.face(i) {
            let seen = &mut first[v as usize];
            if *seen == DVec3::ZERO {
                *seen = n;
            } else if seen.dot(n) < SAME_PLANE_COS {
                shared = true;
                break 'faces;
            }
        }
    }
    let units: Option<Vec<DVec3>> = normals
        .iter()
        .map(|n| n.try_normalize().filter(|u| u.is_finite()))
        .collect();
    match units {
        Some(units) if shared => units,
        _ => Vec::new(),
    }
}

/// The component types positions and normals may have (KHR_mesh_quantization allows integers).
const VECTOR_TYPES: [DataType; 5] = [
    DataType::F32,
    DataType::I16,
    DataType::U16,
    DataType::I8,
    DataType::U8,
];

/// The component types uvs may have (integers normalised, as glTF and KHR_mesh_quantization
/// allow).
const UV_TYPES: [DataType; 3] = [DataType::F32, DataType::U16, DataType::U8];

/// A VEC3 accessor's elements as f64 vectors, integers converted as glTF says (normalised ones
/// to `-1..=1` or `0..=1`). The accessor has passed [`check_accessor`].
fn vectors(accessor: &gltf::Accessor<'_>, blob: &[u8]) -> Vec<DVec3> {
    let view = accessor.view().expect("checked accessors have a view");
    let size = accessor.size() / 3;
    let stride = view.stride().unwrap_or(accessor.size());
    let start = view.offset() + accessor.offset();
    let normalized = accessor.normalized();
    let kind = accessor.data_type();
    let component = |b: &[u8]| -> f64 {
        let (value, scale) = match kind {
            DataType::F32 => (f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])), 1.0),
            DataType::I16 => (f64::from(i16::from_le_bytes([b[0], b[1]])), 32767.0),
            DataType::U16 => (f64::from(u16::from_le_bytes([b[0], b[1]])), 65535.0),
            DataType::I8 => (f64::from(b[0] as i8), 127.0),
            DataType::U8 | DataType::U32 => (f64::from(b[0]), 255.0),
        };
        if normalized && kind != DataType::F32 {
            (value / scale).max(-1.0)
        } else {
            value
        }
    };
    (0..accessor.count())
        .map(|i| {
            let at = start + i * stride;
            DVec3::from_array(std::array::from_fn(|k| {
                component(&blob[at + k * size..at + (k + 1) * size])
            }))
        })
        .collect()
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
/// changes between materials found in `mtllib`); faces stay polygons. The `l` elements of a
/// group become a line set of the same name (a polyline `l a b c` one segment per pair). Without
/// an MTL the colour is the default one. A part is smooth when each vertex has one normal and
/// the group holds no lines. A group whose every face corner names a `vt` keeps them as its
/// uvs, a vertex with several becoming one vertex per uv.
pub fn read_obj(text: &str) -> Result<Model, Error> {
    read_obj_with(text, |_| Err(tobj::LoadError::OpenFileFailed), &|path| {
        Arc::new(Texture {
            path: Arc::from(path),
            image: None,
        })
    })
}

/// [`read_obj`] with a loader for the MTL files named by `mtllib` and one for the texture
/// files they name: a part wears its material's name, colour (`Kd`, `d`), colour map and the
/// rest (see [`crate::mtl`]).
pub(crate) fn read_obj_with(
    text: &str,
    load_mtl: impl Fn(&Path) -> tobj::MTLLoadResult,
    load_texture: &dyn Fn(&str) -> Arc<Texture>,
) -> Result<Model, Error> {
    let broken = |message: String| Error::broken(Format::Obj, message);
    // Other tobj features add fields; the update keeps this compiling when one is enabled.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: false,
        ..Default::default()
    };
    check_obj_indices(text).map_err(broken)?;
    // tobj reads `l a b c` as a face; as pairs it reads them as segments.
    let text = split_polylines(text);
    let (models, materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, load_mtl)
        .map_err(|e| broken(e.to_string()))?;
    // A missing or broken MTL only costs the materials.
    let materials = materials.unwrap_or_default();
    let looks: Vec<mtl::Look> = materials
        .iter()
        .map(|m| mtl::look(m, load_texture))
        .collect();
    let mut model_out = Model::default();
    for model in models {
        let m = &model.mesh;
        let look = m.material_id.and_then(|id| looks.get(id));
        let color = look.map_or_else(Color::default, |l| l.color);
        let (positions, indices, uvs) = corners(m).map_err(broken)?;
        // tobj leaves `face_arities` empty when every face is a triangle.
        let arities: Cow<'_, [u32]> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3].into()
        } else {
            m.face_arities.as_slice().into()
        };
        let mut faces = Vec::with_capacity(arities.len());
        let mut segments = Vec::new();
        let mut rest = indices.as_slice();
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
            match face {
                &[a, b] => segments.push([a, b]),
                _ => faces.push(face),
            }
            rest = tail;
        }
        let normals = if segments.is_empty() {
            obj_vertex_normals(m, &indices, positions.len())
        } else {
            None
        };
        let lines = (!segments.is_empty()).then(|| compact_lines(&positions, segments));
        let mesh = Mesh::from_faces(positions, faces);
        let normals = normals.map_or_else(Vec::new, |n| smooth_normals(&mesh, n));
        if !mesh.is_empty() {
            model_out.parts.push(Part {
                texture: look
                    .and_then(|l| l.texture.clone())
                    .filter(|_| !uvs.is_empty()),
                uvs,
                material: look.map(|l| l.name.clone()),
                surface: look.and_then(|l| l.surface.clone()),
                ..Part::new(model.name.clone(), color, mesh, normals)
            });
        }
        if let Some((points, segments)) = lines {
            push_lines(&mut model_out.lines, model.name, color, points, segments);
        }
    }
    Ok(model_out)
}

/// A group's vertices and its corners' indices into them, with one uv per vertex when every
/// corner names a `vt`: a position used with several uvs becomes one vertex per uv, in the
/// order the corners first use them. Without `vt` (or with some corners lacking one) the
/// positions as the file has them, and no uvs.
#[allow(clippy::type_complexity)]
fn corners(m: &tobj::Mesh) -> Result<(Vec<DVec3>, Vec<u32>, Vec<DVec2>), String> {
    let positions: Vec<DVec3> = m
        .positions
        .chunks_exact(3)
        .map(|p| DVec3::new(p[0], p[1], p[2]))
        .collect();
    if m.texcoord_indices.is_empty() || m.texcoord_indices.len() != m.indices.len() {
        return Ok((positions, m.indices.clone(), Vec::new()));
    }
    let mut vertex_of: HashMap<(u32, u32), u32> = HashMap::new();
    let (mut points, mut uvs) = (Vec::new(), Vec::new());
    let mut indices = Vec::with_capacity(m.indices.len());
    for (&p, &t) in m.indices.iter().zip(&m.texcoord_indices) {
        let i = match vertex_of.get(&(p, t)) {
            Some(&i) => i,
            None => {
                let point = positions
                    .get(p as usize)
                    .ok_or("a face refers to a missing vertex")?;
                let uv = m
                    .texcoords
                    .get(2 * t as usize..2 * t as usize + 2)
                    .ok_or("a face refers to a missing texture coordinate")?;
                points.push(*point);
                uvs.push(DVec2::new(uv[0], uv[1]));
                let i = (points.len() - 1) as u32;
                vertex_of.insert((p, t), i);
                i
            }
        };
        indices.push(i);
    }
    Ok((points, indices, uvs))
}

/// Checks that every index of a face, line or point element names an element of the file:
/// positive ones at most the file's count, negative (relative) ones at most the count declared
/// before the line. tobj multiplies indices unchecked, so an index past the end overflows.
fn check_obj_indices(text: &str) -> Result<(), String> {
    const KINDS: [(&str, &str); 3] = [
        ("v", "vertex"),
        ("vt", "texture coordinate"),
        ("vn", "normal"),
    ];
    let mut total = [0i64; 3];
    for line in text.lines() {
        if let Some(k) = line
            .split_whitespace()
            .next()
            .and_then(|w| KINDS.iter().position(|(tag, _)| *tag == w))
        {
            total[k] += 1;
        }
    }
    let mut before = [0i64; 3];
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let Some(tag) = words.next() else {
            continue;
        };
        if let Some(k) = KINDS.iter().position(|(t, _)| *t == tag) {
            before[k] += 1;
            continue;
        }
        if !matches!(tag, "f" | "l" | "p") {
            continue;
        }
        for word in words {
            for (k, part) in word.split('/').enumerate().take(3) {
                // Empty parts are absent indices; unreadable ones are tobj's to report.
                let Ok(index) = part.parse::<i64>() else {
                    continue;
                };
                let (limit, scope) = if index < 0 {
                    (before[k], "before it")
                } else {
                    (total[k], "in the file")
                };
                if index == 0 || index.unsigned_abs() > limit as u64 {
                    let (_, kind) = KINDS[k];
                    return Err(format!(
                        "line {}: {kind} index {index} is out of range ({limit} declared {scope})",
                        n + 1
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The text with every polyline `l a b c …` written as segments `l a b`, `l b c`, ….
fn split_polylines(text: &str) -> Cow<'_, str> {
    let is_polyline = |line: &str| {
        let mut words = line.split_whitespace();
        words.next() == Some("l") && words.count() > 2
    };
    if !text.lines().any(is_polyline) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        if is_polyline(line) {
            let ends: Vec<&str> = line.split_whitespace().skip(1).collect();
            for pair in ends.windows(2) {
                out.push_str(&format!("l {} {}\n", pair[0], pair[1]));
            }
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    Cow::Owned(out)
}

/// One normal per vertex (of `indices`, the corners of `mesh` renumbered by [`corners`]) when
/// every corner names one and each vertex is always given the same.
fn obj_vertex_normals(mesh: &tobj::Mesh, indices: &[u32], vertices: usize) -> Option<Vec<DVec3>> {
    if mesh.normal_indices.len() != indices.len() {
        return None;
    }
    let mut chosen = vec![u32::MAX; vertices];
    for (&v, &n) in indices.iter().zip(&mesh.normal_indices) {
        let slot = chosen.get_mut(v as usize)?;
        if *slot != u32::MAX && *slot != n {
            return None;
        }
        *slot = n;
    }
    chosen
        .iter()
        .map(|&n| {
            let n = n as usize;
            let xyz = mesh.normals.get(3 * n..3 * n + 3)?;
            Some(DVec3::new(xyz[0], xyz[1], xyz[2]))
        })
        .collect()
}

/// The points the segments use, in their order, and the segments renumbered.
fn compact_lines(positions: &[DVec3], segments: Vec<[u32; 2]>) -> (Vec<DVec3>, Vec<[u32; 2]>) {
    let mut remap = vec![u32::MAX; positions.len()];
    let mut points = Vec::new();
    let segments = segments
        .into_iter()
        .map(|s| {
            s.map(|v| {
                let slot = &mut remap[v as usize];
                if *slot == u32::MAX {
                    *slot = points.len() as u32;
                    points.push(positions[v as usize]);
                }
                *slot
            })
        })
        .collect();
    (points, segments)
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
        Vec::new(),
    );
    Ok(Model {
        skeletons: Vec::new(),
        parts,
        lines: Vec::new(),
    })
}

fn push_part(parts: &mut Vec<Part>, name: String, color: Color, mesh: Mesh, normals: Vec<DVec3>) {
    if !mesh.is_empty() {
        parts.push(Part::new(name, color, mesh, normals));
    }
}

fn push_lines(
    lines: &mut Vec<Lines>,
    name: String,
    color: Color,
    points: Vec<DVec3>,
    segments: Vec<[u32; 2]>,
) {
    if !segments.is_empty() {
        lines.push(Lines {
            name,
            color,
            points,
            segments,
        });
    }
}
