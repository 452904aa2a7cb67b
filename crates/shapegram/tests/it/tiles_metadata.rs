//! `derive --tiles --metadata`: each lot a feature of its near and far tiles, with a row of its
//! metadata in the tile's property table (EXT_mesh_features, EXT_structural_metadata), the
//! same metadata as its lot node in the GLB of `-o` (docs/tiles.md, "Metadata").

use std::collections::BTreeMap;
use std::path::Path;

use crate::common;
use crate::tiles::{assert_same_files, city, derive_tiles, derive_tiles_with};

use common::TempDir;
use serde_json::Value;

/// Random heights, a facade, and a report per lot; every lot one box (12 triangles).
pub(crate) const GRAMMAR: &str = "attr height = rand(5, 40)\nattr facade = \"brick\"\n\
    Lot --> report(\"floor.area\", scope.sx * scope.sz) extrude(height) Mass.\n";

/// A GLB's JSON and BIN chunks.
pub(crate) fn chunks(path: &Path) -> (Value, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap();
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let json_len = word(12);
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = bytes.get(20 + json_len + 8..).unwrap_or_default().to_vec();
    (json, bin)
}

/// A buffer view's bytes.
fn view<'a>(json: &Value, bin: &'a [u8], index: &Value) -> &'a [u8] {
    let view = &json["bufferViews"][index.as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
    assert_eq!(start % 8, 0, "property table views start on 8 bytes");
    &bin[start..start + view["byteLength"].as_u64().unwrap() as usize]
}

/// The property table's rows, decoded: by property id, one value per row (JSON).
pub(crate) fn table(json: &Value, bin: &[u8]) -> BTreeMap<String, Vec<Value>> {
    let metadata = &json["extensions"]["EXT_structural_metadata"];
    let table = &metadata["propertyTables"][0];
    assert_eq!(table["class"], "lot");
    let count = table["count"].as_u64().unwrap() as usize;
    let class = &metadata["schema"]["classes"]["lot"]["properties"];
    let mut rows = BTreeMap::new();
    for (id, columns) in table["properties"].as_object().unwrap() {
        let values = view(json, bin, &columns["values"]);
        let property = &class[id];
        let decoded: Vec<Value> = match (
            property["type"].as_str(),
            property["componentType"].as_str(),
        ) {
            (Some("STRING"), _) => {
                let offsets = view(json, bin, &columns["stringOffsets"]);
                let end = |i: usize| {
                    u32::from_le_bytes(offsets[4 * i..4 * i + 4].try_into().unwrap()) as usize
                };
                (0..count)
                    .map(|i| {
                        std::str::from_utf8(&values[end(i)..end(i + 1)])
                            .unwrap()
                            .into()
                    })
                    .collect()
            }
            (_, Some("FLOAT64")) => values
                .chunks_exact(8)
                .take(count)
                .map(|b| f64::from_le_bytes(b.try_into().unwrap()).into())
                .collect(),
            (_, Some("UINT32")) => values
                .chunks_exact(4)
                .take(count)
                .map(|b| u32::from_le_bytes(b.try_into().unwrap()).into())
                .collect(),
            other => panic!("{id}: unexpected {other:?}"),
        };
        rows.insert(id.clone(), decoded);
    }
    rows
}

/// Triangles per feature id over the GLB's primitives, checking that every triangle's corners
/// are of one feature.
pub(crate) fn triangles_per_feature(json: &Value, bin: &[u8]) -> BTreeMap<u32, usize> {
    let read = |accessor: &Value| -> Vec<u32> {
        let accessor = &json["accessors"][accessor.as_u64().unwrap() as usize];
        let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
        let size = match accessor["componentType"].as_u64().unwrap() {
            5121 => 1,
            5123 => 2,
            _ => 4,
        };
        let stride = view["byteStride"].as_u64().map_or(size, |s| s as usize);
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        (0..accessor["count"].as_u64().unwrap() as usize)
            .map(|i| {
                let mut word = [0; 4];
                word[..size].copy_from_slice(&bin[start + i * stride..start + i * stride + size]);
                u32::from_le_bytes(word)
            })
            .collect()
    };
    let mut per_feature = BTreeMap::new();
    for mesh in json["meshes"].as_array().unwrap() {
        for primitive in mesh["primitives"].as_array().unwrap() {
            let ids = read(&primitive["attributes"]["_FEATURE_ID_0"]);
            let extension = &primitive["extensions"]["EXT_mesh_features"]["featureIds"][0];
            assert_eq!(extension["attribute"], 0);
            assert_eq!(extension["propertyTable"], 0);
            let mut distinct = ids.clone();
            distinct.sort_unstable();
            distinct.dedup();
            assert_eq!(extension["featureCount"], distinct.len());
            for triangle in read(&primitive["indices"]).chunks_exact(3) {
                let feature = ids[triangle[0] as usize];
                assert!(triangle.iter().all(|&v| ids[v as usize] == feature));
                *per_feature.entry(feature).or_insert(0) += 1;
            }
        }
    }
    per_feature
}

/// The lot nodes' metadata in the GLB of `-o`, by path.
fn lot_nodes(glb: &Path) -> BTreeMap<String, Value> {
    let (json, _) = chunks(glb);
    json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|node| node["mesh"].is_null() && node["extras"]["shapegram"]["leaves"].is_u64())
        .map(|node| {
            let extras = node["extras"]["shapegram"].clone();
            (extras["path"].as_str().unwrap().to_owned(), extras)
        })
        .collect()
}

#[test]
fn metadata_makes_each_lot_a_feature_of_its_tiles() {
    let dir = TempDir::new("tiles-metadata");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    let grammar = dir.path("city.cga");
    std::fs::write(&grammar, GRAMMAR).unwrap();
    let (out, glb) = (dir.path("out"), dir.path("city.glb"));
    let err = derive_tiles(
        &grammar,
        &lots,
        &out,
        &["--metadata", "-o", glb.to_str().unwrap()],
    );
    assert!(!err.contains("warning"), "{err}");
    let nodes = lot_nodes(&glb);
    assert_eq!(nodes.len(), 32);
    let mut seen = 0;
    for (folder, lots_per_tile) in [("near", 2), ("far", 8)] {
        for entry in std::fs::read_dir(out.join(folder)).unwrap() {
            let (json, bin) = chunks(&entry.unwrap().path());
            let used = json["extensionsUsed"].as_array().unwrap();
            assert!(used.contains(&"EXT_mesh_features".into()));
            assert!(used.contains(&"EXT_structural_metadata".into()));
            let properties = &json["extensions"]["EXT_structural_metadata"]["schema"]["classes"]["lot"]
                ["properties"];
            assert_eq!(properties["floor_area_sum"]["name"], "floor.area_sum");
            assert_eq!(properties["leaves"]["componentType"], "UINT32");
            assert_eq!(properties["height"]["componentType"], "FLOAT64");
            assert_eq!(properties["facade"]["type"], "STRING");
            let rows = table(&json, &bin);
            let paths = &rows["path"];
            assert_eq!(paths.len(), lots_per_tile);
            // Rows in lot order, each the lot node's metadata.
            let index = |p: &Value| {
                p.as_str().unwrap()[4..]
                    .trim_end_matches(']')
                    .parse::<usize>()
                    .unwrap()
            };
            assert!(
                paths.windows(2).all(|w| index(&w[0]) < index(&w[1])),
                "{paths:?}"
            );
            for (row, path) in paths.iter().enumerate() {
                let node = &nodes[path.as_str().unwrap()];
                assert_eq!(rows["rule"][row], node["rule"]);
                assert_eq!(rows["rule"][row], "Lot");
                assert_eq!(rows["leaves"][row], node["leaves"]);
                assert_eq!(rows["height"][row], node["attributes"]["height"]);
                assert_eq!(rows["facade"][row], "brick");
                assert_eq!(
                    rows["floor_area_sum"][row],
                    node["reports"]["floor.area_sum"]
                );
                assert_eq!(rows["floor_area_sum"][row], 600.0);
                assert_eq!(rows["floor_area_n"][row], 1.0);
            }
            // Every lot is a box: 12 triangles of its own feature.
            let expected: BTreeMap<u32, usize> =
                (0..lots_per_tile as u32).map(|f| (f, 12)).collect();
            assert_eq!(triangles_per_feature(&json, &bin), expected);
            if folder == "near" {
                seen += lots_per_tile;
            }
        }
    }
    assert_eq!(seen, 32);
    // The heights differ from lot to lot, so the rows are each lot's own.
    let heights: std::collections::BTreeSet<String> = nodes
        .values()
        .map(|n| n["attributes"]["height"].to_string())
        .collect();
    assert!(heights.len() > 16, "{heights:?}");
}

#[test]
fn metadata_tiles_are_the_same_bytes_on_any_number_of_threads() {
    let dir = TempDir::new("tiles-metadata-threads");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    let grammar = dir.path("city.cga");
    std::fs::write(&grammar, GRAMMAR).unwrap();
    for threads in ["1", "2", "4"] {
        let out = dir.path(&format!("out-{threads}"));
        derive_tiles_with(
            &grammar,
            &lots,
            &out,
            ("50", Some(threads)),
            &["--metadata", "-q"],
        );
    }
    assert_same_files(&dir.path("out-1"), &dir.path("out-2"));
    assert_same_files(&dir.path("out-1"), &dir.path("out-4"));
    // Not the tiles without metadata.
    let plain = dir.path("plain");
    derive_tiles(&grammar, &lots, &plain, &[]);
    let tile = |dir: &Path| std::fs::read(dir.join("near/0_0.glb")).unwrap();
    assert_ne!(tile(&plain), tile(&dir.path("out-1")));
}
