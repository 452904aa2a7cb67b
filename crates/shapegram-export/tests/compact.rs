//! Compact GLB: shared vertices, merged coplanar rectangles, quantised and compressed encodings,
//! and what compaction must leave apart.

mod common;

use common::*;
use serde_json::Value;
use shapegram_export::{ExportOptions, GlbEncoding, read_glb, write_glb};
use shapegram_geom::primitives::cuboid;
use shapegram_geom::{Color, DVec3, Mesh, Metadata, Model, Part};

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
fn a_flat_box_shares_the_corners_of_each_face() {
    let model = Model {
        parts: vec![flat("box", RED, cuboid(DVec3::ONE))],
        ..Model::default()
    };
    // Four corners per face with the face's normal: 24 vertices, not 36.
    for encoding in ENCODINGS {
        assert_eq!(counts(&write_glb(&model, &options(encoding))), [(24, 36)]);
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
    assert_eq!(primitives[1], (4, 6), "the blue tile on its own");
    let (red_vertices, red_indices) = primitives[0];
    assert!(red_indices > 6 && red_indices < 11 * 6, "{red_indices}");
    assert!(red_vertices < 11 * 4, "{red_vertices}");
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
    // Four views (POSITION, NORMAL, indices) per primitive, one primitive per colour.
    assert_eq!(compressed, 3 * 4);
    let (_, plain) = split_glb(&write_glb(&closed_model(), &ExportOptions::default()));
    assert!(
        bin.len() * 3 < plain.len(),
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
