//! `derive --tiles` and `--crs`: the tileset's structure, its bounds around its content,
//! georeferencing without loss of precision, and the lot files it refuses or skips.

use std::path::Path;
use std::process::Command;

use crate::common;

use common::{TempDir, shapegram, stderr};
use serde_json::{Value, json};

/// Every lot becomes a 12 m block.
const GRAMMAR: &str = "Lot --> extrude(12) Mass.\n";

/// 8 × 4 lots of 20 × 30 m, 25 m apart east and 40 m north, their south-west corners at
/// `(east, north)` plus the lot's offset, scaled by `unit` (1 for metres).
pub(crate) fn city(east: f64, north: f64, unit: (f64, f64)) -> Value {
    let mut features = Vec::new();
    for i in 0..8 {
        for j in 0..4 {
            let (x, y) = (f64::from(i) * 25.0, f64::from(j) * 40.0);
            let ring: Vec<[f64; 2]> = [
                (0.0, 0.0),
                (20.0, 0.0),
                (20.0, 30.0),
                (0.0, 30.0),
                (0.0, 0.0),
            ]
            .iter()
            .map(|(dx, dy)| [east + (x + dx) * unit.0, north + (y + dy) * unit.1])
            .collect();
            features.push(json!({"type": "Feature", "properties": {},
                "geometry": {"type": "Polygon", "coordinates": [ring]}}));
        }
    }
    json!({"type": "FeatureCollection", "features": features})
}

/// Derives `lots` into `dir/out` with the extra arguments; returns stderr.
fn tile(dir: &TempDir, lots: &Value, extra: &[&str]) -> String {
    let grammar = dir.path("block.cga");
    std::fs::write(&grammar, GRAMMAR).unwrap();
    let file = dir.path("city.geojson");
    std::fs::write(&file, lots.to_string()).unwrap();
    let out = dir.path("out");
    let mut args = vec![
        grammar.to_str().unwrap(),
        "--lots",
        file.to_str().unwrap(),
        "--tiles",
        out.to_str().unwrap(),
        "--tile-size",
        "50",
    ];
    args.extend(extra);
    let mut all = vec!["derive"];
    all.extend(args);
    let output = shapegram(&all);
    assert!(output.status.success(), "{}", stderr(&output));
    stderr(&output)
}

fn tileset(dir: &TempDir) -> Value {
    serde_json::from_slice(&std::fs::read(dir.path("out/tileset.json")).unwrap()).unwrap()
}

/// The positions of a GLB, turned z-up as 3D Tiles turns glTF content (x, −z, y).
pub(crate) fn positions(path: &Path) -> Vec<[f64; 3]> {
    let model = shapegram_export::read_glb(&std::fs::read(path).unwrap()).unwrap();
    model
        .parts
        .iter()
        .flat_map(|part| part.mesh.positions().iter().map(|p| [p.x, -p.z, p.y]))
        .collect()
}

pub(crate) fn triangles(path: &Path) -> usize {
    let model = shapegram_export::read_glb(&std::fs::read(path).unwrap()).unwrap();
    model.parts.iter().map(|p| p.mesh.triangulate().len()).sum()
}

/// Whether a point lies in a 3D Tiles box (axis-aligned half-axes, as we write them).
pub(crate) fn in_box(b: &Value, p: [f64; 3]) -> bool {
    let b: Vec<f64> = b
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let half = [b[3], b[7], b[11]];
    (0..3).all(|k| (p[k] - b[k]).abs() <= half[k])
}

fn box_corners(b: &Value) -> Vec<[f64; 3]> {
    let b: Vec<f64> = b
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let mut corners = Vec::new();
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                corners.push([b[0] + sx * b[3], b[1] + sy * b[7], b[2] + sz * b[11]]);
            }
        }
    }
    corners
}

#[test]
fn a_tileset_has_far_masses_over_near_models_in_a_grid() {
    let dir = TempDir::new("tiles-structure");
    let err = tile(&dir, &city(0.0, 0.0, (1.0, 1.0)), &[]);
    assert!(
        err.contains("tileset.json: 16 near tiles, 4 far tiles of 32 lots"),
        "{err}"
    );
    let tileset = tileset(&dir);
    assert_eq!(tileset["asset"]["version"], "1.1");
    let root = &tileset["root"];
    assert_eq!(root["refine"], "REPLACE");
    assert!(root.get("content").is_none());
    // Local metres: the frame's origin is the centre of the lots' bounds (97.5, 75).
    let transform: Vec<f64> = serde_json::from_value(root["transform"].clone()).unwrap();
    assert_eq!(
        transform,
        [
            1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 97.5, 75., 0., 1.
        ]
    );
    let root_error = root["geometricError"].as_f64().unwrap();
    let far = root["children"].as_array().unwrap();
    assert_eq!(far.len(), 4);
    let mut near_count = 0;
    let mut lots = 0;
    for parent in far {
        let error = parent["geometricError"].as_f64().unwrap();
        // The largest side of a 20 × 30 × 12 box.
        assert_eq!(error, 30.0);
        assert!(root_error > error);
        let uri = parent["content"]["uri"].as_str().unwrap();
        assert!(uri.starts_with("far/") && uri.ends_with(".glb"), "{uri}");
        let masses = dir.path(&format!("out/{uri}"));
        for p in positions(&masses) {
            assert!(in_box(&parent["boundingVolume"]["box"], p), "{uri}: {p:?}");
            assert!(in_box(&root["boundingVolume"]["box"], p), "{uri}: {p:?}");
        }
        let children = parent["children"].as_array().unwrap();
        // Each far tile holds 4 near tiles of 2 lots: 8 boxes of 12 triangles.
        assert_eq!(children.len(), 4);
        assert_eq!(triangles(&masses), 12 * 8);
        for child in children {
            near_count += 1;
            assert_eq!(child["geometricError"].as_f64(), Some(0.0));
            for corner in box_corners(&child["boundingVolume"]["box"]) {
                assert!(in_box(&parent["boundingVolume"]["box"], corner));
            }
            let uri = child["content"]["uri"].as_str().unwrap();
            assert!(uri.starts_with("near/"), "{uri}");
            let model = dir.path(&format!("out/{uri}"));
            let points = positions(&model);
            for &p in &points {
                assert!(in_box(&child["boundingVolume"]["box"], p), "{uri}: {p:?}");
            }
            // Two blocks: 2 × 6 faces.
            assert_eq!(triangles(&model), 24, "{uri}");
            lots += 2;
        }
    }
    assert_eq!((near_count, lots), (16, 32));
    assert_eq!(std::fs::read_dir(dir.path("out/near")).unwrap().count(), 16);
    assert_eq!(std::fs::read_dir(dir.path("out/far")).unwrap().count(), 4);

    // The same input gives the same bytes.
    let first = std::fs::read(dir.path("out/tileset.json")).unwrap();
    let a_tile = std::fs::read(dir.path("out/near/0_0.glb")).unwrap();
    tile(&dir, &city(0.0, 0.0, (1.0, 1.0)), &[]);
    assert_eq!(std::fs::read(dir.path("out/tileset.json")).unwrap(), first);
    assert_eq!(std::fs::read(dir.path("out/near/0_0.glb")).unwrap(), a_tile);
}

#[test]
fn large_coordinates_keep_their_precision_in_the_local_frame() {
    let near_zero = TempDir::new("tiles-near-zero");
    tile(&near_zero, &city(0.0, 0.0, (1.0, 1.0)), &[]);
    let far_away = TempDir::new("tiles-far-away");
    tile(&far_away, &city(500_000.0, 5_000_000.0, (1.0, 1.0)), &[]);
    for cell in ["near/0_0.glb", "near/-2_-2.glb", "far/0_0.glb"] {
        let a = std::fs::read(near_zero.path(&format!("out/{cell}"))).unwrap();
        let b = std::fs::read(far_away.path(&format!("out/{cell}"))).unwrap();
        assert!(a == b, "{cell} differs");
    }
    let transform = &tileset(&far_away)["root"]["transform"];
    assert_eq!(transform[12], 500_097.5);
    assert_eq!(transform[13], 5_000_075.0);

    // UTM zone 33N on its central meridian, at the equator and near 45° N: the same lots on
    // the ground to a centimetre (f32 at a northing of 5,000,000 would be off by 0.5 m). The
    // grid itself differs from the ground by d² tan(latitude) / R (its meridians converge):
    // 1.5 mm at 100 m from the origin near 45°.
    let equator = TempDir::new("tiles-utm-equator");
    tile(
        &equator,
        &city(500_000.0, 100.0, (1.0, 1.0)),
        &["--crs", "EPSG:32633"],
    );
    let north = TempDir::new("tiles-utm-north");
    tile(
        &north,
        &city(500_000.0, 5_000_000.0, (1.0, 1.0)),
        &["--crs", "EPSG:32633"],
    );
    for cell in ["near/0_0.glb", "near/1_1.glb", "near/-2_-2.glb"] {
        let a = positions(&equator.path(&format!("out/{cell}")));
        let b = positions(&north.path(&format!("out/{cell}")));
        assert_eq!(a.len(), b.len());
        for (p, q) in a.iter().zip(&b) {
            for k in 0..3 {
                assert!((p[k] - q[k]).abs() < 1e-2, "{cell}: {p:?} vs {q:?}");
            }
        }
        // Grid metres on the central meridian are ground metres / 0.9996.
        let east = |points: &[[f64; 3]]| {
            let xs = points.iter().map(|p| p[0]);
            xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min)
        };
        assert!((east(&b) - 45.0 / 0.9996).abs() < 2e-3, "{}", east(&b));
    }
    // The root transform is the east-north-up frame at the lots' centre, 97.5 m east of 15° E.
    let m: Vec<f64> = serde_json::from_value(tileset(&north)["root"]["transform"].clone()).unwrap();
    let east = [m[0], m[1], m[2]];
    let (sin, cos) = 15f64.to_radians().sin_cos();
    assert!(
        (east[0] + sin).abs() < 1e-4 && (east[1] - cos).abs() < 1e-4,
        "{east:?}"
    );
    let radius = (m[12] * m[12] + m[13] * m[13] + m[14] * m[14]).sqrt();
    assert!((6.36e6..6.38e6).contains(&radius), "{radius}");
}

#[test]
fn wgs84_lots_are_metres_on_the_ground() {
    let dir = TempDir::new("tiles-wgs84");
    // Degrees per metre at 52.5° N (WGS84): 1 / 111,267 north, 1 / 67,900 east (about).
    let lots = city(13.4, 52.5, (1.0 / 67_900.0, 1.0 / 111_267.0));
    tile(&dir, &lots, &["--crs", "wgs84"]);
    let tileset = tileset(&dir);
    let children = tileset["root"]["children"].as_array().unwrap();
    assert_eq!(children.len(), 4);
    let points = positions(&dir.path("out/near/0_0.glb"));
    let span = |k: usize| {
        let v = points.iter().map(|p| p[k]);
        v.clone().fold(f64::MIN, f64::max) - v.fold(f64::MAX, f64::min)
    };
    // One lot's 20 × 30 × 12 m block, within the degrees' rounding above (0.3%).
    assert!((span(0) - 45.0).abs() < 0.3, "{}", span(0));
    assert!((span(2) - 12.0).abs() < 1e-4, "{}", span(2));
}

/// Runs derive on a lot file and returns (success, stderr).
fn derive_lots(dir: &TempDir, text: &str, extra: &[&str]) -> (bool, String) {
    let grammar = dir.path("block.cga");
    std::fs::write(&grammar, GRAMMAR).unwrap();
    let file = dir.path("lots.geojson");
    std::fs::write(&file, text).unwrap();
    let out = dir.path("out");
    let mut args = vec![
        "derive",
        grammar.to_str().unwrap(),
        "--lots",
        file.to_str().unwrap(),
        "--tiles",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    let output = shapegram(&args);
    let err = stderr(&output);
    assert!(!err.contains("panicked"), "{err}");
    (output.status.success(), err)
}

fn polygons(rings: &[&str]) -> String {
    let features: Vec<String> = rings
        .iter()
        .map(|r| {
            format!(
                r#"{{"type": "Feature", "properties": {{}}, "geometry": {{"type": "Polygon", "coordinates": {r}}}}}"#
            )
        })
        .collect();
    format!(
        r#"{{"type": "FeatureCollection", "features": [{}]}}"#,
        features.join(", ")
    )
}

#[test]
fn bad_lots_are_errors_or_warnings_naming_the_feature() {
    let dir = TempDir::new("tiles-bad");
    let square = "[[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]]";
    // Projected metres read as degrees.
    let (ok, err) = derive_lots(
        &dir,
        &polygons(&[
            square,
            "[[[448252, 5411935], [448262, 5411935], [448262, 5411945]]]",
        ]),
        &["--crs", "wgs84"],
    );
    assert!(!ok);
    assert!(
        err.starts_with("error: ")
            && err.contains("lots.geojson: features[1]: [448252, 5411935] is no longitude"),
        "{err}"
    );
    // Outside the UTM zone's range.
    let (ok, err) = derive_lots(&dir, &polygons(&[square]), &["--crs", "EPSG:32633"]);
    assert!(!ok);
    assert!(
        err.contains("features[0]: [0, 0] is outside UTM zone 33N"),
        "{err}"
    );
    // A bow tie is skipped, a repeated position counts once, a hole is ignored.
    let (ok, err) = derive_lots(
        &dir,
        &polygons(&[
            square,
            "[[[20, 0], [30, 10], [30, 0], [20, 10], [20, 0]]]",
            "[[[40, 0], [50, 0], [50, 0], [50, 10], [40, 10], [40, 0]]]",
            "[[[60, 0], [70, 0], [70, 10], [60, 10], [60, 0]], [[62, 2], [64, 2], [64, 4], [62, 2]]]",
        ]),
        &[],
    );
    assert!(ok, "{err}");
    assert!(
        err.contains("skipped 1 polygon whose outer ring crosses or touches itself: features[1]"),
        "{err}"
    );
    assert!(err.contains("ignored 1 hole"), "{err}");
    assert!(err.contains("of 3 lots"), "{err}");
    // No polygons at all.
    let (ok, err) = derive_lots(
        &dir,
        r#"{"type": "FeatureCollection", "features": []}"#,
        &[],
    );
    assert!(!ok);
    assert!(err.contains("has no polygons to use as lots"), "{err}");
    // Lots that grow nothing.
    std::fs::write(dir.path("nil.cga"), "Lot --> NIL\n").unwrap();
    std::fs::write(dir.path("one.geojson"), polygons(&[square])).unwrap();
    let output = shapegram(&[
        "derive",
        dir.path("nil.cga").to_str().unwrap(),
        "--lots",
        dir.path("one.geojson").to_str().unwrap(),
        "--tiles",
        dir.path("nil").to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("nothing to tile"),
        "{}",
        stderr(&output)
    );
    // --lot is local metres only.
    let output = shapegram(&[
        "derive",
        dir.path("nil.cga").to_str().unwrap(),
        "--lot",
        "0,0 1,0 1,1",
        "--crs",
        "wgs84",
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("--lot takes local metres"),
        "{}",
        stderr(&output)
    );
    let output = shapegram(&[
        "derive",
        dir.path("nil.cga").to_str().unwrap(),
        "--crs",
        "EPSG:4978",
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains(
            "unknown coordinate system 'EPSG:4978': an Earth-centred system has no ground plane"
        ),
        "{}",
        stderr(&output)
    );
}

/// Every file under `dir` (its path inside `dir`) with its bytes, leaving out the shards'
/// parts of tileset.json.
fn files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut found = std::collections::BTreeMap::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
                continue;
            }
            let name = path.strip_prefix(dir).unwrap().display().to_string();
            if !name.starts_with("tileset.shard-") {
                found.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    found
}

/// Asserts that two folders hold the same files with the same bytes.
pub(crate) fn assert_same_files(a: &Path, b: &Path) {
    let (a_files, b_files) = (files(a), files(b));
    assert_eq!(
        a_files.keys().collect::<Vec<_>>(),
        b_files.keys().collect::<Vec<_>>(),
        "{} vs {}",
        a.display(),
        b.display()
    );
    for (name, bytes) in &a_files {
        assert!(bytes == &b_files[name], "{name} differs in {}", b.display());
    }
}

/// Runs `derive GRAMMAR --lots LOTS --tile-size 50 --tiles DIR` with the extra arguments.
pub(crate) fn derive_tiles(grammar: &Path, lots: &Path, dir: &Path, extra: &[&str]) -> String {
    derive_tiles_with(grammar, lots, dir, ("50", None), extra)
}

/// [`derive_tiles`] with another tile size, on `threads` threads (`RAYON_NUM_THREADS`; the
/// machine's when `None`).
pub(crate) fn derive_tiles_with(
    grammar: &Path,
    lots: &Path,
    dir: &Path,
    (tile_size, threads): (&str, Option<&str>),
    extra: &[&str],
) -> String {
    let mut command = Command::new(env!("CARGO_BIN_EXE_shapegram"));
    command
        .args(["derive", grammar.to_str().unwrap()])
        .args(["--lots", lots.to_str().unwrap(), "--tile-size", tile_size])
        .args(["--tiles", dir.to_str().unwrap()])
        .args(extra);
    if let Some(threads) = threads {
        command.env("RAYON_NUM_THREADS", threads);
    }
    let output = command.output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    stderr(&output)
}

/// Random heights and floors: each lot's seed must come from its place in the whole file.
const RANDOM: &str = "attr height = rand(5, 40)\n\
    Lot --> extrude(height) split(y) { ~3 : Floor }*\n\
    Floor --> 50% : color(\"#aa3322\") F.\n          else : G.\n";

/// Each mass reaches 8 m east (a `reach` occluder, 40% wider than the lot): a lot turns red
/// when the reach of its western neighbour, 5 m away and often in the next cell, overlaps it.
const REACH: &str = "Lot --> extrude(12) [ s('1.4, '1, '1) label(\"reach\") NIL ] Check\n\
    Check --> case overlaps(inter, \"reach\") : Red\n          else : Grey\n\
    Red --> color(\"#ff0000\") X.\nGrey --> X.\n";

#[test]
fn tiles_derived_cell_by_cell_and_in_shards_are_the_whole_derivations_bytes() {
    let dir = TempDir::new("tiles-streamed");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    // With --metadata too: each lot's row must not depend on how the city is cut either; nor
    // the meshopt encoding of its vertices and feature ids.
    let runs: [(&str, &str, &[&str]); 4] = [
        ("random", RANDOM, &[]),
        ("reach", REACH, &[]),
        ("random-metadata", RANDOM, &["--metadata"]),
        ("random-meshopt", RANDOM, &["--metadata", "--meshopt"]),
    ];
    for (name, text, flags) in runs {
        let grammar = dir.path(&format!("{name}.cga"));
        std::fs::write(&grammar, text).unwrap();
        let with = |args: &[&str]| -> Vec<String> {
            args.iter()
                .chain(flags)
                .map(|&arg| arg.to_owned())
                .collect()
        };
        let derive_tiles = |grammar: &Path, lots: &Path, dir: &Path, extra: &[&str]| {
            let extra = with(extra);
            derive_tiles(
                grammar,
                lots,
                dir,
                &extra.iter().map(String::as_str).collect::<Vec<_>>(),
            )
        };
        // With -o the city is derived whole, as one list of lots.
        let whole = dir.path(&format!("{name}-whole"));
        let glb = dir.path(&format!("{name}.glb"));
        derive_tiles(&grammar, &lots, &whole, &["-o", glb.to_str().unwrap()]);
        let single = dir.path(&format!("{name}-single"));
        let err = derive_tiles(&grammar, &lots, &single, &[]);
        assert!(
            err.contains("16 near tiles, 4 far tiles of 32 lots"),
            "{err}"
        );
        assert_same_files(&whole, &single);
        for n in 1..=3 {
            let parts: Vec<String> = (0..n)
                .map(|k| {
                    let part = dir.path(&format!("{name}-{k}-of-{n}"));
                    derive_tiles(&grammar, &lots, &part, &["--shard", &format!("{k}/{n}")]);
                    assert!(!part.join("tileset.json").exists());
                    part.display().to_string()
                })
                .collect();
            let merged = dir.path(&format!("{name}-merged-{n}"));
            let mut args = vec!["tiles", "merge"];
            args.extend(parts.iter().map(String::as_str));
            args.extend(["--out", merged.to_str().unwrap()]);
            let output = shapegram(&args);
            assert!(output.status.success(), "{}", stderr(&output));
            assert!(
                stderr(&output).contains("tileset.json: 16 near tiles, 4 far tiles of 32 lots"),
                "{}",
                stderr(&output)
            );
            assert_same_files(&single, &merged);
        }
    }
    // Shards written into one folder merge in place.
    let grammar = dir.path("reach.cga");
    let shared = dir.path("shared");
    for k in 0..2 {
        derive_tiles(&grammar, &lots, &shared, &["--shard", &format!("{k}/2")]);
    }
    let output = shapegram(&[
        "tiles",
        "merge",
        shared.to_str().unwrap(),
        "--out",
        shared.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_same_files(&dir.path("reach-single"), &shared);
}

#[test]
fn context_beyond_the_halo_is_not_seen() {
    let dir = TempDir::new("tiles-halo");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    let grammar = dir.path("reach.cga");
    std::fs::write(&grammar, REACH).unwrap();
    let whole = dir.path("whole");
    let glb = dir.path("whole.glb");
    derive_tiles(&grammar, &lots, &whole, &["-o", glb.to_str().unwrap()]);
    // The lots 5 m west of a cell are in its halo of 5 m, not in one of 2 m: without them,
    // the westmost lots of each cell stay grey.
    let wide = dir.path("wide");
    let wide_err = derive_tiles(&grammar, &lots, &wide, &["--halo", "5"]);
    assert_same_files(&whole, &wide);
    let derived = |err: &str| -> usize {
        let (_, after) = err.split_once("32 lots, ").unwrap();
        after.split(' ').next().unwrap().parse().unwrap()
    };
    // Lots count again for every cell whose halo they are in.
    assert!(derived(&wide_err) > 32, "{wide_err}");
    let narrow = dir.path("narrow");
    let err = derive_tiles(&grammar, &lots, &narrow, &["--halo", "2"]);
    // Lots reaching over the border into the next cell to the north or south are its
    // context even without a halo; those 5 m west of a cell are not.
    assert!(derived(&err) < derived(&wide_err), "{err}");
    let (whole, narrow) = (files(&whole), files(&narrow));
    let differ: Vec<&String> = whole.keys().filter(|k| whole[*k] != narrow[*k]).collect();
    // Cells 1 to 3 of every row of cells have a western neighbour in the cell before; the
    // far tiles hold boxes, alike; tileset.json's bounds are alike too.
    assert_eq!(differ.len(), 12, "{differ:?}");
    assert!(differ.iter().all(|k| k.starts_with("near")), "{differ:?}");
    // A grammar without context rules derives each lot once, whatever the halo.
    let random = dir.path("random.cga");
    std::fs::write(&random, RANDOM).unwrap();
    let err = derive_tiles(&random, &lots, &dir.path("random"), &["--halo", "100"]);
    assert!(
        err.contains("32 lots, 32 lots derived cell by cell"),
        "{err}"
    );
}

/// The `print: ` lines of a run's output, sorted.
fn printed(err: &str) -> Vec<&str> {
    let mut lines: Vec<&str> = err
        .lines()
        .filter_map(|l| l.strip_prefix("print: "))
        .collect();
    lines.sort_unstable();
    lines
}

#[test]
fn lots_derived_as_context_do_not_print_again() {
    let dir = TempDir::new("tiles-prints");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    // The reach grammar, printing each lot's name before and after its occlusion query.
    let grammar = dir.path("reach.cga");
    let printing = REACH
        .replace("Lot --> ", "Lot --> print(initialShape.name) ")
        .replace("Red --> ", "Red --> print(initialShape.name + \" red\") ")
        .replace(
            "Grey --> ",
            "Grey --> print(initialShape.name + \" grey\") ",
        );
    std::fs::write(&grammar, printing).unwrap();
    let whole = derive_tiles(
        &grammar,
        &lots,
        &dir.path("whole"),
        &["-o", &dir.path("w.glb").display().to_string()],
    );
    let streamed = derive_tiles(&grammar, &lots, &dir.path("streamed"), &["--halo", "5"]);
    let (whole, streamed) = (printed(&whole), printed(&streamed));
    assert_eq!(whole.len(), 64, "{whole:?}");
    assert_eq!(
        whole.iter().filter(|l| l.ends_with(" red")).count(),
        28,
        "{whole:?}"
    );
    assert_eq!(streamed, whole);
    let shards: Vec<String> = (0..2)
        .map(|k| {
            derive_tiles(
                &grammar,
                &lots,
                &dir.path(&format!("s{k}")),
                &["--shard", &format!("{k}/2")],
            )
        })
        .collect();
    let mut sharded: Vec<&str> = shards.iter().flat_map(|err| printed(err)).collect();
    sharded.sort_unstable();
    assert_eq!(sharded, whole);
}

#[test]
fn empty_shards_are_written_and_bad_shards_refused() {
    let dir = TempDir::new("tiles-shards");
    let lots = dir.path("city.geojson");
    std::fs::write(&lots, city(0.0, 0.0, (1.0, 1.0)).to_string()).unwrap();
    let grammar = dir.path("block.cga");
    std::fs::write(&grammar, GRAMMAR).unwrap();
    let single = dir.path("single");
    derive_tiles(&grammar, &lots, &single, &[]);
    // Four parent tiles among six shards: two shards have none.
    let all = dir.path("all");
    let mut empty = 0;
    for k in 0..6 {
        let err = derive_tiles(&grammar, &lots, &all, &["--shard", &format!("{k}/6")]);
        if err.contains("0 near tiles, 0 far tiles of 0 lots (the city has fewer parent tiles") {
            empty += 1;
            let part: Value = serde_json::from_slice(
                &std::fs::read(all.join(format!("tileset.shard-{k}-of-6.json"))).unwrap(),
            )
            .unwrap();
            assert_eq!(part["far"], json!([]));
        }
    }
    assert_eq!(empty, 2);
    let merged = dir.path("merged");
    let merge = |dirs: &[&Path]| {
        let mut args = vec!["tiles".to_owned(), "merge".to_owned()];
        args.extend(dirs.iter().map(|d| d.display().to_string()));
        args.extend(["--out".to_owned(), merged.display().to_string()]);
        shapegram(&args)
    };
    let output = merge(&[&all]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_same_files(&single, &merged);

    let refused = |args: &[&str], code: i32, expected: &str| {
        let output = shapegram(args);
        assert_eq!(output.status.code(), Some(code), "{}", stderr(&output));
        assert!(stderr(&output).contains(expected), "{}", stderr(&output));
        assert!(!stderr(&output).contains("panicked"));
    };
    let (g, l, out) = (
        grammar.to_str().unwrap(),
        lots.to_str().unwrap(),
        dir.path("out").display().to_string(),
    );
    let derive = ["derive", g, "--lots", l, "--tiles", &out];
    for (shard, expected) in [
        ("3/3", "shards of 3 are numbered 0 to 2"),
        ("0/0", "a tileset needs at least 1 shard"),
        ("1", "is no shard: expected k/n"),
    ] {
        refused(&[&derive[..], &["--shard", shard]].concat(), 2, expected);
    }
    refused(
        &[&derive[..], &["--shard", "0/2", "-o", "x.glb"]].concat(),
        2,
        "--shard writes one shard's tiles only",
    );
    refused(
        &["derive", g, "--shard", "0/2"],
        2,
        "required arguments were not provided",
    );
    // A shard missing, or given twice.
    std::fs::remove_file(all.join("tileset.shard-1-of-6.json")).unwrap();
    let output = merge(&[&all]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("missing shard 1/6 of 6"),
        "{}",
        stderr(&output)
    );
    let output = merge(&[&all, &all]);
    assert!(
        stderr(&output).contains("shard 0/6 is also in"),
        "{}",
        stderr(&output)
    );
    let output = merge(&[&single]);
    assert!(
        stderr(&output).contains("no shard of a tileset here"),
        "{}",
        stderr(&output)
    );
}
