//! `shapegram derive --instancing … --metadata`: repeated assets written once and placed many
//! times, leaves' rule, path, attributes and reports in node extras under a node per lot, read
//! back by the project's reader and by a script.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::*;
use serde_json::Value;

/// Fifty crowns (one OBJ asset) on fifty posts (a primitive), in five rows of ten.
const ORCHARD: &str = r##"
version "2024.0"

attr crownH = 2.5

@StartRule
Lot --> color("#8a9a5b") [ Ground. ] split(x) { '0.1 : Row }*

Row  --> split(z) { '0.2 : Spot }*
Spot --> s(2, crownH + 1.5, 2) center(xz) Tree

Tree --> split(y) { 1.5 : s('0.2, '1, '0.2) center(xz) color("#6b4f2a") primitiveCylinder(8) Post.
                  | ~1 : color("#4f7a3a") i("roof.obj") Crown. }
"##;

/// A folder with the orchard grammar and its asset.
fn orchard(test: &str) -> (TempDir, PathBuf) {
    let dir = TempDir::new(test);
    let grammar = dir.path("orchard.cga");
    std::fs::write(&grammar, ORCHARD).unwrap();
    std::fs::copy(example("roof.obj"), dir.path("roof.obj")).unwrap();
    (dir, grammar)
}

/// The file `shapegram derive grammar args… -o out` writes (with `threads` rayon threads).
fn derive(grammar: &Path, out: &Path, args: &[&str], threads: usize) -> Vec<u8> {
    let output = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .arg("derive")
        .arg("-q")
        .arg(grammar)
        .args(args)
        .arg("-o")
        .arg(out)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    std::fs::read(out).unwrap()
}

/// The JSON chunk of a GLB.
fn json_of(glb: &[u8]) -> Value {
    let length = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&glb[20..20 + length]).unwrap()
}

/// The nodes named `name`.
fn named<'a>(json: &'a Value, name: &str) -> Vec<&'a Value> {
    json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|n| n["name"] == name)
        .collect()
}

#[test]
fn fifty_crowns_are_one_mesh_placed_fifty_times() {
    let (dir, grammar) = orchard("fifty");
    let flat = derive(
        &grammar,
        &dir.path("flat.glb"),
        &["--instancing", "none"],
        1,
    );
    let nodes = derive(
        &grammar,
        &dir.path("nodes.glb"),
        &["--instancing", "nodes"],
        1,
    );
    let gpu = derive(&grammar, &dir.path("gpu.glb"), &["--instancing", "gpu"], 1);
    let auto = derive(&grammar, &dir.path("auto.glb"), &[], 1);

    let json = json_of(&nodes);
    let crowns = named(&json, "Crown");
    assert_eq!(crowns.len(), 50);
    assert!(crowns.iter().all(|c| c["mesh"] == crowns[0]["mesh"]));
    assert_eq!(crowns[0]["scale"], serde_json::json!([2.0, 2.5, 2.0]));
    assert_eq!(named(&json, "Post").len(), 50);
    assert_eq!(
        json["meshes"].as_array().unwrap().len(),
        3,
        "the ground, a post and a crown"
    );

    let json = json_of(&gpu);
    let crowns = named(&json, "Crown");
    assert_eq!(crowns.len(), 1);
    let translations =
        &crowns[0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"];
    let accessor = &json["accessors"][translations.as_u64().unwrap() as usize];
    assert_eq!(accessor["count"], 50);

    // Auto picks GPU instancing for both: fifty copies of either cost more flat.
    assert_eq!(auto, gpu);
    assert!(gpu.len() < nodes.len() && nodes.len() < flat.len());
    // Flat copies share their corners now, which narrows the gap (it was five times).
    assert!(
        gpu.len() * 3 < flat.len(),
        "{} bytes instanced, {} flat",
        gpu.len(),
        flat.len()
    );
}

#[test]
fn instanced_files_read_back_as_the_flat_triangles() {
    let (dir, grammar) = orchard("read-back");
    let area_and_count = |glb: &[u8]| {
        let model = shapegram_export::read_glb(glb).unwrap();
        let mesh = model.merged_mesh();
        (mesh.area(), mesh.face_count(), model.bounds().unwrap())
    };
    // With metadata every leaf keeps its own node, so no coplanar rectangles of two leaves
    // are merged: the flat file holds each copy's triangles, as an instanced mesh does.
    let (area, faces, bounds) = area_and_count(&derive(
        &grammar,
        &dir.path("flat.glb"),
        &["--instancing", "none", "--metadata"],
        1,
    ));
    for how in ["nodes", "gpu"] {
        let glb = derive(&grammar, &dir.path("i.glb"), &["--instancing", how], 1);
        let (a, f, b) = area_and_count(&glb);
        assert_eq!(f, faces, "{how}: triangles");
        assert!(
            (a - area).abs() < 1e-6 * area,
            "{how}: area {a} against {area}"
        );
        assert!(b.min.distance(bounds.min) < 1e-5 && b.max.distance(bounds.max) < 1e-5);
    }
    // Without metadata the flat file merges rectangles across leaves: the same surface in
    // fewer triangles.
    let merged = derive(
        &grammar,
        &dir.path("merged.glb"),
        &["--instancing", "none"],
        1,
    );
    let (a, f, _) = area_and_count(&merged);
    assert!(f < faces, "{f} merged triangles against {faces}");
    assert!(
        (a - area).abs() < 1e-6 * area,
        "merged area {a} against {area}"
    );
}

#[test]
fn instancing_and_metadata_are_deterministic_across_threads() {
    let (dir, grammar) = orchard("threads");
    for args in [
        &["--instancing", "gpu", "--metadata"][..],
        &["--instancing", "nodes"],
    ] {
        let one = derive(&grammar, &dir.path("one.glb"), args, 1);
        let two = derive(&grammar, &dir.path("two.glb"), args, 2);
        let again = derive(&grammar, &dir.path("again.glb"), args, 2);
        assert_eq!(one, two, "{args:?}");
        assert_eq!(two, again, "{args:?}");
    }
}

#[test]
fn metadata_is_readable_by_a_script() {
    let (dir, grammar) = orchard("metadata");
    let out = dir.path("meta.glb");
    derive(&grammar, &out, &["--metadata", "--attr", "crownH=3"], 1);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/glb_metadata.py");
    let output = Command::new("python3")
        .arg(script)
        .arg(&out)
        .output()
        .expect("python3 runs tools/glb_metadata.py");
    assert!(output.status.success(), "{}", stderr(&output));
    let rows: Vec<Value> = String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    // The lot, then the ground, fifty posts and fifty crowns: every leaf a node, under the lot.
    assert_eq!(rows.len(), 102);
    assert_eq!(rows[0]["path"], "Lot[0]");
    assert_eq!(rows[0]["leaves"], 101);
    assert_eq!(rows[0]["mesh"], Value::Null);
    assert!(rows[1..].iter().all(|r| r["parent"] == rows[0]["node"]));
    let crowns: Vec<&Value> = rows.iter().filter(|r| r["rule"] == "Crown").collect();
    assert_eq!(crowns.len(), 50);
    for crown in &crowns {
        assert_eq!(crown["attributes"], serde_json::json!({"crownH": 3.0}));
        assert_eq!(crown["goals"], serde_json::json!([]));
        let path = crown["path"].as_str().unwrap();
        assert!(
            path.starts_with("Lot[0]/Lot[") && path.ends_with("/Tree[0]/Tree[1]/Crown[0]"),
            "{path}"
        );
    }
    let mut paths: Vec<&str> = crowns.iter().map(|c| c["path"].as_str().unwrap()).collect();
    paths.sort();
    paths.dedup();
    assert_eq!(paths.len(), 50, "each crown has a path of its own");
    assert_eq!(
        crowns[0]["path"],
        "Lot[0]/Lot[1]/Row[0]/Row[0]/Spot[0]/Tree[0]/Tree[1]/Crown[0]"
    );
    // The crowns still share one mesh, each on its node.
    assert!(crowns.iter().all(|c| c["mesh"] == crowns[0]["mesh"]));
    let ground = rows.iter().find(|r| r["rule"] == "Ground").unwrap();
    assert_eq!(ground["path"], "Lot[0]/Ground[0]");
    // The orchard reports nothing: every node says so.
    assert!(rows.iter().all(|r| r["reports"] == serde_json::json!({})));
}

/// Three floors on each lot, each reporting its area and level; the lot reports its own area,
/// and so does a shape it deletes.
const FLOORS: &str = r#"
version "2024.0"

attr height = 9

@StartRule
Lot --> report("lot.area", geometry.area) Gone extrude(height) Mass
Gone --> report("gone", 1) NIL
Mass --> split(y) { 3 : Floor }*
Floor --> report("floor.area", scope.sx * scope.sz) report("floor.level", split.index) Slab.
"#;

/// A 10 × 20 lot and a 6 × 8 one.
const TWO_LOTS: [&str; 4] = [
    "--lot",
    "0,0 10,0 10,20 0,20",
    "--lot",
    "30,0 36,0 36,8 30,8",
];

/// The rows `tools/glb_metadata.py` prints for `glb`.
fn script_rows(glb: &Path) -> Vec<Value> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/glb_metadata.py");
    let output = Command::new("python3")
        .arg(script)
        .arg(glb)
        .output()
        .expect("python3 runs tools/glb_metadata.py");
    assert!(output.status.success(), "{}", stderr(&output));
    String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect()
}

/// PRT's summary of one key: count, sum, mean, least and greatest.
fn prt(key: &str, [n, sum, avg, min, max]: [f64; 5]) -> Vec<(String, Value)> {
    ["n", "sum", "avg", "min", "max"]
        .into_iter()
        .zip([n, sum, avg, min, max])
        .map(|(suffix, v)| (format!("{key}_{suffix}"), serde_json::json!(v)))
        .collect()
}

#[test]
fn reports_are_summarised_per_lot_and_per_leaf() {
    let dir = TempDir::new("reports");
    let grammar = dir.path("floors.cga");
    std::fs::write(&grammar, FLOORS).unwrap();
    let out = dir.path("floors.glb");
    let mut args = TWO_LOTS.to_vec();
    args.push("--metadata");
    derive(&grammar, &out, &args, 2);
    let rows = script_rows(&out);
    assert_eq!(rows.len(), 2 + 6, "two lots, three slabs each");
    let reports = |entries: Vec<Vec<(String, Value)>>| -> Value {
        Value::Object(entries.into_iter().flatten().collect())
    };
    for (lot, area) in [(0, 200.0), (1, 48.0)] {
        let path = format!("Lot[{lot}]");
        let lot_row = rows.iter().find(|r| r["path"] == path).unwrap();
        assert_eq!(lot_row["name"], path.as_str());
        assert_eq!(lot_row["rule"], "Lot");
        assert_eq!(lot_row["leaves"], 3);
        assert_eq!(lot_row["attributes"], serde_json::json!({"height": 9.0}));
        // Every report made deriving the lot, the deleted shape's too.
        assert_eq!(
            lot_row["reports"],
            reports(vec![
                prt("lot.area", [1.0, area, area, area, area]),
                prt("gone", [1.0; 5]),
                prt("floor.area", [3.0, 3.0 * area, area, area, area]),
                prt("floor.level", [3.0, 3.0, 1.0, 0.0, 2.0]),
            ])
        );
        let slabs: Vec<&Value> = rows
            .iter()
            .filter(|r| r["parent"] == lot_row["node"])
            .collect();
        assert_eq!(slabs.len(), 3);
        for (floor, slab) in slabs.iter().enumerate() {
            assert_eq!(slab["rule"], "Slab");
            assert_eq!(
                slab["path"],
                format!("Lot[{lot}]/Mass[1]/Mass[{floor}]/Floor[0]/Slab[0]").as_str()
            );
            let level = floor as f64;
            // The reports on the way from the lot to the slab: its floor's, and the lot's.
            assert_eq!(
                slab["reports"],
                reports(vec![
                    prt("lot.area", [1.0, area, area, area, area]),
                    prt("floor.area", [1.0, area, area, area, area]),
                    prt("floor.level", [1.0, level, level, level, level]),
                ])
            );
        }
    }
}

#[test]
fn reports_change_no_byte_without_metadata() {
    let dir = TempDir::new("reports-bytes");
    let grammar = dir.path("floors.cga");
    std::fs::write(&grammar, FLOORS).unwrap();
    let silent = dir.path("silent.cga");
    let mut quiet = FLOORS.replace("report(\"lot.area\", geometry.area) ", "");
    quiet = quiet.replace("report(\"gone\", 1) ", "");
    quiet = quiet.replace(
        "report(\"floor.area\", scope.sx * scope.sz) report(\"floor.level\", split.index) ",
        "",
    );
    assert!(!quiet.contains("report"), "{quiet}");
    std::fs::write(&silent, quiet).unwrap();
    let reporting = derive(&grammar, &dir.path("a.glb"), &TWO_LOTS, 1);
    let plain = derive(&silent, &dir.path("b.glb"), &TWO_LOTS, 1);
    assert!(reporting == plain, "reports changed the file");
    // With metadata, the reports are all that differs: the same nodes, the same meshes.
    let mut args = TWO_LOTS.to_vec();
    args.push("--metadata");
    let with = json_of(&derive(&grammar, &dir.path("c.glb"), &args, 1));
    let without = json_of(&derive(&silent, &dir.path("d.glb"), &args, 1));
    assert_eq!(with["nodes"].as_array().unwrap().len(), 9);
    assert_eq!(with["meshes"], without["meshes"]);
    assert_eq!(
        without["nodes"][1]["extras"]["shapegram"]["reports"],
        serde_json::json!({})
    );
}

#[test]
fn skinned_models_are_never_instanced() {
    let dir = TempDir::new("skinned");
    for name in ["excavator.cga", "robot.cga", "clock_tower.cga"] {
        let grammar = example(name);
        let none = derive(
            &grammar,
            &dir.path("none.glb"),
            &["--instancing", "none"],
            1,
        );
        for how in ["nodes", "gpu", "auto"] {
            let glb = derive(&grammar, &dir.path("i.glb"), &["--instancing", how], 1);
            assert!(glb == none, "{name} --instancing {how} differs");
        }
    }
}

#[test]
fn obj_and_stl_stay_flat() {
    let (dir, grammar) = orchard("flat-formats");
    for format in ["obj", "stl"] {
        // The same file name in two folders: an OBJ names its MTL.
        let written = |folder: &str, args: &[&str]| {
            std::fs::create_dir_all(dir.path(folder)).unwrap();
            let out = dir.path(folder).join(format!("orchard.{format}"));
            derive(&grammar, &out, args, 1)
        };
        let plain = written("none", &["--instancing", "none"]);
        let asked = written("gpu", &["--instancing", "gpu", "--metadata"]);
        assert!(plain == asked, "{format}");
    }
}

#[test]
fn grouped_metadata_is_per_part() {
    let (dir, grammar) = orchard("per-part");
    let glb = derive(
        &grammar,
        &dir.path("parts.glb"),
        &["--metadata", "--group", "--instancing", "none"],
        1,
    );
    let json = json_of(&glb);
    let summary = |name: &str| {
        let nodes = named(&json, name);
        assert_eq!(nodes.len(), 1, "{name}");
        nodes[0]["extras"]["shapegram"].clone()
    };
    assert_eq!(
        summary("Crown"),
        serde_json::json!({
            "rule": "Crown",
            "leaves": 50,
            "attributes": {"crownH": 2.5},
            "goals": [],
            "tags": [],
        })
    );
    assert_eq!(summary("Post")["leaves"], 50);
    assert_eq!(summary("Ground")["leaves"], 1);
}

#[test]
fn metadata_where_no_glb_carries_it_is_warned_about() {
    let (dir, grammar) = orchard("metadata_without_a_glb");
    let obj = dir.path("orchard.obj");
    let warnings = [
        (
            Some(&obj),
            format!(
                "warning: --metadata applies to a GLB (-o) and to tiles (--tiles); {} is \
                 written without it",
                obj.display()
            ),
        ),
        (
            None,
            "warning: --metadata applies to a GLB (-o) and to tiles (--tiles); nothing is \
             written"
                .to_owned(),
        ),
    ];
    for (output, warning) in warnings {
        let mut command = Command::new(env!("CARGO_BIN_EXE_shapegram"));
        command.arg("derive").arg(&grammar).arg("--metadata");
        if let Some(output) = output {
            command.arg("-o").arg(output);
        }
        let result = command.output().unwrap();
        assert!(result.status.success(), "{}", stderr(&result));
        assert_eq!(
            stderr(&result).lines().next(),
            Some(warning.as_str()),
            "{}",
            stderr(&result)
        );
    }
    assert!(obj.exists());
}
