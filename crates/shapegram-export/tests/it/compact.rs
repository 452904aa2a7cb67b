//! Compact GLB: shared vertices, merged coplanar rectangles, quantised and compressed encodings,
//! and what compaction must leave apart.

use crate::common;

use common::*;
use serde_json::Value;
use shapegram_export::{ExportOptions, FlatNormals, GlbEncoding, read_glb, write_glb};
use shapegram_geom::primitives::{self, cuboid};
use shapegram_geom::{Color, DVec2, DVec3, Mesh, Metadata, Model, Part, Texture};

const ENCODINGS: [GlbEncoding; 3] = [
    GlbEncoding::Float,
    GlbEncoding::Quantized,
    GlbEncoding::Compressed,
];

fn options(encoding: GlbEncoding) -> ExportOptions {
    ExportOptions {
        encoding,
        ..ExportOptions::default()
    }
}

fn flat(name: &str, color: Color, mesh: Mesh) -> Part {
    Part {
        name: name.to_owned(),
        color,
        mesh,
        ..Part::default()
    }
}

/// A unit square facing +z with its lower left corner at (x, y).
fn tile(x: f64, y: f64) -> Mesh {
    Mesh::from_polygon(&[
        DVec3::new(x, y, 0.0),
        DVec3::new(x + 1.0, y, 0.0),
        DVec3::new(x + 1.0, y + 1.0, 0.0),
        DVec3::new(x, y + 1.0, 0.0),
    ])
}

/// A wall of 4 × 3 tiles, one part each, coloured by `color(column, row)`.
fn wall(color: impl Fn(usize, usize) -> Color) -> Model {
    let parts = (0..12)
        .map(|i| {
            let (column, row) = (i % 4, i / 4);
            flat("Tile", color(column, row), tile(column as f64, row as f64))
        })
        .collect();
    Model {
        parts,
        ..Model::default()
    }
}

/// The accessor of a primitive's attribute (or of its indices, for "indices").
fn accessor<'a>(json: &'a Value, primitive: &Value, key: &str) -> &'a Value {
    let index = match key {
        "indices" => &primitive["indices"],
        _ => &primitive["attributes"][key],
    };
    &json["accessors"][index.as_u64().unwrap() as usize]
}

/// (vertices, indices) of each primitive of each mesh.
fn counts(glb: &[u8]) -> Vec<(u64, u64)> {
    let (json, _) = split_glb(glb);
    json["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|mesh| mesh["primitives"].as_array().unwrap())
        .map(|primitive| {
            let count = |key| accessor(&json, primitive, key)["count"].as_u64().unwrap();
            (count("POSITION"), count("indices"))
        })
        .collect()
}

/// The total area of a model's faces.
fn area(model: &Model) -> f64 {
    model
        .parts
        .iter()
        .map(|p| {
            (0..p.mesh.face_count())
                .map(|f| p.mesh.face_area(f))
                .sum::<f64>()
        })
        .sum()
}

#[test]
fn a_flat_box_shares_its_corners_and_leaves_normals_to_the_reader() {
    let model = Model {
        parts: vec![flat("box", RED, cuboid(DVec3::ONE))],
        ..Model::default()
    };
    // Without normals the faces share the box's 8 corners.
    for encoding in ENCODINGS {
        let glb = write_glb(&model, &options(encoding));
        assert_eq!(counts(&glb), [(8, 36)]);
        let (json, _) = split_glb(&glb);
        let attributes = &json["meshes"][0]["primitives"][0]["attributes"];
        assert_eq!(attributes.as_object().unwrap().len(), 1, "{attributes}");
        assert!(attributes.get("NORMAL").is_none());
    }
    // With flat normals, four corners per face with the face's normal: 24 vertices, not 36.
    for encoding in ENCODINGS {
        let options = ExportOptions {
            flat_normals: FlatNormals::Written,
            ..options(encoding)
        };
        let glb = write_glb(&model, &options);
        assert_eq!(counts(&glb), [(24, 36)]);
        let (json, _) = split_glb(&glb);
        assert!(json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].is_u64());
    }
}

#[test]
fn a_wall_of_one_colour_becomes_one_rectangle() {
    let model = wall(|_, _| RED);
    let glb = write_glb(&model, &ExportOptions::default());
    assert_eq!(counts(&glb), [(4, 6)]);
    let back = read_glb(&glb).unwrap();
    assert_close(area(&back), 12.0, 1e-12, "area");
    let bounds = back.parts[0].mesh.bounds().unwrap();
    assert_eq!(
        (bounds.min, bounds.max),
        (DVec3::ZERO, DVec3::new(4.0, 3.0, 0.0))
    );
}

#[test]
fn merging_stops_at_materials_and_at_parts_with_metadata() {
    // A blue tile in the second row: the red ones around it cannot all become one.
    let model = wall(|column, row| if (column, row) == (1, 1) { BLUE } else { RED });
    let glb = write_glb(&model, &ExportOptions::default());
    let primitives = counts(&glb);
    assert_eq!(primitives[1].1, 6, "the blue tile on its own");
    let red_indices = primitives[0].1;
    assert!(red_indices > 6 && red_indices < 11 * 6, "{red_indices}");
    // Both name one pool of vertices: the blue tile's corners are corners of the red.
    let (json, _) = split_glb(&glb);
    let position = |k: usize| json["meshes"][0]["primitives"][k]["attributes"]["POSITION"].clone();
    assert_eq!(position(0), position(1));
    assert!(primitives[0].0 < 11 * 4, "{}", primitives[0].0);
    let back = read_glb(&glb).unwrap();
    assert_close(area(&back), 12.0, 1e-12, "area");

    // A tile with metadata keeps its own node, and its own four corners.
    let mut model = wall(|_, _| RED);
    model.parts[5].metadata = Some(std::sync::Arc::new(Metadata {
        tags: vec!["door".to_owned()],
        ..Metadata::default()
    }));
    let glb = write_glb(&model, &ExportOptions::default());
    let primitives = counts(&glb);
    assert_eq!(primitives.len(), 2);
    assert!(primitives.contains(&(4, 6)));
    assert_close(area(&read_glb(&glb).unwrap()), 12.0, 1e-12, "area");
}

#[test]
fn every_encoding_reads_back_as_the_same_solids() {
    let model = closed_model();
    let float = read_glb(&write_glb(&model, &ExportOptions::default())).unwrap();
    let float_volume: f64 = float.parts.iter().map(|p| p.mesh.signed_volume()).sum();
    let triangles = |m: &Model| m.parts.iter().map(|p| p.mesh.face_count()).sum::<usize>();
    let bounds = expected(&model.parts.iter().map(|p| &p.mesh).collect::<Vec<_>>()).bounds_f32;
    for encoding in [GlbEncoding::Quantized, GlbEncoding::Compressed] {
        let glb = write_glb(&model, &options(encoding));
        let back = read_glb(&glb).unwrap();
        assert_eq!(triangles(&back), triangles(&float), "{encoding:?}");
        let volume: f64 = back.parts.iter().map(|p| p.mesh.signed_volume()).sum();
        assert_close(volume, float_volume, 1e-3, "volume");
        // Positions lie on a grid of 32767 steps each side of the centre: within half a step.
        let step = (bounds.max - bounds.min).max_element() / 2.0 / 32767.0;
        for part in &back.parts {
            let read = part.mesh.bounds().unwrap();
            assert!(read.min.cmpge(bounds.min - step).all(), "{encoding:?}");
            assert!(read.max.cmple(bounds.max + step).all(), "{encoding:?}");
        }
        let (json, _) = split_glb(&glb);
        let required = json["extensionsRequired"].as_array().unwrap();
        assert!(required.contains(&Value::from("KHR_mesh_quantization")));
        assert_eq!(json["extensionsUsed"].as_array().unwrap(), required);
    }
}

#[test]
fn compressed_views_follow_the_fallback_rules() {
    let glb = write_glb(&closed_model(), &options(GlbEncoding::Compressed));
    let (json, bin) = split_glb(&glb);
    let required = json["extensionsRequired"].as_array().unwrap();
    assert!(required.contains(&Value::from("EXT_meshopt_compression")));
    // Buffer 0 is the BIN chunk with the compressed data; buffer 1 the fallback without data.
    let buffers = json["buffers"].as_array().unwrap();
    assert_eq!(buffers.len(), 2);
    assert_eq!(
        buffers[0]["byteLength"].as_u64().unwrap() as usize,
        bin.len()
    );
    assert_eq!(
        buffers[1]["extensions"]["EXT_meshopt_compression"]["fallback"],
        true
    );
    assert!(buffers[1].get("uri").is_none());
    let mut compressed = 0;
    for view in json["bufferViews"].as_array().unwrap() {
        let Some(extension) = view["extensions"].get("EXT_meshopt_compression") else {
            continue;
        };
        compressed += 1;
        assert_eq!(view["buffer"], 1);
        assert_eq!(extension["buffer"], 0);
        let end =
            extension["byteOffset"].as_u64().unwrap() + extension["byteLength"].as_u64().unwrap();
        assert!(end as usize <= bin.len());
        let stride = extension["byteStride"].as_u64().unwrap();
        let count = extension["count"].as_u64().unwrap();
        assert_eq!(view["byteLength"].as_u64().unwrap(), stride * count);
        match extension["mode"].as_str().unwrap() {
            "ATTRIBUTES" => {
                assert_eq!(stride % 4, 0);
                assert_eq!(view["byteStride"].as_u64().unwrap(), stride);
            }
            "TRIANGLES" => assert_eq!(count % 3, 0),
            mode => panic!("unexpected mode {mode}"),
        }
    }
    // One primitive per colour, without normals (flat parts leave them to the reader), all
    // naming one POSITION view (their vertex pool), and each its own indices.
    assert_eq!(compressed, 1 + 4);
    // Float data without normals is already small for this model of a few boxes.
    let (_, plain) = split_glb(&write_glb(&closed_model(), &ExportOptions::default()));
    assert!(
        bin.len() * 2 < plain.len(),
        "{} against {}",
        bin.len(),
        plain.len()
    );
}

#[test]
fn broken_compressed_data_is_an_error() {
    let glb = write_glb(&closed_model(), &options(GlbEncoding::Compressed));
    let (mut json, bin) = split_glb(&glb);
    let extension = "/bufferViews/0/extensions/EXT_meshopt_compression";
    json.pointer_mut(extension).unwrap()["byteLength"] = Value::from(3);
    let error = read_glb(&frame_glb(&json, &bin)).unwrap_err().to_string();
    assert!(error.contains("bufferView 0"), "{error}");
    json.pointer_mut(extension).unwrap()["byteOffset"] = Value::from(u32::MAX);
    let error = read_glb(&frame_glb(&json, &bin)).unwrap_err().to_string();
    assert!(error.contains("runs past the BIN chunk"), "{error}");
}

#[test]
fn every_encoding_gives_the_same_bytes_every_time_and_on_any_thread() {
    let model = sample_model();
    for encoding in ENCODINGS {
        let once = write_glb(&model, &options(encoding));
        assert_eq!(once, write_glb(&model, &options(encoding)));
        let model = model.clone();
        let elsewhere = std::thread::spawn(move || write_glb(&model, &options(encoding)))
            .join()
            .unwrap();
        assert_eq!(once, elsewhere);
    }
}

/// A triangle's corners.
type Triangle = [[f32; 3]; 3];

/// Every triangle of a float GLB's primitives as three positions, each turned to start at its
/// least corner (keeping its winding), sorted; and the NORMAL of its first corner where the
/// primitive has normals.
fn triangles(glb: &[u8]) -> Vec<(Triangle, Option<[f32; 3]>)> {
    let gltf = gltf::Gltf::from_slice(glb).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let mut found = Vec::new();
    for primitive in gltf
        .meshes()
        .flat_map(|m| m.primitives().collect::<Vec<_>>())
    {
        let reader = primitive.reader(|_| Some(blob));
        let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(Iterator::collect);
        let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
        for t in indices.chunks_exact(3) {
            let first = (0..3)
                .min_by(|&a, &b| {
                    let (p, q) = (positions[t[a] as usize], positions[t[b] as usize]);
                    p.partial_cmp(&q).unwrap()
                })
                .unwrap();
            let corners = [0, 1, 2].map(|k| positions[t[(first + k) % 3] as usize]);
            let normal = normals.as_ref().map(|n| n[t[0] as usize]);
            found.push((corners, normal));
        }
    }
    found.sort_by(|a, b| a.partial_cmp(b).unwrap());
    found
}

/// The direction of a triangle's corners taken counter-clockwise, as a reader that computes
/// flat normals finds it.
fn winding_normal([a, b, c]: [[f32; 3]; 3]) -> DVec3 {
    let [a, b, c] = [a, b, c].map(|p| DVec3::from(p.map(f64::from)));
    (b - a).cross(c - a)
}

#[test]
fn without_normals_the_same_triangles_face_the_same_way() {
    let model = sample_model();
    let written = ExportOptions {
        flat_normals: FlatNormals::Written,
        ..ExportOptions::default()
    };
    let with = triangles(&write_glb(&model, &written));
    let without = triangles(&write_glb(&model, &ExportOptions::default()));
    // The smooth-free sample: no primitive of the default file has normals.
    assert!(without.iter().all(|(_, n)| n.is_none()));
    let corners = |t: &[(Triangle, Option<[f32; 3]>)]| -> Vec<Triangle> {
        t.iter().map(|(c, _)| *c).collect()
    };
    assert_eq!(corners(&without), corners(&with));
    // The normal a reader computes from the winding is the face's normal that was written.
    for (triangle, normal) in &with {
        let normal = DVec3::from(normal.unwrap().map(f64::from));
        let computed = winding_normal(*triangle).normalize();
        assert!(
            computed.dot(normal) > 0.999,
            "{triangle:?}: {normal} against {computed}"
        );
    }
    // Fewer vertices, fewer bytes.
    let vertices = |glb: &[u8]| {
        let (json, _) = split_glb(glb);
        let meshes = json["meshes"].as_array().unwrap();
        let mut positions: Vec<u64> = meshes
            .iter()
            .flat_map(|m| m["primitives"].as_array().unwrap())
            .map(|p| p["attributes"]["POSITION"].as_u64().unwrap())
            .collect();
        positions.dedup();
        let count = |&a: &u64| json["accessors"][a as usize]["count"].as_u64().unwrap();
        positions.iter().map(count).sum::<u64>()
    };
    let (a, b) = (
        write_glb(&model, &written),
        write_glb(&model, &ExportOptions::default()),
    );
    assert!(
        vertices(&b) * 2 < vertices(&a),
        "{} against {}",
        vertices(&b),
        vertices(&a)
    );
    assert!(
        b.len() * 2 < a.len(),
        "{} against {} bytes",
        b.len(),
        a.len()
    );
    let back = read_glb(&b).unwrap();
    assert_close(area(&back), area(&read_glb(&a).unwrap()), 1e-9, "area");
    assert!(back.parts.iter().all(|p| p.normals.is_empty()));
}

#[test]
fn smooth_parts_keep_their_normals_in_a_mesh_of_their_own() {
    let ball = primitives::sphere(DVec3::ONE, 12, 6);
    let model = Model {
        parts: vec![
            flat("box", RED, cuboid(DVec3::ONE)),
            Part {
                name: "ball".to_owned(),
                color: RED,
                normals: ball.vertex_normals(),
                mesh: ball,
                ..Part::default()
            },
        ],
        ..Model::default()
    };
    let glb = write_glb(&model, &ExportOptions::default());
    let (json, _) = split_glb(&glb);
    // One material, flat and smooth apart: meshes of their own, so that a reader that makes
    // one object of a mesh (Blender) does not mix corners with and without normals.
    let meshes = json["meshes"].as_array().unwrap();
    let names: Vec<&str> = meshes.iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["model", "model-smooth"]);
    let primitive = |m: usize| meshes[m]["primitives"][0].clone();
    assert_eq!(meshes[0]["primitives"].as_array().unwrap().len(), 1);
    assert_eq!(primitive(0)["material"], primitive(1)["material"]);
    assert!(primitive(0)["attributes"].get("NORMAL").is_none());
    assert_eq!(accessor(&json, &primitive(0), "POSITION")["count"], 8);
    let normals = accessor(&json, &primitive(1), "NORMAL");
    assert_eq!(
        normals["count"],
        accessor(&json, &primitive(1), "POSITION")["count"]
    );
    let back = read_glb(&glb).unwrap();
    assert_eq!(
        back.parts.iter().filter(|p| !p.normals.is_empty()).count(),
        1
    );
    // With flat normals written, both share one primitive again.
    let written = ExportOptions {
        flat_normals: FlatNormals::Written,
        ..ExportOptions::default()
    };
    let (json, _) = split_glb(&write_glb(&model, &written));
    assert_eq!(json["meshes"].as_array().unwrap().len(), 1);
    assert_eq!(json["meshes"][0]["primitives"].as_array().unwrap().len(), 1);
}

#[test]
fn a_textured_box_keeps_its_uvs_and_splits_its_corners_only_at_seams() {
    let mut part = flat("box", RED, cuboid(DVec3::ONE));
    // Each face's own uvs: the corners of a face map to the corners of the image.
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut uvs = Vec::new();
    for f in 0..part.mesh.face_count() {
        let face: Vec<u32> = part.mesh.face(f).to_vec();
        let first = positions.len() as u32;
        for (k, &v) in face.iter().enumerate() {
            positions.push(part.mesh.positions()[v as usize]);
            uvs.push([DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y][k]);
        }
        faces.push([first, first + 1, first + 2, first + 3]);
    }
    part.mesh = Mesh::from_faces(positions, faces);
    part.uvs = uvs;
    part.texture = Some(std::sync::Arc::new(Texture {
        path: "brick.png".into(),
        image: Some(
            include_bytes!("../../../../examples/textures/brick.png")
                .as_slice()
                .into(),
        ),
    }));
    let model = Model {
        parts: vec![part],
        ..Model::default()
    };
    let glb = write_glb(&model, &ExportOptions::default());
    let (json, _) = split_glb(&glb);
    let primitive = &json["meshes"][0]["primitives"][0];
    assert!(primitive["attributes"].get("NORMAL").is_none());
    // Faces share a corner only where they give it the same uv: 20 of the 24 (position, uv)
    // pairs differ.
    assert_eq!(counts(&glb), [(20, 36)]);
    assert_eq!(accessor(&json, primitive, "TEXCOORD_0")["count"], 20);
    let pairs = |part: &Part| -> Vec<[f32; 5]> {
        let mut pairs: Vec<[f32; 5]> = (0..part.mesh.vertex_count())
            .map(|v| {
                let (p, uv) = (part.mesh.positions()[v], part.uvs[v]);
                [p.x, p.y, p.z, uv.x, uv.y].map(|x| x as f32)
            })
            .collect();
        pairs.sort_by(|a, b| a.partial_cmp(b).unwrap());
        pairs.dedup();
        pairs
    };
    let back = read_glb(&glb).unwrap();
    assert_eq!(pairs(&back.parts[0]), pairs(&model.parts[0]));
}

#[test]
fn a_double_sided_leaf_keeps_its_back_on_corners_of_its_own() {
    // A quad and its back, as L-system leaves are: readers that keep one face per set of
    // corners (Blender) must not see the back as a copy of the front.
    let corners = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    let leaf = Mesh::from_faces(corners.to_vec(), [[0u32, 1, 2, 3], [3, 2, 1, 0]]);
    let model = Model {
        parts: vec![flat("leaf", GREEN, leaf)],
        ..Model::default()
    };
    let glb = write_glb(&model, &ExportOptions::default());
    assert_eq!(counts(&glb), [(8, 12)]);
    let back = read_glb(&glb).unwrap();
    let mesh = &back.parts[0].mesh;
    let mut sets: Vec<Vec<u32>> = (0..mesh.face_count())
        .map(|f| {
            let mut set = mesh.face(f).to_vec();
            set.sort_unstable();
            set
        })
        .collect();
    sets.sort();
    sets.dedup();
    assert_eq!(sets.len(), 4);
}
