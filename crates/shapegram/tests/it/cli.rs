//! End-to-end tests of the `shapegram` binary: write primitives in every format, read them back
//! with `info --json`, derive and check grammars, and check the failures users will meet.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;

use common::{TempDir, example, shapegram, stderr};
use serde_json::Value;
use shapegram_geom::DVec3;
use shapegram_geom::primitives::{cylinder_volume, sphere_volume};

/// Runs a command that must succeed, returning its stderr.
fn ok<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> String {
    let output = shapegram(args);
    assert!(
        output.status.success(),
        "{:?} failed: {}",
        args.iter().map(|a| a.as_ref()).collect::<Vec<_>>(),
        stderr(&output)
    );
    stderr(&output)
}

/// Runs a command that must fail with `code` and exactly one line `error: <prefix>...`.
fn fails<S: AsRef<std::ffi::OsStr>>(args: &[S], code: i32, prefix: &str) -> String {
    let output = shapegram(args);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(code), "stderr: {err}");
    assert!(
        err.starts_with(&format!("error: {prefix}")),
        "expected 'error: {prefix}...', got: {err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(output.stdout.is_empty());
    err
}

/// Like [`fails`], and the message is exactly one line.
fn fails_one_line<S: AsRef<std::ffi::OsStr>>(args: &[S], prefix: &str) -> String {
    let err = fails(args, 1, prefix);
    assert_eq!(err.lines().count(), 1, "not one line: {err}");
    assert!(err.ends_with('\n'));
    err
}

fn info_json(path: &Path) -> Value {
    let output = shapegram(&["info".as_ref(), path.as_os_str(), "--json".as_ref()]);
    assert!(output.status.success(), "info failed: {}", stderr(&output));
    serde_json::from_slice(&output.stdout).unwrap()
}

fn num(info: &Value, key: &str) -> f64 {
    info[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {info}"))
}

fn assert_relative(actual: f64, expected: f64, tolerance: f64) {
    assert!(
        ((actual - expected) / expected).abs() <= tolerance,
        "{actual} differs from {expected} by more than {tolerance} relative"
    );
}

#[test]
fn box_round_trips_through_every_format() {
    let dir = TempDir::new("box");
    for ext in ["glb", "obj", "stl"] {
        let path = dir.path(&format!("box.{ext}"));
        let path_text = path.to_str().unwrap();
        let err = ok(&["primitive", "box", "--size", "10,20,5", "-o", path_text]);
        assert_eq!(
            err,
            format!("wrote {path_text}: 8 vertices, 6 faces, 12 triangles\n")
        );
        if ext == "obj" {
            assert!(dir.path("box.mtl").exists());
        }

        let info = info_json(&path);
        assert_eq!(info["format"], ext);
        assert_eq!(info["parts"], 1);
        assert_eq!(info["vertices"], 8, "{ext}: {info}");
        assert_eq!(info["triangles"], 12, "{ext}: {info}");
        assert_relative(num(&info, "volume"), 1000.0, 1e-9);
        assert_relative(num(&info, "area"), 2.0 * (200.0 + 50.0 + 100.0), 1e-9);
        assert_eq!(info["watertight"], true);
        assert_eq!(info["edges"]["boundary"], 0);
        assert_eq!(info["degenerate_triangles"], 0);
        assert_eq!(info["bounds"]["size"], serde_json::json!([10.0, 20.0, 5.0]));
    }
}

#[test]
fn info_json_is_one_line_with_keys_in_a_stable_order() {
    let dir = TempDir::new("order");
    let path = dir.path("p.stl");
    ok(&["primitive", "pyramid", "-q", "-o", path.to_str().unwrap()]);
    let output = shapegram(&["info", "--json", path.to_str().unwrap()]);
    let text = String::from_utf8(output.stdout).unwrap();
    assert_eq!(text.lines().count(), 1, "{text}");
    let positions: Vec<usize> = [
        "file",
        "format",
        "parts",
        "vertices",
        "faces",
        "triangles",
        "segments",
        "bounds",
        "area",
        "volume",
        "watertight",
        "edges",
        "degenerate_triangles",
    ]
    .iter()
    .map(|key| {
        text.find(&format!("\"{key}\":"))
            .unwrap_or_else(|| panic!("no {key} in {text}"))
    })
    .collect();
    assert!(positions.is_sorted(), "keys out of order: {text}");
}

#[test]
fn info_text_names_every_measure() {
    let dir = TempDir::new("text");
    let path = dir.path("box.glb");
    ok(&[
        "primitive",
        "box",
        "--size",
        "10,20,5",
        "-q",
        "-o",
        path.to_str().unwrap(),
    ]);
    let output = shapegram(&["info", path.to_str().unwrap()]);
    assert!(output.status.success());
    let text = String::from_utf8(output.stdout).unwrap();
    for expected in [
        "format      glb\n",
        "vertices    8 (welded)\n",
        "size        10 × 20 × 5\n",
        "area        700\n",
        "volume      1000 (signed; meaningful only when watertight)\n",
        // GLB stores triangles, so the welded box has 18 edges.
        "watertight  yes (18 edges: 0 boundary, 0 non-manifold, 0 misoriented)\n",
        "degenerate  0 triangles\n",
    ] {
        assert!(text.contains(expected), "missing {expected:?} in:\n{text}");
    }
}

#[test]
fn cylinder_volume_matches_the_polyhedron_and_the_smooth_cylinder() {
    let dir = TempDir::new("cylinder");
    let size = DVec3::new(2.0, 3.0, 2.0);
    for ext in ["glb", "stl"] {
        let path = dir.path(&format!("c.{ext}"));
        let path_text = path.to_str().unwrap();
        ok(&[
            "primitive",
            "cylinder",
            "--size",
            "2,3,2",
            "--sides",
            "64",
            "-q",
            "-o",
            path_text,
        ]);
        let info = info_json(&path);
        let volume = num(&info, "volume");
        // f32 positions in the file: relative round-off around 1e-7 per coordinate.
        assert_relative(volume, cylinder_volume(size, 64), 1e-5);
        assert_relative(volume, PI * 1.0 * 1.0 * 3.0, 2e-3);
        assert_eq!(info["watertight"], true);
        assert_eq!(info["vertices"], 128);
    }
}

#[test]
fn sphere_is_watertight_with_the_polyhedron_volume() {
    let dir = TempDir::new("sphere");
    let path = dir.path("s.glb");
    let path_text = path.to_str().unwrap();
    ok(&[
        "primitive",
        "sphere",
        "--size",
        "2,2,2",
        "--segments",
        "32",
        "--rings",
        "16",
        "-q",
        "-o",
        path_text,
    ]);
    let info = info_json(&path);
    assert_eq!(info["watertight"], true);
    assert_eq!(info["vertices"], 2 + 32 * 15);
    assert_relative(
        num(&info, "volume"),
        sphere_volume(DVec3::splat(2.0), 32, 16),
        1e-4,
    );
}

#[test]
fn quad_is_open_with_exact_area() {
    let dir = TempDir::new("quad");
    let path = dir.path("lot.obj");
    ok(&[
        "primitive",
        "quad",
        "--size",
        "4,0,3",
        "-q",
        "-o",
        path.to_str().unwrap(),
    ]);
    let info = info_json(&path);
    assert_eq!(info["watertight"], false);
    assert_eq!(info["edges"]["boundary"], 4);
    assert_eq!(num(&info, "area"), 12.0);
    assert_eq!(info["bounds"]["size"], serde_json::json!([4.0, 0.0, 3.0]));
}

#[test]
fn l_shaped_footprint_has_its_area() {
    let dir = TempDir::new("footprint");
    let path = dir.path("l.stl");
    // 4 × 1 along x plus 1 × 2 up z: area 6, in clockwise order to check either winding works.
    let err = ok(&[
        "primitive",
        "footprint",
        "--points",
        "0,3 1,3 1,1 4,1 4,0 0,0",
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(
        err.ends_with(": 6 vertices, 1 face, 4 triangles\n"),
        "{err}"
    );
    let info = info_json(&path);
    assert_eq!(num(&info, "area"), 6.0);
    assert_eq!(info["triangles"], 4);
    assert_eq!(info["watertight"], false);
    // Facing up: the enclosed volume of an open mesh is meaningless but the bounds are exact.
    assert_eq!(info["bounds"]["max"], serde_json::json!([4.0, 0.0, 3.0]));
}

#[test]
fn quiet_prints_nothing() {
    let dir = TempDir::new("quiet");
    let path = dir.path("c.glb");
    let output = shapegram(&["primitive", "cone", "-q", "-o", path.to_str().unwrap()]);
    assert!(output.status.success());
    assert!(output.stderr.is_empty() && output.stdout.is_empty());
    assert!(path.exists());
}

#[test]
fn bad_sizes_are_one_line_errors() {
    let dir = TempDir::new("size");
    let out = dir.path("x.glb");
    let out = out.to_str().unwrap();
    let err = fails_one_line(
        &["primitive", "box", "--size", "1,x,3", "-o", out],
        "invalid --size '1,x,3'",
    );
    assert_eq!(
        err,
        "error: invalid --size '1,x,3': expected three positive numbers like 10,20,5\n"
    );
    for bad in ["0,1,1", "-1,1,1", "NaN,1,1", "1,inf,1", "1,2", "1e300,1,1"] {
        fails_one_line(
            &["primitive", "cylinder", "--size", bad, "-o", out],
            "invalid --size",
        );
    }
    assert!(!dir.path("x.glb").exists());
}

#[test]
fn bad_counts_points_and_colours_are_one_line_errors() {
    let dir = TempDir::new("counts");
    let out = dir.path("x.obj");
    let out = out.to_str().unwrap();
    fails_one_line(
        &["primitive", "cylinder", "--sides", "2", "-o", out],
        "invalid --sides 2: expected 3 to 100000 for a cylinder",
    );
    fails_one_line(
        &["primitive", "sphere", "--rings", "1", "-o", out],
        "invalid --rings 1",
    );
    fails_one_line(
        &[
            "primitive",
            "sphere",
            "--segments",
            "2000",
            "--rings",
            "1000",
            "-o",
            out,
        ],
        "a sphere of 2000 segments × 1000 rings is too fine: segments × rings must be at most 1000000",
    );
    fails_one_line(
        &["primitive", "box", "--sides", "8", "-o", out],
        "--sides does not apply to box",
    );
    fails_one_line(
        &["primitive", "footprint", "-o", out],
        "footprint needs --points",
    );
    fails_one_line(
        &["primitive", "footprint", "--points", "0,0 1,0", "-o", out],
        "invalid --points '0,0 1,0'",
    );
    fails_one_line(
        &[
            "primitive",
            "footprint",
            "--points",
            "0,0 1,0 2,0",
            "-o",
            out,
        ],
        "invalid --points '0,0 1,0 2,0': the polygon has no area",
    );
    fails_one_line(
        &[
            "primitive",
            "footprint",
            "--points",
            "-1,0 1,x 0,1",
            "-o",
            out,
        ],
        "invalid --points: '1,x' is not an x,z pair",
    );
    fails_one_line(
        &["primitive", "box", "--color", "blue", "-o", out],
        "invalid --color 'blue'",
    );
    assert!(!dir.path("x.obj").exists());
}

#[test]
fn usage_errors_exit_with_two() {
    fails(
        &["primitive", "dodecahedron", "-o", "x.glb"],
        2,
        "invalid value 'dodecahedron'",
    );
    fails(&["primitive", "box"], 2, "the following required arguments");
    fails(
        &["primitive", "cone", "--sides", "many", "-o", "x.glb"],
        2,
        "invalid value 'many'",
    );
}

#[test]
fn bad_output_paths_are_one_line_errors() {
    let dir = TempDir::new("output");
    let fbx = dir.path("box.fbx");
    let err = fails_one_line(
        &["primitive", "box", "-o", fbx.to_str().unwrap()],
        "unknown file format",
    );
    assert!(err.contains("box.fbx"), "{err}");
    assert!(!fbx.exists());

    let missing_dir = dir.path("no/such/dir/box.glb");
    let err = fails_one_line(
        &["primitive", "box", "-o", missing_dir.to_str().unwrap()],
        "cannot write",
    );
    assert!(err.contains("box.glb"), "{err}");
}

#[test]
fn unreadable_inputs_are_one_line_errors() {
    let dir = TempDir::new("input");
    let missing = dir.path("missing.glb");
    let err = fails_one_line(&["info", missing.to_str().unwrap()], "cannot read");
    assert!(err.contains("missing.glb"), "{err}");

    for (name, bytes, prefix) in [
        (
            "garbage.glb",
            &b"this is not a glb file"[..],
            "broken GLB file",
        ),
        ("garbage.stl", &b"\x00\x01"[..], "broken STL file"),
        ("empty.glb", &b""[..], "broken GLB file"),
        ("garbage.obj", &b"f 1 2 3\nv x y z\n"[..], "broken OBJ file"),
    ] {
        let path = dir.path(name);
        std::fs::write(&path, bytes).unwrap();
        let err = fails_one_line(&["info", path.to_str().unwrap()], prefix);
        assert!(err.contains(name), "{err}");
    }

    let fbx = dir.path("model.fbx");
    std::fs::write(&fbx, b"x").unwrap();
    let err = fails_one_line(&["info", fbx.to_str().unwrap()], "unknown file format");
    assert!(err.contains("model.fbx"), "{err}");
}

#[test]
fn help_shows_examples_and_the_volume_caveat() {
    let output = shapegram(&["--help"]);
    assert!(output.status.success());
    let help = String::from_utf8(output.stdout).unwrap();
    for expected in [
        "primitive",
        "info",
        "derive",
        "check",
        "shapegram primitive box --size 10,20,5 -o box.glb",
        "shapegram derive house.cga -o house.glb",
    ] {
        assert!(help.contains(expected), "missing {expected:?} in:\n{help}");
    }
    assert!(!help.contains("soon"), "{help}");
    let info_help = String::from_utf8(shapegram(&["info", "--help"]).stdout).unwrap();
    let info_help = info_help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        info_help.contains("meaningful only for watertight meshes"),
        "{info_help}"
    );
    let primitive_help = String::from_utf8(shapegram(&["primitive", "--help"]).stdout).unwrap();
    for expected in ["box", "footprint", "[default: 32]", "Examples:"] {
        assert!(
            primitive_help.contains(expected),
            "missing {expected:?} in:\n{primitive_help}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// derive and check

/// The house of the README: on the default 20 × 30 lot with height 12 every facade has a 4.5 m
/// ground floor and round((12 − 4.5) / 3.5) = 2 floors; a floor is 1 m of wall at each end and
/// tiles of about 3 m between: 18 / 3 = 6 on the 20 m front and back, round(28 / 3) = 9 on the
/// 30 m sides.
const HOUSE: &str = r##"attr height = 12
@StartRule
Lot --> extrude(height) Mass
Mass --> comp(f) { front : Facade | side : Facade | top : Roof | bottom : NIL }
Facade --> split(y) { 4.5 : Ground | { ~3.5 : Floor }* }
Floor --> split(x) { 1 : Wall | { ~3 : Tile }* | 1 : Wall }
Tile --> color("#3a6ea5") Window
Roof --> color("#883322")
"##;

/// Leaves of [`HOUSE`]: 4 ground floors, 2 walls on each of 8 floors, 2 × 2 × 6 + 2 × 2 × 9 = 60
/// windows and the roof.
const HOUSE_LEAVES: u64 = 4 + 8 * 2 + 60 + 1;

/// Shapes of [`HOUSE`]: every split part, component and successor is a shape. The lot and Mass
/// (2); 6 faces, each with a successor but the deleted bottom (11); per facade the ground floor
/// and 2 floors, each a part and a successor (4 × 6 = 24); per floor 2 walls and its tiles, each
/// a part and a successor (4 × (4 + 12) + 4 × (4 + 18) = 152); a Window per tile (60).
const HOUSE_SHAPES: u64 = 2 + 11 + 24 + 152 + 60;

/// A directory holding `house.cga`.
fn house_dir(test: &str) -> (TempDir, PathBuf) {
    let dir = TempDir::new(test);
    let grammar = dir.path("house.cga");
    std::fs::write(&grammar, HOUSE).unwrap();
    (dir, grammar)
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs `derive GRAMMAR --stats -q ARGS...`, which must succeed, and returns the JSON.
fn derive_stats(grammar: &Path, args: &[&str]) -> Value {
    let (stats, _) = derive_stats_text(grammar, args);
    stats
}

/// Like [`derive_stats`], also returning the JSON text (whose key order `Value` loses).
fn derive_stats_text(grammar: &Path, args: &[&str]) -> (Value, String) {
    let mut all = vec!["derive", text(grammar), "--stats", "-q"];
    all.extend_from_slice(args);
    let output = shapegram(&all);
    assert!(output.status.success(), "{all:?}: {}", stderr(&output));
    assert!(output.stderr.is_empty(), "-q printed: {}", stderr(&output));
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    (serde_json::from_str(&stdout).unwrap(), stdout)
}

/// The rule counts, in the order of the JSON text.
fn rules(stats: &Value, json: &str) -> Vec<(String, u64)> {
    let rules_at = json.find("\"rules\":").unwrap();
    let mut list: Vec<(usize, String, u64)> = stats["rules"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| {
            let at = json[rules_at..].find(&format!("\"{k}\":")).unwrap();
            (at, k.clone(), v.as_u64().unwrap())
        })
        .collect();
    list.sort();
    list.into_iter().map(|(_, k, v)| (k, v)).collect()
}

fn rule(stats: &Value, name: &str) -> u64 {
    stats["rules"][name].as_u64().unwrap()
}

fn pairs(list: &[(&str, u64)]) -> Vec<(String, u64)> {
    list.iter().map(|&(k, v)| (k.to_owned(), v)).collect()
}

#[test]
fn derive_writes_every_format_and_a_summary_line() {
    let (dir, grammar) = house_dir("derive-formats");
    for ext in ["glb", "obj", "stl"] {
        let out = dir.path(&format!("house.{ext}"));
        let err = ok(&["derive", text(&grammar), "-o", text(&out)]);
        let last = err.lines().last().unwrap();
        let prefix = format!(
            "derived {}: 1 lot, {HOUSE_SHAPES} shapes, {HOUSE_LEAVES} leaves, ",
            text(&out)
        );
        assert!(last.starts_with(&prefix), "{last}");
        assert!(last.ends_with(" ms") || last.ends_with(" s"), "{last}");
        // The grammar leaves Ground, Wall and Window without rules: warnings, not errors.
        assert!(err.starts_with("warning: no rule `Ground`"), "{err}");

        let info = info_json(&out);
        assert_eq!(info["bounds"]["min"], serde_json::json!([0.0, 0.0, 0.0]));
        assert_eq!(info["bounds"]["max"], serde_json::json!([20.0, 12.0, 30.0]));
        // Four walls and the roof; the bottom was deleted.
        assert_relative(num(&info, "area"), 2.0 * (20.0 + 30.0) * 12.0 + 600.0, 1e-6);
        assert_eq!(info["degenerate_triangles"], 0, "{ext}: {info}");
    }
    assert!(dir.path("house.mtl").exists());

    // --group keeps one part per rule name and colour.
    let grouped = dir.path("grouped.glb");
    ok(&[
        "derive",
        text(&grammar),
        "--group",
        "-q",
        "-o",
        text(&grouped),
    ]);
    let info = info_json(&grouped);
    assert_eq!(info["parts"], 4, "Ground, Wall, Window, Roof: {info}");
}

#[test]
fn stats_count_shapes_leaves_and_rules_exactly() {
    let (_dir, grammar) = house_dir("stats");
    let (stats, json) = derive_stats_text(&grammar, &[]);
    assert_eq!(stats["grammar"], text(&grammar));
    assert_eq!(stats["lots"], 1);
    assert_eq!(stats["seed"], 0);
    assert_eq!(stats["shapes"], HOUSE_SHAPES);
    assert_eq!(stats["leaves"], HOUSE_LEAVES);
    // Every leaf is one rectangle.
    assert_eq!(stats["faces"], HOUSE_LEAVES);
    assert_eq!(stats["triangles"], 2 * HOUSE_LEAVES);
    assert!(stats["derive_ms"].as_f64().unwrap() >= 0.0);
    assert!(stats["export_ms"].as_f64().unwrap() >= 0.0);
    assert_eq!(
        rules(&stats, &json),
        pairs(&[
            ("Lot", 1),
            ("Mass", 1),
            ("Facade", 4),
            ("Floor", 8),
            ("Tile", 60),
            ("Roof", 1)
        ])
    );
    assert_eq!(stats["reports"], serde_json::json!({}));

    // Keys in a fixed order.
    let positions: Vec<usize> = [
        "grammar",
        "lots",
        "seed",
        "shapes",
        "leaves",
        "faces",
        "triangles",
        "derive_ms",
        "export_ms",
        "rules",
        "reports",
    ]
    .iter()
    .map(|key| json.find(&format!("\"{key}\":")).unwrap())
    .collect();
    assert!(positions.is_sorted(), "keys out of order: {json}");
}

#[test]
fn attributes_from_the_command_line_override_the_grammar() {
    let (_dir, grammar) = house_dir("attr");
    // round((20 − 4.5) / 3.5) = 4 floors per facade.
    let stats = derive_stats(&grammar, &["--attr", "height=20"]);
    assert_eq!(rule(&stats, "Floor"), 16);
    assert_eq!(rule(&stats, "Tile"), 120);
    assert_eq!(stats["leaves"], 4 + 16 * 2 + 120 + 1);
}

#[test]
fn every_lot_option_is_one_lot() {
    let (_dir, grammar) = house_dir("lots");
    let stats = derive_stats(
        &grammar,
        &[
            "--lot",
            "0,0 20,0 20,30 0,30",
            // Clockwise this time, and away from the origin.
            "--lot",
            "40,30 60,30 60,0 40,0",
        ],
    );
    assert_eq!(stats["lots"], 2);
    assert_eq!(stats["leaves"], 2 * HOUSE_LEAVES);
    assert_eq!(stats["shapes"], 2 * HOUSE_SHAPES);
    assert_eq!(rule(&stats, "Tile"), 120);
}

#[test]
fn lots_come_from_obj_faces_and_geojson_polygons() {
    let (dir, grammar) = house_dir("lot-files");
    // Two 20 × 30 quads: one facing down (its winding is reversed), one facing up.
    let obj = dir.path("parcels.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 20 0 0\nv 20 0 30\nv 0 0 30\n\
         v 50 0 0\nv 70 0 0\nv 70 0 30\nv 50 0 30\n\
         f 1 2 3 4\nf 5 8 7 6\n",
    )
    .unwrap();
    let out = dir.path("parcels.glb");
    let stats = derive_stats(&grammar, &["--lots", text(&obj), "-o", text(&out)]);
    assert_eq!(stats["lots"], 2);
    assert_eq!(stats["leaves"], 2 * HOUSE_LEAVES);
    let info = info_json(&out);
    // Both houses stand on y = 0 and rise to 12: no lot was extruded downwards.
    assert_eq!(info["bounds"]["min"], serde_json::json!([0.0, 0.0, 0.0]));
    assert_eq!(info["bounds"]["max"], serde_json::json!([70.0, 12.0, 30.0]));

    // GeoJSON: y is north, which is −z; the hole is ignored with a warning.
    let geojson = dir.path("parcels.geojson");
    std::fs::write(
        &geojson,
        r#"{"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {"id": 1}, "geometry": {"type": "Polygon",
             "coordinates": [[[0, 0], [20, 0], [20, 30], [0, 30], [0, 0]],
                             [[5, 5], [6, 5], [6, 6], [5, 5]]]}},
            {"type": "Feature", "properties": {"id": 2}, "geometry": {"type": "MultiPolygon",
             "coordinates": [[[[100, 0], [120, 0], [120, 30], [100, 30], [100, 0]]]]}}
        ]}"#,
    )
    .unwrap();
    let out = dir.path("geo.glb");
    let err = ok(&[
        "derive",
        text(&grammar),
        "--lots",
        text(&geojson),
        "-o",
        text(&out),
    ]);
    assert!(
        err.starts_with(&format!(
            "warning: {}: ignored 1 hole (lots have no holes)\n",
            text(&geojson)
        )),
        "{err}"
    );
    assert!(err.contains(": 2 lots, "), "{err}");
    let info = info_json(&out);
    assert_eq!(info["bounds"]["min"], serde_json::json!([0.0, 0.0, -30.0]));
    assert_eq!(info["bounds"]["max"], serde_json::json!([120.0, 12.0, 0.0]));
}

#[test]
fn bad_lots_are_one_line_errors() {
    let (dir, grammar) = house_dir("bad-lots");
    fails_one_line(
        &["derive", text(&grammar), "--lot", "0,0 1,x 1,1"],
        "invalid --lot: '1,x' is not an x,z pair of numbers like 4,2.5",
    );
    fails_one_line(
        &["derive", text(&grammar), "--lot", "0,0 1,0"],
        "invalid --lot '0,0 1,0': expected at least three x,z pairs",
    );
    fails_one_line(
        &["derive", text(&grammar), "--lot", "0,0 1,0 2,0"],
        "invalid --lot '0,0 1,0 2,0': the polygon has no area",
    );
    let json = dir.path("broken.json");
    std::fs::write(&json, "{\"type\": \"FeatureCollection\", ").unwrap();
    let err = fails_one_line(
        &["derive", text(&grammar), "--lots", text(&json)],
        "invalid GeoJSON in ",
    );
    assert!(err.contains("broken.json"), "{err}");
    let empty = dir.path("empty.geojson");
    std::fs::write(&empty, r#"{"type": "FeatureCollection", "features": []}"#).unwrap();
    fails_one_line(
        &["derive", text(&grammar), "--lots", text(&empty)],
        &format!("{} has no polygons to use as lots", text(&empty)),
    );
    fails_one_line(
        &[
            "derive",
            text(&grammar),
            "--lots",
            text(&dir.path("none.obj")),
        ],
        "cannot read",
    );
    fails_one_line(
        &["derive", text(&grammar), "--lots", text(&grammar)],
        "cannot read lots from",
    );
}

#[test]
fn derivations_are_deterministic_and_follow_the_seed() {
    let dir = TempDir::new("seed");
    let grammar = dir.path("random.cga");
    std::fs::write(
        &grammar,
        HOUSE.replace(
            r##"Tile --> color("#3a6ea5") Window"##,
            r##"Tile --> 50% : color("#ff0000") W. else : color("#00ff00") W."##,
        ),
    )
    .unwrap();
    let derive = |seed: &str, threads: &str, name: &str| {
        let out = dir.path(name);
        let output = Command::new(env!("CARGO_BIN_EXE_shapegram"))
            .args(["derive", text(&grammar), "-q", "--seed", seed, "-o"])
            .arg(&out)
            .args(["--lot", "0,0 20,0 20,30 0,30"])
            .args(["--lot", "30,0 50,0 50,30 30,30"])
            .args(["--lot", "60,0 80,0 80,30 60,30"])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(output.status.success(), "{}", stderr(&output));
        std::fs::read(out).unwrap()
    };
    let first = derive("7", "1", "a.glb");
    assert_eq!(first, derive("7", "1", "b.glb"), "the same run twice");
    assert_eq!(first, derive("7", "4", "c.glb"), "1 and 4 threads");
    assert_ne!(first, derive("8", "4", "d.glb"), "another seed");
}

#[test]
fn generations_stop_the_rewriting() {
    let dir = TempDir::new("generations");
    let grammar = dir.path("halves.cga");
    std::fs::write(&grammar, "A --> split(x) { ~1 : A | ~1 : A }\n").unwrap();
    // 1 + 2 + 4 rule applications; the 8 shapes of the last generation become leaves.
    let stats = derive_stats(&grammar, &["--generations", "3"]);
    assert_eq!(stats["leaves"], 8);
    assert_eq!(rule(&stats, "A"), 7);
    assert_eq!(stats["faces"], 8);
}

#[test]
fn print_and_report_reach_stderr_and_stats() {
    let dir = TempDir::new("report");
    let grammar = dir.path("report.cga");
    std::fs::write(
        &grammar,
        "attr floors = 3\n\
         @StartRule\n\
         Lot --> print(\"floors: \" + floors) extrude(floors * 3) comp(f) { side : Side | top : Top. | bottom : NIL }\n\
         Side --> report(\"wall area\", scope.sx * scope.sy) report(\"kind\", \"wall\") Wall.\n",
    )
    .unwrap();
    let output = shapegram(&["derive", text(&grammar), "--stats", "-q"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(stderr(&output), "print: floors: 3\n");
    let stats: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(
        stats["reports"],
        serde_json::json!({
            "wall area": {"count": 4, "sum": 900.0, "min": 180.0, "max": 270.0},
            "kind": {"count": 1 + 3}
        })
    );
    // PRT's summary of the same reports: a facade 30 × 9 or 20 × 9, two of each.
    assert_eq!(
        stats["prt_reports"],
        serde_json::json!({
            "wall area_n": 4.0, "wall area_sum": 900.0, "wall area_avg": 225.0,
            "wall area_min": 180.0, "wall area_max": 270.0,
            "kind_n": 4.0, "kind_sum": "wall", "kind_avg": "wall",
            "kind_min": "wall", "kind_max": "wall"
        })
    );
    let text = String::from_utf8(output.stdout).unwrap();
    assert!(text.find("\"wall area\"").unwrap() < text.find("\"kind\"").unwrap());
}

#[test]
fn assets_are_read_relative_to_the_grammar() {
    let dir = TempDir::new("assets");
    std::fs::create_dir_all(dir.path("rules/assets")).unwrap();
    let column = dir.path("rules/assets/column.obj");
    ok(&["primitive", "cylinder", "-q", "-o", text(&column)]);
    let grammar = dir.path("rules/columns.cga");
    std::fs::write(
        &grammar,
        "@StartRule\nLot --> extrude(6) split(x) { ~4 : i(\"assets/column.obj\") Column. }*\n",
    )
    .unwrap();
    // Run from another folder: the asset is found beside the grammar.
    let out = dir.path("columns.glb");
    let output = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(["derive", text(&grammar), "--stats", "-q", "-o", text(&out)])
        .current_dir(std::env::temp_dir())
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let stats: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(stats["leaves"], 5);
    // Five cylinders of 32 sides (32 quads, 2 × 30 cap triangles), each stretched to 4 × 6 × 30.
    assert_eq!(stats["triangles"], 5 * (32 * 2 + 2 * 30));
    let info = info_json(&out);
    assert_eq!(info["bounds"]["max"], serde_json::json!([20.0, 6.0, 30.0]));

    std::fs::write(
        &grammar,
        "@StartRule\nLot --> extrude(6) i(\"assets/missing.obj\") Column.\n",
    )
    .unwrap();
    let err = fails(
        &["derive", text(&grammar)],
        1,
        "cannot insert `assets/missing.obj`: cannot read",
    );
    assert!(err.contains("columns.cga:2:22"), "{err}");

    // Stand-ins: a cube filling the scope, or nothing; each missing file is named once.
    let out = dir.path("standin.obj");
    let output = shapegram(&[
        "derive",
        text(&grammar),
        "--missing-assets",
        "cube",
        "--lot",
        "0,0 4,0 4,3 0,3",
        "--lot",
        "10,0 14,0 14,3 10,3",
        "-o",
        text(&out),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let warnings = stderr(&output);
    assert_eq!(
        warnings.matches("inserting a cube instead").count(),
        1,
        "{warnings}"
    );
    let info = info_json(&out);
    assert_eq!(info["volume"], 2.0 * 4.0 * 3.0 * 6.0);
    let output = shapegram(&[
        "derive",
        text(&grammar),
        "--missing-assets",
        "skip",
        "--stats",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let stats: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(stats["leaves"], 0);
}

#[test]
fn assets_are_found_as_cityengine_finds_them_in_a_project() {
    // A CityEngine project: rules in `rules/`, assets in `assets/`, and a file at its root.
    let dir = TempDir::new("project");
    std::fs::create_dir_all(dir.path("city/rules")).unwrap();
    std::fs::create_dir_all(dir.path("city/assets/facade")).unwrap();
    std::fs::create_dir_all(dir.path("city/extra")).unwrap();
    for (kind, file) in [
        ("box", "city/assets/facade/win.obj"),
        ("cylinder", "city/extra/post.obj"),
        ("sphere", "city/rules/ball.obj"),
    ] {
        ok(&["primitive", kind, "-q", "-o", text(&dir.path(file))]);
    }
    let grammar = dir.path("city/rules/street.cga");
    let count = |insert: &str| {
        std::fs::write(
            &grammar,
            format!("@StartRule\nLot --> extrude(6) i(\"{insert}\") X.\n"),
        )
        .unwrap();
        let output = shapegram(&["derive", text(&grammar), "--stats", "-q"]);
        assert!(output.status.success(), "{insert}: {}", stderr(&output));
        let stats: Value = serde_json::from_slice(&output.stdout).unwrap();
        stats["triangles"].as_u64().unwrap()
    };
    // Beside the grammar, then in the project's assets, then in the project; a path starting
    // with `/` names the project in the workspace.
    let (ball, cube, post) = (
        count("ball.obj"),
        count("facade/win.obj"),
        count("extra/post.obj"),
    );
    assert_eq!(cube, 12);
    assert!(
        ball != cube && post != cube && ball != post,
        "{ball} {cube} {post}"
    );
    assert_eq!(count("/city/assets/facade/win.obj"), 12);
    // A file in none of the places is an error naming the place beside the grammar.
    std::fs::write(
        &grammar,
        "@StartRule\nLot --> extrude(6) i(\"facade/door.obj\") X.\n",
    )
    .unwrap();
    let err = fails(
        &["derive", text(&grammar)],
        1,
        "cannot insert `facade/door.obj`",
    );
    assert!(err.contains("rules/facade/door.obj"), "{err}");
}

#[test]
fn syntax_errors_show_the_place_and_end_with_a_count() {
    let dir = TempDir::new("syntax");
    let grammar = dir.path("broken.cga");
    std::fs::write(
        &grammar,
        "attr height = 12\nLot --> extrude(height Mass\nMass --> comp(f) { top : Roof | }\n",
    )
    .unwrap();
    let out = dir.path("broken.glb");
    let output = shapegram(&["derive", text(&grammar), "-o", text(&out)]);
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(err.starts_with("error: "), "{err}");
    assert!(err.contains(&format!("--> {}:2:", text(&grammar))), "{err}");
    assert!(err.contains("2 | Lot --> extrude(height Mass\n"), "{err}");
    assert!(err.contains('^'), "{err}");
    let last = err.lines().last().unwrap();
    assert!(
        last.starts_with("error: ") && last.ends_with(&format!(" in {}", text(&grammar))),
        "{last}"
    );
    let errors = err.lines().filter(|l| l.starts_with("error: ")).count() - 1;
    let expected = if errors == 1 {
        "error: 1 error in ".to_owned()
    } else {
        format!("error: {errors} errors in ")
    };
    assert!(last.starts_with(&expected), "{errors} errors but: {last}");
    assert!(output.stdout.is_empty());
    assert!(!out.exists());
}

#[test]
fn runtime_errors_name_the_problem() {
    let (dir, grammar) = house_dir("runtime");
    // An unknown attribute: the engine's error with its hint.
    let err = fails(
        &["derive", text(&grammar), "-q", "--attr", "heigth=3"],
        1,
        "",
    );
    assert_eq!(
        err,
        "error: the grammar has no attribute `heigth`\n  = hint: did you mean `height`?\n"
    );
    // Not NAME=VALUE: a usage error.
    fails(
        &["derive", text(&grammar), "-q", "--attr", "height"],
        2,
        "invalid value 'height' for '--attr <NAME=VALUE>'",
    );
    fails(
        &["derive", text(&grammar), "-q", "--start", "Flor"],
        1,
        "the grammar has no rule `Flor`",
    );

    let recursive = dir.path("recursive.cga");
    std::fs::write(&recursive, "Lot --> A\nA --> A\n").unwrap();
    let err = fails(&["derive", text(&recursive), "--max-depth", "50"], 1, "");
    assert!(err.lines().next().unwrap().contains("`A`"), "{err}");
    assert!(err.contains("50"), "{err}");
    assert!(err.contains("recursive.cga:2:7"), "{err}");
    assert!(err.contains("= hint: "), "{err}");

    let err = fails_one_line(&["derive", text(&dir.path("missing.cga"))], "cannot read");
    assert!(err.contains("missing.cga"), "{err}");
    fails_one_line(
        &["derive", text(&grammar), "-o", text(&dir.path("x.fbx"))],
        "unknown file format",
    );
}

#[test]
fn derive_help_documents_the_default_lot_and_shows_examples() {
    let help = String::from_utf8(shapegram(&["derive", "--help"]).stdout).unwrap();
    for expected in [
        "20 × 30",
        "x from 0 to 20, z from 0 to 30",
        "Examples:",
        "shapegram derive house.cga -o house.glb",
        "--attr <NAME=VALUE>",
        "[default: 60]",
        "[default: 10000000]",
    ] {
        assert!(help.contains(expected), "missing {expected:?} in:\n{help}");
    }
}

#[test]
fn check_reports_each_file() {
    let (dir, good) = house_dir("check");
    let bad = dir.path("bad.cga");
    std::fs::write(
        &bad,
        "Lot --> extrude(10) Mass\nMass --> split(q) { 1 : A }\n",
    )
    .unwrap();

    let err = ok(&["check", text(&good)]);
    assert!(err.contains("warning: no rule `Ground`"), "{err}");
    assert_eq!(
        err.lines().last().unwrap(),
        format!("ok: {} (6 rules, 1 attribute, 3 warnings)", text(&good))
    );
    let quiet = ok(&["check", "--quiet-warnings", text(&good)]);
    assert_eq!(
        quiet,
        format!("ok: {} (6 rules, 1 attribute, 3 warnings)\n", text(&good))
    );

    let output = shapegram(&["check", "--quiet-warnings", text(&good), text(&bad)]);
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(err.starts_with(&format!("ok: {}", text(&good))), "{err}");
    assert!(err.contains(&format!("--> {}:2:", text(&bad))), "{err}");
    assert!(
        err.ends_with(&format!("error: 1 error in {}\n", text(&bad))),
        "{err}"
    );

    let missing = dir.path("missing.cga");
    let output = shapegram(&["check", text(&missing), text(&good)]);
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(err.starts_with("error: cannot read "), "{err}");
    assert!(err.contains(&format!("ok: {}", text(&good))), "{err}");
}

#[test]
fn l_systems_are_planted_as_assets() {
    // The park example: a lawn, paths and a grid of spots, four with a tree of tree-3d.lsys
    // and two with three shrubs each of the stochastic shrub-3d.lsys.
    let park = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/park.cga");
    let stats = derive_stats(&park, &[]);
    assert_eq!(rule(&stats, "Spot"), 6);
    assert_eq!(rule(&stats, "Shrub"), 6);
    assert_eq!(stats["leaves"], 1 + 6 + 4 + 6);
    // Each plant is far more than a box: thousands of triangles of tubes and leaves.
    assert!(stats["triangles"].as_u64().unwrap() > 10 * 3000, "{stats}");
    // Another seed grows other shrubs (the trees are not stochastic).
    let other = derive_stats(&park, &["--seed", "1"]);
    assert_ne!(other["triangles"], stats["triangles"]);

    // A broken L-system is an error at the insert, with the place in the L-system file.
    let dir = TempDir::new("lsys-asset");
    let grammar = dir.path("garden.cga");
    std::fs::write(&grammar, "Lot --> s(2, 3, 2) i(\"weed.lsys\") Weed.\n").unwrap();
    std::fs::write(dir.path("weed.lsys"), "n: 3\naxiom: F\nF : -> F\n").unwrap();
    let err = fails(&["derive", text(&grammar)], 1, "cannot insert `weed.lsys`:");
    assert!(err.contains("weed.lsys:3:"), "{err}");
}

#[test]
fn the_carved_tower_is_drilled_trimmed_and_set_in_a_punched_lot() {
    let tower = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/carved_tower.cga");
    let stats = derive_stats(&tower, &[]);
    // The operands' shapes count, but only the tower and the ground are leaves.
    assert_eq!(stats["shapes"], 6);
    assert_eq!(stats["leaves"], 2);
    assert_eq!(stats["triangles"], 140);
    let dir = TempDir::new("carved-tower");
    let (first, second) = (dir.path("first.glb"), dir.path("second.glb"));
    ok(&["derive", text(&tower), "-o", text(&first)]);
    ok(&["derive", text(&tower), "-o", text(&second)]);
    assert_eq!(
        std::fs::read(&first).unwrap(),
        std::fs::read(&second).unwrap()
    );
    let info = info_json(&first);
    // The tower is closed; the ground is open along the lot's four edges and its hole's four.
    assert_eq!(info["edges"]["boundary"], 8, "{info}");
    assert_eq!(info["edges"]["non_manifold"], 0, "{info}");
    // The slant takes the top below 24 m: 20 m at the middle, 3.2 m higher at the far end.
    let top = info["bounds"]["max"][1].as_f64().unwrap();
    assert!(top > 21.0 && top < 21.5, "{info}");

    // A bad form is an error at its place.
    let grammar = dir.path("bad.cga");
    std::fs::write(&grammar, "Lot --> extrude(2)\n  union { A. | B. | C. }\n").unwrap();
    let err = fails(&["derive", text(&grammar)], 1, "");
    assert!(err.contains("takes one operand"), "{err}");
    assert!(err.contains("bad.cga:2:9"), "{err}");
}

/// The bounds (min, size) of a model file, from `info --json`.
fn bounds(path: &Path) -> ([f64; 3], [f64; 3]) {
    let info = info_json(path);
    let vector = |key: &str| -> [f64; 3] {
        std::array::from_fn(|k| info["bounds"][key][k].as_f64().expect("a coordinate"))
    };
    (vector("min"), vector("size"))
}

#[test]
fn planted_l_systems_keep_their_proportions_and_interpretation() {
    let dir = TempDir::new("lsys-fit");
    // Drawn alone, the plant's own size; `B` exists only for drawing (a homomorphism rule).
    let plant = dir.path("plant.lsys");
    std::fs::write(
        &plant,
        "n: 2\nangle: 90\nwidth: 0.2\nsides: 4\naxiom: A\nA -> AB\nhomomorphism:\nA -> F\nB -> F[+F]\n",
    )
    .unwrap();
    let alone = dir.path("alone.obj");
    ok(&["lsystem", "-q", text(&plant), "-o", text(&alone)]);
    let (_, own) = bounds(&alone);
    assert!(own[1] > own[0] && own[1] > 2.0, "{own:?}");

    // Planted in a 6 × 5 × 6 scope: scaled by 5 / height, centred in x and z, on the floor.
    let grammar = dir.path("garden.cga");
    std::fs::write(&grammar, "Lot --> s(6, 5, 6) i(\"plant.lsys\") Plant.\n").unwrap();
    let planted = dir.path("planted.obj");
    ok(&["derive", "-q", text(&grammar), "-o", text(&planted)]);
    let (min, size) = bounds(&planted);
    let scale = 5.0 / own[1];
    for k in 0..3 {
        assert!(
            (size[k] - own[k] * scale).abs() < 1e-4,
            "{size:?} vs {own:?}"
        );
    }
    assert!((min[0] - (6.0 - size[0]) / 2.0).abs() < 1e-4, "{min:?}");
    assert!(min[1].abs() < 1e-6, "{min:?}");
}

#[test]
fn stochastic_l_systems_grow_variants_per_shape() {
    let dir = TempDir::new("lsys-variants");
    // One segment or four: tubes of 3 sides have 8 or 26 triangles.
    std::fs::write(
        dir.path("weed.lsys"),
        "n: 1\nsides: 3\naxiom: A\nA (1) -> F\nA (1) -> FFFF\n",
    )
    .unwrap();
    let grammar = dir.path("meadow.cga");
    std::fs::write(
        &grammar,
        "Lot --> split(x) { ~1 : Spot }*\nSpot --> s('1, 2, '1) i(\"weed.lsys\") Weed.\n",
    )
    .unwrap();
    let stats = derive_stats(&grammar, &["--lot", "0,0 16,0 16,2 0,2"]);
    assert_eq!(rule(&stats, "Spot"), 16);
    let triangles = stats["triangles"].as_u64().unwrap();
    let tall = (triangles - 16 * 8) / (26 - 8);
    assert_eq!(16 * 8 + tall * (26 - 8), triangles, "{stats}");
    assert!((1..16).contains(&tall), "{tall} of 16 weeds are tall");
    // The same seed plants the same meadow; the choice follows the run's seed.
    let meadow = |seed: &str| {
        derive_stats(&grammar, &["--lot", "0,0 16,0 16,2 0,2", "--seed", seed])["triangles"]
            .as_u64()
            .unwrap()
    };
    assert_eq!(meadow("0"), triangles);
    assert_ne!(meadow("1"), triangles);
}

#[test]
fn implicit_grammars_are_inserted_as_closed_meshes() {
    // A unit sphere meshed at 8 cells per unit, stretched to 10 × 4 × 8: an ellipsoid of volume
    // 4/3 π · 5 · 2 · 4 (the mesh is within 1 % of it).
    let dir = TempDir::new("cave-asset");
    let grammar = dir.path("rock.cga");
    std::fs::write(&grammar, "Lot --> s(10, 4, 8) i(\"rock.cave\") Rock.\n").unwrap();
    std::fs::write(dir.path("rock.cave"), "lod 8\nadd sphere(1)\n").unwrap();
    let out = dir.path("rock.glb");
    ok(&["derive", text(&grammar), "-o", text(&out)]);
    let info = info_json(&out);
    assert_eq!(info["watertight"], true);
    assert_eq!(info["bounds"]["size"], serde_json::json!([10.0, 4.0, 8.0]));
    assert_relative(num(&info, "volume"), 4.0 / 3.0 * PI * 5.0 * 2.0 * 4.0, 0.01);

    std::fs::write(dir.path("rock.cave"), "lod 8\nadd sphere(-1)\n").unwrap();
    let err = fails(&["derive", text(&grammar)], 1, "cannot insert `rock.cave`:");
    assert!(err.contains("rock.cave:2:"), "{err}");
}

#[test]
fn implicit_solids_are_written_smooth_and_their_detail_is_an_option() {
    let dir = TempDir::new("implicit");
    let grammar = example("outcrop.cga");
    let out = dir.path("outcrop.glb");
    ok(&["derive", text(&grammar), "--group", "-q", "-o", text(&out)]);
    let model = shapegram_export::load(&out).unwrap();
    let rock = model.parts.iter().find(|p| p.name == "outcrop").unwrap();
    assert!(rock.mesh.is_watertight());
    assert_eq!(rock.normals.len(), rock.mesh.vertex_count());
    assert!(
        model
            .parts
            .iter()
            .any(|p| p.name == "Slab" && p.normals.is_empty())
    );

    let coarse = dir.path("coarse.glb");
    ok(&[
        "derive",
        text(&grammar),
        "--group",
        "-q",
        "--implicit-cell",
        "2",
        "-o",
        text(&coarse),
    ]);
    let coarse = shapegram_export::load(&coarse).unwrap();
    let coarse_rock = coarse.parts.iter().find(|p| p.name == "outcrop").unwrap();
    assert!(coarse_rock.mesh.face_count() * 2 < rock.mesh.face_count());

    let err = fails(
        &["derive", text(&grammar), "--implicit-cell", "0"],
        2,
        "invalid value '0' for '--implicit-cell <SIZE>'",
    );
    assert!(err.contains("expected a cell size above 0"), "{err}");
}

#[test]
fn an_implicit_grammar_joins_a_group_and_is_carved() {
    let dir = TempDir::new("implicit-file");
    std::fs::copy(example("grotto.cave"), dir.path("grotto.cave")).unwrap();
    let whole = dir.path("whole.cga");
    std::fs::write(
        &whole,
        "Lot --> extrude(8) implicit(\"grotto.cave\") csg(\"g\", union) Cave.\n",
    )
    .unwrap();
    // The same, with the right half of the scope carved away.
    let half = dir.path("half.cga");
    std::fs::write(
        &half,
        "Lot --> extrude(8) [ implicit(\"grotto.cave\") csg(\"g\", union) Cave. ]\n\
         s('0.5, '1, '1) t('1, 0, 0) csg(\"g\", subtract) Cut.\n",
    )
    .unwrap();
    let lot = "0,0 20,0 20,10 0,10";
    let (a, b) = (dir.path("whole.glb"), dir.path("half.glb"));
    ok(&["derive", text(&whole), "--lot", lot, "-q", "-o", text(&a)]);
    ok(&["derive", text(&half), "--lot", lot, "-q", "-o", text(&b)]);
    let (a, b) = (info_json(&a), info_json(&b));
    assert_eq!(a["watertight"], true, "{a}");
    assert_eq!(b["watertight"], true, "{b}");
    // Stretched to the 20 × 8 × 10 scope; the carved one ends halfway along x.
    assert_relative(a["bounds"]["size"][0].as_f64().unwrap(), 20.0, 0.02);
    assert!(
        b["bounds"]["max"][0].as_f64().unwrap() <= 10.0 + 1e-6,
        "{b}"
    );
    let (va, vb) = (num(&a, "volume"), num(&b, "volume"));
    assert!(vb > 0.2 * va && vb < 0.8 * va, "{vb} of {va}");

    let wrong = dir.path("wrong.cga");
    std::fs::write(&wrong, "Lot --> extrude(8) implicit(\"rock.obj\") R.\n").unwrap();
    let err = fails(
        &["derive", text(&wrong)],
        1,
        "cannot run `rock.obj`: only implicit grammars (.cave files) make implicit solids",
    );
    assert!(err.contains("wrong.cga:1:29"), "{err}");
}

#[test]
fn stats_count_the_skeleton_of_a_kinematic_grammar() {
    let stats = derive_stats(&example("rotating_tower.cga"), &[]);
    let skeleton = &stats["skeleton"];
    assert_eq!(skeleton["skeletons"], 1);
    // The root (lot and lobby), 12 floors and their 12 storeys in one chain, 6 faces for each
    // slab, storey and the lobby (78 + 6), and a section per facade part: 1,200 on the floors
    // and 56 on the lobby.
    assert_eq!(skeleton["sections"], 1 + 12 + 12 + 2 * 72 + 6 + 1200 + 56);
    assert_eq!(skeleton["joints"], 1430);
    // Only the floors turn.
    assert_eq!(skeleton["free_joints"], 12);
    let plain = derive_stats(&example("house.cga"), &[]);
    assert!(plain.get("skeleton").is_none());
}

#[test]
fn a_pose_file_names_joints_and_an_unknown_one_is_an_error() {
    let dir = TempDir::new("pose");
    let pose = dir.path("pose.json");
    std::fs::write(&pose, r#"{"Elbow": {"rotation": [0, 10, 0]}}"#).unwrap();
    let tower = example("rotating_tower.cga");
    let output = shapegram(&["derive", text(&tower), "--pose", text(&pose), "-q"]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {}: the model has no joint named Elbow\n",
            pose.display()
        )
    );
}

#[test]
fn merging_locked_joints_keeps_a_bone_per_free_joint_and_the_posed_model() {
    let dir = TempDir::new("merge-locked");
    let excavator = example("excavator.cga");
    let all = derive_stats(&excavator, &[]);
    assert_eq!(all["skeleton"]["sections"], 35);
    let merged = derive_stats(&excavator, &["--merge-locked"]);
    // The root and the four free joints: upper structure, boom, stick, bucket.
    assert_eq!(merged["skeleton"]["sections"], 5);
    assert_eq!(merged["skeleton"]["free_joints"], 4);
    // The posed model is the same either way.
    let (a, b) = (dir.path("all.stl"), dir.path("merged.stl"));
    ok(&["derive", text(&excavator), "-o", text(&a), "-q"]);
    ok(&[
        "derive",
        text(&excavator),
        "-o",
        text(&b),
        "-q",
        "--merge-locked",
    ]);
    let points = |path: &Path| {
        let model = shapegram_export::load(path).unwrap();
        model.merged_mesh().positions().to_vec()
    };
    let (a, b) = (points(&a), points(&b));
    assert_eq!(a.len(), b.len());
    assert!(a.iter().zip(&b).all(|(p, q)| (*p - *q).length() < 1e-5));
}

/// A wall and a door hinged on its left edge (at x = 1), opened 90° about y, then split into a
/// panel and a lintel rewritten once more; on the 3 × 4 lot [`DOOR_LOT`] every part is 3 high
/// and 4 deep. Its tree: 0 `Lot`, 1 a part, 2 `Wall`, 3 a part, 4 `Door`, 5 a part, 6 `Panel`,
/// 7 a part, 8 `Lintel`, 9 `Beam`.
const DOOR: &str = "attr open = 90
Lot --> extrude(3) split(x) { 1 : Wall. | ~1 : Door }
Door --> joint(0, 0, 0) rotationLimits(y, 0, 100) rotateJoint(0, open, 0)
         split(y) { ~1 : Panel. | 0.5 : Lintel }
Lintel --> color(\"#ff0000\") Beam.
";

const DOOR_LOT: &str = "0,0 3,0 3,4 0,4";

/// Bounds of a file's vertices as stored, rounded to 1e-4 (posed for STL, rest pose for GLB).
fn rounded_bounds(path: &Path) -> [[f64; 3]; 2] {
    let bounds = shapegram_export::load(path).unwrap().bounds().unwrap();
    let round = |v: DVec3| v.to_array().map(|c| (c * 1e4).round() / 1e4 + 0.0);
    [round(bounds.min), round(bounds.max)]
}

#[test]
fn the_derivation_at_a_node_is_written_posed() {
    let dir = TempDir::new("at-node");
    let grammar = dir.path("door.cga");
    std::fs::write(&grammar, DOOR).unwrap();
    let derive = |node: &str, out: &Path, extra: &[&str]| {
        let mut args = vec!["derive", text(&grammar), "--lot", DOOR_LOT];
        args.extend(["--at-node", node, "-o", text(out)]);
        args.extend_from_slice(extra);
        ok(&args)
    };
    // Node 8: the wall and the panel (leaves) and the lintel (rewritten later, as its box),
    // one part each, hanging from the skeleton's root, the door and the door's upper part.
    let glb = dir.path("at8.glb");
    let err = derive("8", &glb, &["--group"]);
    assert!(
        err.starts_with(&format!("derived {} at node 8 of 10: ", text(&glb))),
        "{err}"
    );
    let info = info_json(&glb);
    assert_eq!(info["parts"], 3, "{info}");
    assert_eq!(info["vertices"], 24, "{info}");
    assert_eq!(info["triangles"], 36, "{info}");
    let names: Vec<String> = shapegram_export::load(&glb)
        .unwrap()
        .parts
        .into_iter()
        .map(|p| p.name)
        .collect();
    assert_eq!(names, ["Wall", "Panel", "Lintel"]);
    let json = glb_json(&glb);
    assert_eq!(json["skins"].as_array().unwrap().len(), 1);
    assert_eq!(json["skins"][0]["joints"].as_array().unwrap().len(), 3);
    // The GLB keeps the rest pose for its skin; the STL holds the posed state: the door turned
    // about its hinge reaches 4 m along x and 2 m in front of the lot.
    assert_eq!(rounded_bounds(&glb), [[0.0; 3], [3.0, 3.0, 4.0]]);
    let stl = dir.path("at8.stl");
    derive("8", &stl, &["-q"]);
    assert_eq!(rounded_bounds(&stl), [[0.0, 0.0, -2.0], [5.0, 3.0, 4.0]]);
    // --stats count the state written and name the node.
    let stats = derive_stats(
        &grammar,
        &["--lot", DOOR_LOT, "--at-node", "8", "-o", text(&glb)],
    );
    assert_eq!(stats["at_node"], 8);
    assert_eq!(stats["shapes"], 10);
    assert_eq!(stats["leaves"], 3);
    assert_eq!(stats["faces"], 18);
    // The root: the lot's rectangle.
    let root = dir.path("at0.stl");
    derive("0", &root, &["-q"]);
    assert_eq!(rounded_bounds(&root), [[0.0; 3], [3.0, 0.0, 4.0]]);

    // Past the last node: an error with the node count, and nothing written.
    let missing = dir.path("at10.glb");
    let output = shapegram(&[
        "derive",
        text(&grammar),
        "--lot",
        DOOR_LOT,
        "--at-node",
        "10",
        "-o",
        text(&missing),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        "error: there is no node 10: the derivation tree has 10 nodes (0 to 9)\n"
    );
    assert!(!missing.exists());

    let help = String::from_utf8(shapegram(&["derive", "--help"]).stdout).unwrap();
    assert!(help.contains("--at-node <N>"), "{help}");
    assert!(help.contains("shapegram derive excavator.cga --at-node 40 -o step.glb"));
}

#[test]
fn generations_of_a_kinematic_grammar_are_written_posed() {
    // After three generations the excavator's upper structure has been turned by cabTurn on
    // its axis through the lot's centre (10, 15): turned 90° instead of 0°, each of its
    // vertices goes from (x, y, z) to (10 + z − 15, y, 15 − x + 10); the undercarriage stays.
    let dir = TempDir::new("generations-posed");
    let excavator = example("excavator.cga");
    let points = |turn: &str| {
        let out = dir.path(&format!("turn{turn}.stl"));
        let attr = format!("cabTurn={turn}");
        ok(&[
            "derive",
            text(&excavator),
            "--generations",
            "3",
            "--attr",
            &attr,
            "-o",
            text(&out),
            "-q",
        ]);
        shapegram_export::load(&out)
            .unwrap()
            .merged_mesh()
            .positions()
            .to_vec()
    };
    let (straight, turned) = (points("0"), points("90"));
    assert_eq!(straight.len(), turned.len());
    let mut moved = 0;
    for (a, b) in straight.iter().zip(&turned) {
        if (*a - *b).length() < 1e-5 {
            continue;
        }
        moved += 1;
        let want = DVec3::new(10.0 + a.z - 15.0, a.y, 15.0 - a.x + 10.0);
        assert!((*b - want).length() < 1e-4, "{a} went to {b}, not {want}");
    }
    assert!(moved > 0 && moved < straight.len(), "{moved} moved");
}

/// The JSON chunk of a GLB file.
fn glb_json(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + len]).unwrap()
}

#[test]
fn named_poses_become_animations_named_after_them() {
    let dir = TempDir::new("named-poses");
    let house = example("hinged_house.cga");
    let glb = dir.path("house.glb");
    ok(&["derive", text(&house), "-o", text(&glb), "-q"]);
    let json = glb_json(&glb);
    let animations = json["animations"].as_array().expect("animations");
    let names: Vec<&str> = animations
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["closed", "open"]);
    let joints: Vec<u64> = json["skins"][0]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j.as_u64().unwrap())
        .collect();
    let nodes = json["nodes"].as_array().unwrap();
    let free = joints
        .iter()
        .filter(|&&j| {
            let limits = &nodes[j as usize]["extras"]["shapegram"]["joint"]["rotation_limits_deg"];
            limits
                .as_array()
                .unwrap()
                .iter()
                .any(|r| r[0].as_f64() < r[1].as_f64())
        })
        .count();
    assert!(free > 2, "the door and the window sashes");
    for animation in animations {
        let channels = animation["channels"].as_array().unwrap();
        // A translation and a rotation per free joint, each on a joint node.
        assert_eq!(channels.len(), 2 * free);
        for channel in channels {
            let node = channel["target"]["node"].as_u64().unwrap();
            assert!(joints.contains(&node));
            assert!(matches!(
                channel["target"]["path"].as_str(),
                Some("translation" | "rotation")
            ));
        }
    }
    // The same door in "closed" and "open": shut, then turned about y by 95°.
    let door = joints
        .iter()
        .copied()
        .find(|&j| {
            nodes[j as usize]["name"]
                .as_str()
                .unwrap()
                .starts_with("Door_")
        })
        .unwrap();
    let bytes = std::fs::read(&glb).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let bin = 20 + json_len + 8;
    let accessors = json["accessors"].as_array().unwrap();
    let rotation_of = |animation: &Value| {
        let channel = animation["channels"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["target"]["node"] == door && c["target"]["path"] == "rotation")
            .unwrap();
        let sampler = &animation["samplers"][channel["sampler"].as_u64().unwrap() as usize];
        assert_eq!(sampler["interpolation"], "LINEAR");
        let input = &accessors[sampler["input"].as_u64().unwrap() as usize];
        assert_eq!(input["min"], serde_json::json!([0.0]));
        assert_eq!(input["max"], serde_json::json!([0.0]));
        let output = &accessors[sampler["output"].as_u64().unwrap() as usize];
        assert_eq!(output["type"], "VEC4");
        let view = &json["bufferViews"][output["bufferView"].as_u64().unwrap() as usize];
        let at = bin + view["byteOffset"].as_u64().unwrap() as usize;
        bytes[at..at + 16]
            .chunks_exact(4)
            .map(|b| f64::from(f32::from_le_bytes(b.try_into().unwrap())))
            .collect::<Vec<f64>>()
    };
    let (closed, open) = (rotation_of(&animations[0]), rotation_of(&animations[1]));
    let dot: f64 = closed.iter().zip(&open).map(|(a, b)| a * b).sum();
    assert!(
        (dot.abs() - 47.5f64.to_radians().cos()).abs() < 1e-5,
        "{closed:?} {open:?}"
    );
    // The grammar's named poses are listed by --stats.
    let stats = derive_stats(&house, &[]);
    assert_eq!(stats["named_poses"], serde_json::json!(["closed", "open"]));
    assert!(
        derive_stats(&example("house.cga"), &[])
            .get("named_poses")
            .is_none()
    );
    // Merged, the rig keeps them.
    let merged = dir.path("merged.glb");
    ok(&[
        "derive",
        text(&house),
        "-o",
        text(&merged),
        "-q",
        "--merge-locked",
    ]);
    let json = glb_json(&merged);
    assert_eq!(json["animations"].as_array().unwrap().len(), 2);
}

#[test]
fn a_named_pose_that_changes_the_skeleton_is_an_error_naming_it() {
    let dir = TempDir::new("named-pose-changes");
    let grammar = dir.path("g.cga");
    std::fs::write(
        &grammar,
        "@Pose(\"wide\", 2)\nattr n = 1\n\
         Lot --> extrude(1) rotationLimits(y, -90, 90) A\n\
         A --> case n > 1 : comp(f) { side : B } else : B\n",
    )
    .unwrap();
    let out = dir.path("g.glb");
    let err = fails_one_line(
        &["derive", text(&grammar), "-o", text(&out), "-q"],
        "the pose 'wide' changes the skeleton (",
    );
    assert!(err.contains("sections instead of"), "{err}");
    // Other formats have no animations, so they derive once.
    ok(&[
        "derive",
        text(&grammar),
        "-o",
        text(&dir.path("g.obj")),
        "-q",
    ]);
}

#[test]
fn rule_files_from_cityengine_on_windows_read_as_windows_1252() {
    let dir = TempDir::new("windows-1252");
    let grammar = dir.path("cafe.cga");
    // "Café 5€" in Windows-1252: é is 0xE9 and € is 0x80 (a control character in Latin-1).
    let mut bytes = b"attr sign = \"Caf".to_vec();
    bytes.extend([0xE9]);
    bytes.extend(b" 5");
    bytes.extend([0x80]);
    bytes.extend(b"\"\nLot --> print(sign) extrude(3) Block.\n");
    std::fs::write(&grammar, &bytes).unwrap();
    let output = shapegram(&["derive", text(&grammar)]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    assert!(
        err.starts_with(&format!(
            "warning: {} is not UTF-8 (byte 16): read as Windows-1252, as CityEngine writes rule files on Windows\nprint: Café 5€\n",
            text(&grammar)
        )),
        "{err}"
    );
    let quiet = shapegram(&["derive", text(&grammar), "-q"]);
    assert_eq!(stderr(&quiet), "print: Café 5€\n");
    // A UTF-8 file with a byte-order mark reads without a word.
    let marked = dir.path("marked.cga");
    std::fs::write(&marked, b"\xEF\xBB\xBFLot --> extrude(3) Block.\n").unwrap();
    let err = ok(&["check", text(&marked)]);
    assert_eq!(
        err,
        format!("ok: {} (1 rule, 0 attributes, 0 warnings)\n", text(&marked))
    );
}

#[test]
fn textured_house_embeds_its_textures_and_a_missing_one_is_a_warning() {
    let dir = TempDir::new("textured");
    let out = dir.path("house.glb");
    ok(&[
        "derive",
        text(&example("textured_house.cga")),
        "-o",
        text(&out),
    ]);
    let bytes = std::fs::read(&out).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let images: Vec<&str> = gltf.images().filter_map(|i| i.name()).collect();
    assert_eq!(images, ["brick.png", "tiles.png"]);
    let brick = std::fs::read(example("textures/brick.png")).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let gltf::image::Source::View { view, mime_type } = gltf.images().next().unwrap().source()
    else {
        panic!("the image is embedded");
    };
    assert_eq!(mime_type, "image/png");
    assert_eq!(&blob[view.offset()..view.offset() + view.length()], brick);
    // The brick walls: u runs along the 20 m front and the 30 m sides in 1 m tiles, v up the
    // 6 m walls in 0.5 m ones (12 courses), turned down as glTF has it.
    let (mut low, mut high) = ([f32::MAX; 2], [f32::MIN; 2]);
    let mut textured = 0;
    for primitive in gltf.meshes().flat_map(|m| m.primitives()) {
        let material = primitive.material().pbr_metallic_roughness();
        let Some(info) = material.base_color_texture() else {
            continue;
        };
        if info.texture().source().name() != Some("brick.png") {
            continue;
        }
        textured += 1;
        let reader = primitive.reader(|_| Some(blob));
        for [u, v] in reader.read_tex_coords(0).unwrap().into_f32() {
            low = [low[0].min(u), low[1].min(v)];
            high = [high[0].max(u), high[1].max(v)];
        }
    }
    assert_eq!(textured, 1);
    assert_eq!((low, high), ([0.0, -11.0], [30.0, 1.0]));
    // Materials are named as the grammar names them (`set(material.name, …)`), else by colour.
    let mut materials: Vec<&str> = gltf.materials().filter_map(|m| m.name()).collect();
    materials.sort_unstable();
    assert_eq!(
        materials,
        [
            "#2f5d3a",
            "#3a4f7a",
            "#5a3a22",
            "#6c8ea8",
            "#cccccc",
            "#d6d0c4",
            "brick",
            "roof_tiles"
        ]
    );
    let obj = dir.path("house.obj");
    ok(&[
        "derive",
        text(&example("textured_house.cga")),
        "-o",
        text(&obj),
    ]);
    let mtl = std::fs::read_to_string(dir.path("house.mtl")).unwrap();
    assert!(
        mtl.contains("newmtl brick\n") && mtl.contains("newmtl roof_tiles\n"),
        "{mtl}"
    );

    let grammar = dir.path("missing.cga");
    std::fs::write(
        &grammar,
        "@StartRule\nLot --> setupProjection(0, scope.xz, 2, 2) projectUV(0)\n    texture(\"nowhere.png\") Ground.\n",
    )
    .unwrap();
    // As CityEngine goes on with a placeholder: a warning, once, and the colour alone.
    let output = shapegram(&["derive", text(&grammar), "-o", text(&out)]);
    assert!(output.status.success(), "{}", stderr(&output));
    let warnings = stderr(&output);
    assert_eq!(
        warnings
            .matches("nowhere.png: No such file or directory (os error 2): the shapes keep their colour instead")
            .count(),
        1,
        "{warnings}"
    );
    let gltf = gltf::Gltf::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(gltf.images().count(), 0);
}

#[test]
fn derive_style_picks_a_cga_style() {
    let dir = TempDir::new("derive_style");
    let grammar = dir.path("styles.cga");
    std::fs::write(
        &grammar,
        "attr h = 3\nconst label = \"default\"\n\
         Lot --> print(label + \" \" + h) extrude(h) X.\n\
         style Tall\nattr h = 9\n\
         style Taller extends Tall\nconst label = \"taller\"\n",
    )
    .unwrap();
    let printed = |args: &[&str]| {
        let mut all = vec!["derive", text(&grammar), "-q"];
        all.extend_from_slice(args);
        let output = shapegram(&all);
        assert!(output.status.success(), "{}", stderr(&output));
        stderr(&output)
    };
    assert_eq!(printed(&[]), "print: default 3\n");
    assert_eq!(printed(&["--style", "Tall"]), "print: default 9\n");
    assert_eq!(printed(&["--style", "Taller"]), "print: taller 9\n");
    assert_eq!(printed(&["--style", "Default"]), "print: default 3\n");
    // The chosen style's warning is left out; the other style's stays.
    let warnings = ok(&["derive", text(&grammar), "--style", "Tall"]);
    assert_eq!(
        warnings.matches("derived only when chosen").count(),
        1,
        "{warnings}"
    );
    assert!(warnings.contains("style Taller"), "{warnings}");
    fails(
        &["derive", text(&grammar), "--style", "Wide"],
        2,
        "--style: no style `Wide` (the styles: Default, Tall, Taller)",
    );
}

#[test]
fn reference_functions_read_material_files_beside_the_grammar() {
    // `readMaterial` finds its file as assets are found, and names the file's textures from
    // its folder; `colorRamp` and `getTreeKey` print CityEngine's values.
    let dir = TempDir::new("reference_functions");
    std::fs::create_dir_all(dir.path("materials")).unwrap();
    std::fs::write(
        dir.path("materials/brick.mtl"),
        "newmtl brick\nKd 0.5 0.25 0.125\nmap_Kd brick.png\n",
    )
    .unwrap();
    let grammar = dir.path("functions.cga");
    std::fs::write(
        &grammar,
        "Lot --> print(readMaterial(\"materials/brick.mtl\")) print(colorRamp(\"spectrum\", 0.25))\n\
         \x20       print(getTreeKey) Mass\nMass --> print(getTreeKey) X.\n",
    )
    .unwrap();
    let out = dir.path("functions.obj");
    let err = ok(&["derive", text(&grammar), "-q", "-o", text(&out)]);
    assert_eq!(
        err,
        "print: [[name,brick],[color.r,0.5],[color.g,0.25],[color.b,0.125],\
         [colormap,materials/brick.png]]\nprint: #39A9DF\nprint: 0;\nprint: 0;0;\n"
    );
    assert_eq!(
        ok(&["check", text(&grammar)]),
        format!(
            "ok: {} (2 rules, 0 attributes, 0 warnings)\n",
            text(&grammar)
        )
    );
}

#[test]
fn a_mass_leaves_its_normals_to_the_reader_unless_asked_and_encodes_as_asked() {
    let dir = TempDir::new("glb-flags");
    let grammar = dir.path("mass.cga");
    std::fs::write(&grammar, "Lot --> extrude(10) Mass.\n").unwrap();
    let write = |name: &str, flags: &[&str]| {
        let path = dir.path(name);
        let mut args = vec!["derive", text(&grammar), "-q", "-o", text(&path)];
        args.extend_from_slice(flags);
        ok(&args);
        path
    };
    // (vertices, whether there are normals) of the one primitive.
    let primitive = |path: &Path| {
        let json = glb_json(path);
        let attributes = &json["meshes"][0]["primitives"][0]["attributes"];
        let position = attributes["POSITION"].as_u64().unwrap() as usize;
        let count = json["accessors"][position]["count"].as_u64().unwrap();
        (count, attributes.get("NORMAL").is_some())
    };
    let float = write("float.glb", &[]);
    // The box's 8 corners, shared by its faces.
    assert_eq!(primitive(&float), (8, false));
    assert_eq!(primitive(&write("normals.glb", &["--normals"])), (24, true));
    let quantized = write("quantized.glb", &["--quantize"]);
    let compressed = write("compressed.glb", &["--meshopt"]);
    common::check_glb_encodings(&float, &quantized, &compressed);
    let obj = dir.path("mass.obj");
    let err = ok(&["derive", text(&grammar), "--normals", "-o", text(&obj)]);
    assert!(
        err.starts_with("warning: --quantize, --meshopt and --normals apply to GLB only"),
        "{err}"
    );
}

#[test]
fn an_empty_model_is_warned_about_with_or_without_an_output_file() {
    let dir = TempDir::new("empty-model");
    const WARNING: &str = "warning: the model is empty: no leaf has geometry";
    let grammars = [
        ("nothing", "Lot --> NIL\n", true),
        ("block", "Lot --> extrude(3) Block\n", false),
        // Its only leaf is an implicit solid: the model's faces are the meshed solid's.
        ("solid", "Lot --> extrude(3) implicit(box) Rock\n", false),
    ];
    for (name, source, empty) in grammars {
        let grammar = dir.path(&format!("{name}.cga"));
        std::fs::write(&grammar, source).unwrap();
        let out = dir.path(&format!("{name}.glb"));
        let without_output = ok(&["derive", text(&grammar)]);
        let with_output = ok(&["derive", text(&grammar), "-o", text(&out)]);
        for err in [&without_output, &with_output] {
            assert_eq!(err.contains(WARNING), empty, "{name}: {err}");
        }
    }
}
