//! Features (EXT_mesh_features, EXT_structural_metadata): each vertex's feature id, a property
//! table of the features' metadata, and compaction that never joins two features.

use crate::common;

use common::*;
use serde_json::Value;
use shapegram_export::{
    ExportOptions, Features, GlbEncoding, write_glb, write_glb_with_features_to,
};
use shapegram_geom::primitives::cuboid;
use shapegram_geom::{DAffine3, DVec3, MetaValue, Metadata, Model, Part};

/// Two lots side by side: boxes of 10 × 6 × 10 m at x 0..10 and 10..20, the same colour, so
/// that their roofs (and fronts, backs and bottoms) are coplanar rectangles with an edge in
/// common, which compaction would merge.
fn two_lots() -> Model {
    let lot = |x: f64| Part {
        name: "Mass".to_owned(),
        color: GREY,
        mesh: cuboid(DVec3::new(10.0, 6.0, 10.0))
            .transformed(&DAffine3::from_translation(DVec3::new(x, 0.0, 0.0))),
        ..Part::default()
    };
    Model {
        parts: vec![lot(0.0), lot(10.0)],
        ..Model::default()
    }
}

fn row(index: usize, height: f64) -> Metadata {
    Metadata {
        rule: Some("Lot".to_owned()),
        path: Some(format!("Lot[{index}]")),
        leaves: Some(1),
        attributes: vec![("height".to_owned(), MetaValue::Number(height))],
        reports: Some(vec![(
            "floor.area_sum".to_owned(),
            MetaValue::Number(100.0 * height),
        )]),
        ..Metadata::default()
    }
}

fn written(model: &Model, features: &Features<'_>, encoding: GlbEncoding) -> Vec<u8> {
    let options = ExportOptions {
        encoding,
        ..ExportOptions::default()
    };
    let mut out = Vec::new();
    write_glb_with_features_to(model, &options, features, &mut out).unwrap();
    out
}

/// An accessor's elements as u32, each read from the first `size` bytes of its element of
/// `element` bytes (when its view states no stride).
fn elements(json: &Value, bin: &[u8], accessor: u64, (size, element): (usize, usize)) -> Vec<u32> {
    let accessor = &json["accessors"][accessor as usize];
    let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + accessor["byteOffset"].as_u64().unwrap_or(0) as usize;
    let stride = view["byteStride"].as_u64().map_or(element, |s| s as usize);
    (0..accessor["count"].as_u64().unwrap() as usize)
        .map(|i| {
            let at = start + i * stride;
            let mut word = [0; 4];
            word[..size].copy_from_slice(&bin[at..at + size]);
            u32::from_le_bytes(word)
        })
        .collect()
}

/// Each primitive's (feature id per vertex, triangles as vertex indices, x of each vertex).
fn primitives(glb: &[u8]) -> Vec<(Vec<u32>, Vec<u32>, Vec<f32>)> {
    let (json, bin) = split_glb(glb);
    let mut out = Vec::new();
    for mesh in json["meshes"].as_array().unwrap() {
        for primitive in mesh["primitives"].as_array().unwrap() {
            let ids = primitive["attributes"]["_FEATURE_ID_0"].as_u64().unwrap();
            let id_accessor = &json["accessors"][ids as usize];
            assert_eq!(id_accessor["type"], "SCALAR");
            assert_eq!(id_accessor["componentType"], 5121, "u8 holds 2 features");
            let indices = primitive["indices"].as_u64().unwrap();
            let index_size = match json["accessors"][indices as usize]["componentType"].as_u64() {
                Some(5123) => 2,
                _ => 4,
            };
            let positions = primitive["attributes"]["POSITION"].as_u64().unwrap();
            let x = elements(&json, &bin, positions, (4, 12))
                .into_iter()
                .map(f32::from_bits)
                .collect();
            out.push((
                elements(&json, &bin, ids, (1, 4)),
                elements(&json, &bin, indices, (index_size, index_size)),
                x,
            ));
        }
    }
    out
}

#[test]
fn touching_lots_keep_their_faces_and_vertices_apart() {
    let model = two_lots();
    let (a, b) = (row(0, 6.0), row(1, 6.0));
    let features = Features {
        rows: vec![&a, &b],
        parts: vec![0, 1],
        lines: Vec::new(),
    };
    // Without features the coplanar faces merge: fewer than 2 × 12 triangles.
    let plain = write_glb(
        &model,
        &ExportOptions {
            encoding: GlbEncoding::Float,
            ..ExportOptions::default()
        },
    );
    let (json, _) = split_glb(&plain);
    let plain_triangles: u64 = json["meshes"][0]["primitives"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            json["accessors"][p["indices"].as_u64().unwrap() as usize]["count"]
                .as_u64()
                .unwrap()
                / 3
        })
        .sum();
    assert!(plain_triangles < 24, "{plain_triangles} triangles");

    let glb = written(&model, &features, GlbEncoding::Float);
    let mut triangles_of = [0; 2];
    let mut at_the_seam = [0; 2];
    for (ids, indices, x) in primitives(&glb) {
        for triangle in indices.chunks_exact(3) {
            let feature = ids[triangle[0] as usize];
            assert!(
                triangle.iter().all(|&v| ids[v as usize] == feature),
                "a triangle's corners are of one feature"
            );
            triangles_of[feature as usize] += 1;
        }
        // Both lots have corners at x = 10, each its own: no vertex is used by both.
        for (v, &x) in x.iter().enumerate() {
            if x == 10.0 {
                at_the_seam[ids[v] as usize] += 1;
            }
        }
    }
    // Each box keeps its 6 faces of 2 triangles.
    assert_eq!(triangles_of, [12, 12]);
    assert!(at_the_seam.iter().all(|&n| n >= 4), "{at_the_seam:?}");
}

#[test]
fn the_file_carries_the_extensions_and_the_table() {
    let model = two_lots();
    let (a, b) = (row(4, 6.0), row(9, 12.5));
    let features = Features {
        rows: vec![&a, &b],
        parts: vec![0, 1],
        lines: Vec::new(),
    };
    for encoding in [
        GlbEncoding::Float,
        GlbEncoding::Quantized,
        GlbEncoding::Compressed,
    ] {
        let glb = written(&model, &features, encoding);
        let (json, bin) = split_glb(&glb);
        let used: Vec<&str> = json["extensionsUsed"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e.as_str().unwrap())
            .collect();
        assert!(used.contains(&"EXT_mesh_features") && used.contains(&"EXT_structural_metadata"));
        for primitive in json["meshes"][0]["primitives"].as_array().unwrap() {
            assert_eq!(
                primitive["extensions"]["EXT_mesh_features"],
                serde_json::json!({"featureIds": [
                    {"featureCount": 2, "attribute": 0, "propertyTable": 0}
                ]})
            );
        }
        let metadata = &json["extensions"]["EXT_structural_metadata"];
        let table = &metadata["propertyTables"][0];
        assert_eq!(table["count"], 2);
        let properties = &metadata["schema"]["classes"]["lot"]["properties"];
        assert_eq!(properties["floor_area_sum"]["name"], "floor.area_sum");
        // The table's views come first, each on an 8-byte boundary.
        let view = |k: &Value| &json["bufferViews"][k.as_u64().unwrap() as usize];
        let path = &table["properties"]["path"];
        let (values, offsets) = (view(&path["values"]), view(&path["stringOffsets"]));
        for v in [values, offsets] {
            assert_eq!(v["byteOffset"].as_u64().unwrap_or(0) % 8, 0);
        }
        let start = values["byteOffset"].as_u64().unwrap_or(0) as usize;
        let ends: Vec<usize> = (0..3)
            .map(|i| {
                let at = offsets["byteOffset"].as_u64().unwrap() as usize + 4 * i;
                u32::from_le_bytes(bin[at..at + 4].try_into().unwrap()) as usize
            })
            .collect();
        let text = |i: usize| std::str::from_utf8(&bin[start + ends[i]..start + ends[i + 1]]);
        assert_eq!((text(0).unwrap(), text(1).unwrap()), ("Lot[4]", "Lot[9]"));
        let height = view(&table["properties"]["height"]["values"]);
        let at = height["byteOffset"].as_u64().unwrap() as usize;
        assert_eq!(
            f64::from_le_bytes(bin[at + 8..at + 16].try_into().unwrap()),
            12.5
        );
    }
}
