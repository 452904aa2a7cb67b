//! `derive --tiles` with `--quantize` and `--meshopt`: every near and far tile encoded as the
//! GLB of `-o` would be, with and without `--metadata`: the same triangles and feature ids as
//! float tiles in fewer bytes, inside the tiles' boxes (docs/tiles.md, "Encodings").

use std::path::Path;

use crate::common;
use crate::tiles::{
    assert_same_files, city, derive_tiles, derive_tiles_with, in_box, positions, triangles,
};
use crate::tiles_metadata::{GRAMMAR, chunks, table, triangles_per_feature};

use common::{TempDir, example, shapegram, stderr};
use serde_json::{Value, json};

/// The runs compared: floats, then each encoding's flag.
const ENCODINGS: [(&str, &[&str]); 3] = [
    ("float", &[]),
    ("quantized", &["--quantize"]),
    ("meshopt", &["--meshopt"]),
];

/// The tiles of a tileset, as paths relative to it (`near/0_0.glb`), in order.
fn tiles_of(dir: &Path) -> Vec<String> {
    let mut names = Vec::new();
    for folder in ["near", "far"] {
        for entry in std::fs::read_dir(dir.join(folder)).unwrap() {
            let name = entry.unwrap().file_name();
            names.push(format!("{folder}/{}", name.to_str().unwrap()));
        }
    }
    names.sort();
    names
}

/// A list of extension names in a GLB's JSON (`extensionsUsed` or `extensionsRequired`).
fn names(json: &Value, list: &str) -> Vec<String> {
    let names = json[list].as_array().cloned().unwrap_or_default();
    names
        .iter()
        .map(|name| name.as_str().unwrap().to_owned())
        .collect()
}

/// A GLB's JSON and BIN chunks with its EXT_meshopt_compression views decoded by
/// meshoptimizer's decoders: the data appended to the BIN chunk and each view pointed there, as
/// a reader does before it reads the accessors.
fn decoded(path: &Path) -> (Value, Vec<u8>) {
    let (mut json, compressed) = chunks(path);
    let mut bin = compressed.clone();
    for view in json["bufferViews"].as_array_mut().unwrap() {
        let Some(codec) = view
            .get("extensions")
            .and_then(|e| e.get("EXT_meshopt_compression"))
            .cloned()
        else {
            continue;
        };
        let field = |name: &str| codec[name].as_u64().unwrap() as usize;
        let start = field("byteOffset");
        let data = &compressed[start..start + field("byteLength")];
        let (count, stride) = (field("count"), field("byteStride"));
        let indices = |decoded: Vec<u32>| -> Vec<u8> {
            match stride {
                2 => decoded
                    .iter()
                    .flat_map(|&i| (i as u16).to_le_bytes())
                    .collect(),
                _ => decoded.iter().flat_map(|i| i.to_le_bytes()).collect(),
            }
        };
        let bytes: Vec<u8> = match (codec["mode"].as_str().unwrap(), stride) {
            ("ATTRIBUTES", 4) => meshopt::decode_vertex_buffer::<[u8; 4]>(data, count)
                .unwrap()
                .concat(),
            ("ATTRIBUTES", 8) => meshopt::decode_vertex_buffer::<[u8; 8]>(data, count)
                .unwrap()
                .concat(),
            ("ATTRIBUTES", 12) => meshopt::decode_vertex_buffer::<[u8; 12]>(data, count)
                .unwrap()
                .concat(),
            ("ATTRIBUTES", 16) => meshopt::decode_vertex_buffer::<[u8; 16]>(data, count)
                .unwrap()
                .concat(),
            ("TRIANGLES", _) => indices(meshopt::decode_index_buffer::<u32>(data, count).unwrap()),
            ("INDICES", _) => indices(meshopt::decode_index_sequence::<u32>(data, count).unwrap()),
            other => panic!("{}: unexpected view {other:?}", path.display()),
        };
        assert_eq!(bytes.len(), count * stride);
        bin.resize(bin.len().next_multiple_of(4), 0);
        view["buffer"] = json!(0);
        view["byteOffset"] = json!(bin.len());
        view["byteLength"] = json!(bytes.len());
        bin.extend(bytes);
    }
    (json, bin)
}

/// Each primitive's `_FEATURE_ID_0`, vertex by vertex, in order of meshes and primitives.
fn feature_ids(json: &Value, bin: &[u8]) -> Vec<Vec<u32>> {
    let mut all = Vec::new();
    for mesh in json["meshes"].as_array().unwrap() {
        for primitive in mesh["primitives"].as_array().unwrap() {
            let index = primitive["attributes"]["_FEATURE_ID_0"].as_u64().unwrap();
            let accessor = &json["accessors"][index as usize];
            let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
            assert_eq!(
                view["byteStride"], 4,
                "vertex attributes are padded to 4 bytes"
            );
            let size = match accessor["componentType"].as_u64().unwrap() {
                5121 => 1,
                5123 => 2,
                _ => 4,
            };
            let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
            let ids = (0..accessor["count"].as_u64().unwrap() as usize).map(|i| {
                let mut word = [0; 4];
                word[..size].copy_from_slice(&bin[start + 4 * i..start + 4 * i + size]);
                u32::from_le_bytes(word)
            });
            all.push(ids.collect());
        }
    }
    all
}

fn folder_size(dir: &Path) -> u64 {
    let tiles = tiles_of(dir).into_iter();
    tiles
        .map(|tile| std::fs::metadata(dir.join(tile)).unwrap().len())
        .sum()
}

#[test]
fn encoded_tiles_are_smaller_with_the_same_triangles_and_feature_ids() {
    let dir = TempDir::new("tiles-encoded");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    // Houses, not bare boxes: tiles of a few boxes are mostly JSON, which the encodings make
    // longer (the node that undoes the grid, the extensions' names and objects).
    let grammar = example("house.cga");
    for metadata in [false, true] {
        let run = |name: &str| {
            let suffix = if metadata { "-metadata" } else { "" };
            dir.path(&format!("{name}{suffix}"))
        };
        for (name, flags) in ENCODINGS {
            let mut extra = flags.to_vec();
            extra.extend(metadata.then_some("--metadata"));
            let err = derive_tiles(&grammar, &lots, &run(name), &extra);
            assert!(!err.contains("warning"), "{err}");
            // glTF extensions are declared in each GLB: the tileset's extensionsUsed and
            // extensionsRequired are for 3D Tiles extensions, of which it uses none.
            let tileset: Value =
                serde_json::from_slice(&std::fs::read(run(name).join("tileset.json")).unwrap())
                    .unwrap();
            assert!(tileset.get("extensionsUsed").is_none(), "{tileset}");
            assert!(tileset.get("extensionsRequired").is_none(), "{tileset}");
        }
        let dirs = ENCODINGS.map(|(name, _)| run(name));
        let tiles = tiles_of(&dirs[0]);
        assert_eq!(tiles.len(), 16 + 4);
        for other in &dirs[1..] {
            assert_eq!(tiles_of(other), tiles);
        }
        for tile in &tiles {
            let paths = dirs.clone().map(|dir| dir.join(tile));
            let json = paths.clone().map(|path| chunks(&path).0);
            // As the GLB of -o: quantisation required; meshopt required too, since its
            // fallback buffer has no data.
            let required = json.clone().map(|json| names(&json, "extensionsRequired"));
            assert_eq!(
                required,
                [
                    vec![],
                    vec!["KHR_mesh_quantization".to_owned()],
                    vec![
                        "KHR_mesh_quantization".to_owned(),
                        "EXT_meshopt_compression".to_owned()
                    ],
                ],
                "{tile}"
            );
            for json in &json {
                let used = names(json, "extensionsUsed");
                let features = ["EXT_mesh_features", "EXT_structural_metadata"];
                let described = features.iter().all(|f| used.contains(&f.to_string()));
                assert_eq!(described, metadata, "{tile}: {used:?}");
            }
            let counts = paths.clone().map(|path| triangles(&path));
            assert!(counts[0] >= 12, "{tile}: {counts:?}");
            assert_eq!(counts, [counts[0]; 3], "{tile}");
            if metadata {
                let [float, quantized, meshopt] = paths.clone().map(|path| decoded(&path));
                let ids = feature_ids(&float.0, &float.1);
                assert_eq!(feature_ids(&quantized.0, &quantized.1), ids, "{tile}");
                assert_eq!(feature_ids(&meshopt.0, &meshopt.1), ids, "{tile}");
                // Each lot's triangles, all corners of each carrying its lot's feature id: two
                // lots in a near tile, eight in a far tile.
                let per_feature = triangles_per_feature(&meshopt.0, &meshopt.1);
                assert_eq!(per_feature, triangles_per_feature(&float.0, &float.1));
                let lots = if tile.starts_with("near") { 2 } else { 8 };
                assert_eq!(per_feature.len(), lots, "{tile}: {per_feature:?}");
                assert_eq!(table(&meshopt.0, &meshopt.1), table(&float.0, &float.1));
            }
        }
        let sizes = dirs.clone().map(|dir| folder_size(&dir));
        assert!(sizes[1] < sizes[0] && sizes[2] < sizes[1], "{sizes:?}");
    }
}

#[test]
fn encoded_tiles_are_the_same_bytes_on_any_number_of_threads() {
    let dir = TempDir::new("tiles-encoded-threads");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    let grammar = dir.path("city.cga");
    std::fs::write(&grammar, GRAMMAR).unwrap();
    for threads in ["1", "4"] {
        let out = dir.path(&format!("out-{threads}"));
        let flags = ["--metadata", "--meshopt", "-q"];
        derive_tiles_with(&grammar, &lots, &out, ("50", Some(threads)), &flags);
    }
    assert_same_files(&dir.path("out-1"), &dir.path("out-4"));
}

#[test]
fn quantised_tiles_stay_inside_their_boxes() {
    // A 12 m block 60 km long: the grid of its tiles' mesh has steps of 0.92 m, so its roof
    // is quantised 6.41 m above the block's middle, not 6 m, far beyond the centimetre float
    // boxes keep.
    let dir = TempDir::new("tiles-quantised-boxes");
    let lots = dir.path("long.geojson");
    let long = [
        [0.0, 0.0],
        [60_000.0, 0.0],
        [60_000.0, 30.0],
        [0.0, 30.0],
        [0.0, 0.0],
    ];
    let city = json!({"type": "Polygon", "coordinates": [long]});
    std::fs::write(&lots, city.to_string()).unwrap();
    let grammar = dir.path("block.cga");
    std::fs::write(&grammar, "Lot --> extrude(12) Mass.\n").unwrap();
    let boxes = |name: &str, flags: &[&str]| -> Vec<(String, Value)> {
        let out = dir.path(name);
        derive_tiles_with(&grammar, &lots, &out, ("100000", None), flags);
        let tileset: Value =
            serde_json::from_slice(&std::fs::read(out.join("tileset.json")).unwrap()).unwrap();
        let far = &tileset["root"]["children"][0];
        let near = &far["children"][0];
        [far, near]
            .map(|tile| {
                let uri = tile["content"]["uri"].as_str().unwrap();
                (
                    out.join(uri).display().to_string(),
                    tile["boundingVolume"]["box"].clone(),
                )
            })
            .to_vec()
    };
    let float = boxes("float", &[]);
    for flag in ["--quantize", "--meshopt"] {
        let encoded = boxes(flag.trim_start_matches('-'), &[flag]);
        for ((path, b), (_, float_box)) in encoded.iter().zip(&float) {
            let points = positions(Path::new(path));
            assert_eq!(points.len(), 8, "{path}: a box's corners");
            assert!(points.iter().all(|&p| in_box(b, p)), "{path}: {b}");
            // The boxes of float tiles would not hold these positions.
            assert!(points.iter().any(|&p| !in_box(float_box, p)), "{path}");
        }
    }
}

#[test]
fn shards_of_other_encodings_are_not_merged() {
    let dir = TempDir::new("tiles-encoded-shards");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    let grammar = dir.path("city.cga");
    std::fs::write(&grammar, GRAMMAR).unwrap();
    let (first, second) = (dir.path("part0"), dir.path("part1"));
    derive_tiles(&grammar, &lots, &first, &["--shard", "0/2", "--meshopt"]);
    derive_tiles(&grammar, &lots, &second, &["--shard", "1/2"]);
    let merged = dir.path("merged");
    let output = shapegram(&[
        "tiles",
        "merge",
        first.to_str().unwrap(),
        second.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let err = stderr(&output);
    assert!(
        err.contains("shard 1/2 is not of the run of")
            && err.contains("(another shard count, tile size, frame or encoding: --quantize, --meshopt, --normals)"),
        "{err}"
    );
    assert!(!merged.join("tileset.json").exists());
    // An OBJ beside the tiles is written as usual, and says so; the tiles are encoded.
    let obj = dir.path("city.obj");
    let err = derive_tiles(
        &grammar,
        &lots,
        &dir.path("with-obj"),
        &["--meshopt", "-o", obj.to_str().unwrap()],
    );
    assert!(
        err.contains(&format!(
            "warning: --quantize, --meshopt and --normals apply to GLB only; {} is written as usual",
            obj.display()
        )),
        "{err}"
    );
    let (json, _) = chunks(&dir.path("with-obj/near/0_0.glb"));
    assert!(names(&json, "extensionsRequired").contains(&"EXT_meshopt_compression".to_owned()));
}
