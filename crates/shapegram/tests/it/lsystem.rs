//! End-to-end tests of `shapegram lsystem`: every example in examples/*.lsys, words on stdout,
//! SVG and model output, seeds, and the failures users will meet.

use std::path::Path;

use crate::common;

use common::{TempDir, shapegram};
use shapegram_lsystem::{DeriveOptions, LSystem, drawing_to_lines, drawing_to_model, interpret};

/// A path as a command-line argument.
fn arg(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// An example file as a command-line argument.
fn example(name: &str) -> String {
    arg(&common::example(name))
}

/// Runs `shapegram lsystem ARGS`, which must succeed; returns (stdout, stderr).
fn ok(args: &[&str]) -> (String, String) {
    let mut all = vec!["lsystem"];
    all.extend_from_slice(args);
    let output = shapegram(&all);
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(output.status.success(), "{args:?} failed: {stderr}");
    (String::from_utf8(output.stdout).unwrap(), stderr)
}

/// Runs `shapegram lsystem ARGS`, which must fail with exit code 1; returns stderr.
fn fails(args: &[&str]) -> String {
    let mut all = vec!["lsystem"];
    all.extend_from_slice(args);
    let output = shapegram(&all);
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(output.stdout.is_empty());
    stderr
}

#[test]
fn string_prints_the_derived_word() {
    let algae = example("algae.lsys");
    assert_eq!(ok(&[&algae, "--string", "-q"]).0, "abaababaabaab\n");
    assert_eq!(ok(&[&algae, "--string", "-q", "-n", "3"]).0, "abaab\n");
    let parametric = example("parametric.lsys");
    assert_eq!(ok(&[&parametric, "--string", "-q"]).0, "CB(1)A(8,7)\n");
    assert_eq!(
        ok(&[&parametric, "--string", "-q", "-n", "5"]).0,
        "CB(0)B(8)A(1.1428571428571428,0)\n"
    );
    let signal = example("signal.lsys");
    for (n, expected) in ["baaaa", "abaaa", "aabaa", "aaaba", "aaaab"]
        .iter()
        .enumerate()
    {
        let (out, _) = ok(&[&signal, "--string", "-q", "-n", &n.to_string()]);
        assert_eq!(out.trim_end(), *expected);
    }
}

#[test]
fn summary_line_counts_steps_modules_segments_and_polygons() {
    let dir = TempDir::new("summary");
    let svg = arg(&dir.path("island.svg"));
    let (out, err) = ok(&[&example("koch-island.lsys"), "-o", &svg]);
    assert!(out.is_empty());
    assert!(
        err.starts_with(&format!(
            "derived {svg}: 3 steps, 3803 modules, 2048 segments, 0 polygons, "
        )),
        "{err}"
    );
    let (_, quiet) = ok(&[&example("koch-island.lsys"), "-o", &svg, "-q"]);
    assert!(quiet.is_empty());
}

#[test]
fn koch_island_svg_is_one_closed_polyline() {
    let dir = TempDir::new("koch");
    let path = arg(&dir.path("island.svg"));
    ok(&[&example("koch-island.lsys"), "-o", &path]);
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert_eq!(svg.matches("<polyline").count(), 1);
    let points = svg
        .split("points=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    let points: Vec<&str> = points.split(' ').collect();
    assert_eq!(points.len(), 4 * 8usize.pow(3) + 1);
    assert_eq!(points.first(), points.last());
}

#[test]
fn every_example_draws() {
    let dir = TempDir::new("examples");
    let cases = [
        ("koch-island.lsys", 2048, 0),
        ("bush-2d.lsys", 1488, 0),
        ("stochastic-plant.lsys", 935, 0),
        // 2^9 - 1 internodes; the leaves of all but the last step's lateral shoots.
        ("tree-3d.lsys", 511, 247),
        ("algae.lsys", 0, 0),
        ("parametric.lsys", 0, 0),
        ("signal.lsys", 0, 0),
        ("context-plant.lsys", 2501, 0),
        ("bush-3d.lsys", 3891, 1284),
        // Seed 0 of the stochastic shrub.
        ("shrub-3d.lsys", 218, 76),
    ];
    for (name, segments, polygons) in cases {
        let path = arg(&dir.path(&name.replace(".lsys", ".glb")));
        let (_, err) = ok(&[&example(name), "-o", &path]);
        assert!(
            err.contains(&format!(", {segments} segment"))
                && err.contains(&format!(", {polygons} polygon")),
            "{name}: {err}"
        );
        if segments > 0 {
            let model = shapegram_export::load(Path::new(&path)).unwrap();
            assert!(model.parts.iter().all(|p| !p.mesh.is_empty()), "{name}");
        } else {
            assert!(
                err.contains("warning: the drawing is empty"),
                "{name}: {err}"
            );
        }
    }
}

#[test]
fn tree_model_matches_the_library_and_every_format_writes() {
    let dir = TempDir::new("tree");
    let text = std::fs::read_to_string(example("tree-3d.lsys")).unwrap();
    let system = LSystem::parse(&text).unwrap();
    let word = system.derive(&DeriveOptions::default()).unwrap();
    let model = drawing_to_model(&interpret(&system, &word), &system.settings);
    let names: Vec<&str> = model.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["branches-0", "leaves-1"]);
    // Two faces (front and back) per leaf.
    assert_eq!(model.parts[1].mesh.face_count(), 2 * 247);
    assert!(model.parts[0].mesh.is_watertight());
    let triangles: usize = model.parts.iter().map(|p| p.mesh.triangulate().len()).sum();
    for extension in ["glb", "obj", "stl"] {
        let path = arg(&dir.path(&format!("tree.{extension}")));
        ok(&[&example("tree-3d.lsys"), "-o", &path, "-q"]);
        let loaded = shapegram_export::load(Path::new(&path)).unwrap();
        let loaded_triangles: usize = loaded
            .parts
            .iter()
            .map(|p| p.mesh.triangulate().len())
            .sum();
        assert_eq!(loaded_triangles, triangles, "{extension}");
    }
}

#[test]
fn tubes_read_back_smooth_with_a_normal_per_vertex() {
    let dir = TempDir::new("smooth");
    let text = std::fs::read_to_string(example("tree-3d.lsys")).unwrap();
    let system = LSystem::parse(&text).unwrap();
    let word = system.derive(&DeriveOptions::default()).unwrap();
    let model = drawing_to_model(&interpret(&system, &word), &system.settings);
    let vertices = model.parts[0].mesh.vertex_count();
    for extension in ["glb", "obj"] {
        let path = arg(&dir.path(&format!("tree.{extension}")));
        ok(&[&example("tree-3d.lsys"), "-o", &path, "-q"]);
        let loaded = shapegram_export::load(Path::new(&path)).unwrap();
        let branches = &loaded.parts[0];
        assert_eq!(branches.mesh.vertex_count(), vertices, "{extension}");
        assert_eq!(branches.normals.len(), vertices, "{extension}");
        assert!(branches.mesh.is_watertight(), "{extension}");
        // Leaves stay flat.
        assert!(loaded.parts[1].normals.is_empty(), "{extension}");
    }
}

#[test]
fn quantize_and_meshopt_write_the_same_tree_smaller() {
    let dir = TempDir::new("encodings");
    let tree = example("tree-3d.lsys");
    let paths = ["float", "quantized", "compressed"].map(|name| dir.path(&format!("{name}.glb")));
    ok(&[&tree, "-q", "-o", &arg(&paths[0])]);
    ok(&[&tree, "-q", "--quantize", "-o", &arg(&paths[1])]);
    ok(&[&tree, "-q", "--meshopt", "-o", &arg(&paths[2])]);
    common::check_glb_encodings(&paths[0], &paths[1], &paths[2]);
    let size = |k: usize| std::fs::metadata(&paths[k]).unwrap().len();
    assert!(size(1) * 4 < size(0) * 3, "{} against {}", size(1), size(0));
    assert!(size(2) < size(1), "{} against {}", size(2), size(1));
    // The tubes keep their normals; the leaves leave theirs to the reader unless asked.
    let back = shapegram_export::load(&paths[0]).unwrap();
    assert_eq!(
        back.parts[0].normals.len(),
        back.parts[0].mesh.vertex_count()
    );
    let normals = dir.path("normals.glb");
    ok(&[&tree, "-q", "--normals", "-o", &arg(&normals)]);
    // Whether some primitive (the leaves') has no normals.
    let leaves = |path: &Path| {
        let json = common::glb_json_of(&std::fs::read(path).unwrap());
        let meshes = json["meshes"].as_array().unwrap().clone();
        meshes
            .iter()
            .flat_map(|m| m["primitives"].as_array().unwrap().clone())
            .any(|p| p["attributes"].get("NORMAL").is_none())
    };
    assert!(leaves(&paths[0]));
    assert!(!leaves(&normals));
    // Not a GLB: a warning, and the file as usual.
    let svg = arg(&dir.path("tree.svg"));
    let (_, err) = ok(&[&tree, "--meshopt", "-o", &svg]);
    assert!(
        err.starts_with("warning: --quantize, --meshopt and --normals apply to GLB only"),
        "{err}"
    );
}

#[test]
fn lines_write_one_segment_per_drawn_segment() {
    let dir = TempDir::new("lines");
    let text = std::fs::read_to_string(example("bush-3d.lsys")).unwrap();
    let system = LSystem::parse(&text).unwrap();
    let word = system.derive(&DeriveOptions::default()).unwrap();
    let drawing = interpret(&system, &word);
    assert_eq!(drawing.segment_count(), 3891);
    let model = drawing_to_lines(&drawing, &system.settings);
    let points: usize = model.lines.iter().map(|l| l.points.len()).sum();
    let leaf_faces: usize = model.parts.iter().map(|p| p.mesh.face_count()).sum();
    assert_eq!(leaf_faces, 2 * 1284);
    for extension in ["glb", "obj"] {
        let path = arg(&dir.path(&format!("bush.{extension}")));
        let (_, err) = ok(&[&example("bush-3d.lsys"), "--lines", "-o", &path]);
        assert!(err.contains(", 3891 segments, 1284 polygons, "), "{err}");
        let loaded = shapegram_export::load(Path::new(&path)).unwrap();
        let segments: usize = loaded.lines.iter().map(|l| l.segments.len()).sum();
        assert_eq!(segments, 3891, "{extension}");
        let loaded_points: usize = loaded.lines.iter().map(|l| l.points.len()).sum();
        assert_eq!(loaded_points, points, "{extension}");
        let loaded_faces: usize = loaded.parts.iter().map(|p| p.mesh.face_count()).sum();
        // GLB holds the leaves' triangles, OBJ their polygons.
        let want = if extension == "obj" {
            leaf_faces
        } else {
            model.parts.iter().map(|p| p.mesh.triangulate().len()).sum()
        };
        assert_eq!(loaded_faces, want, "{extension}");
        // `info` counts the segments too.
        let info = shapegram(&["info", "--json", &path]);
        let json: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
        assert_eq!(json["segments"], 3891, "{extension}");
    }
    // Without leaves, lines are a small fraction of the tubes' size.
    let (tubes, lines) = (arg(&dir.path("tubes.glb")), arg(&dir.path("lines.glb")));
    ok(&[&example("stochastic-plant.lsys"), "-o", &tubes, "-q"]);
    ok(&[
        &example("stochastic-plant.lsys"),
        "--lines",
        "-o",
        &lines,
        "-q",
    ]);
    let size = |p: &str| std::fs::metadata(p).unwrap().len();
    assert!(
        size(&lines) * 10 < size(&tubes),
        "{} vs {}",
        size(&lines),
        size(&tubes)
    );
}

#[test]
fn seeds_choose_the_plant() {
    let dir = TempDir::new("seeds");
    let plant = example("stochastic-plant.lsys");
    let write = |name: &str, seed: &str| {
        let path = arg(&dir.path(name));
        ok(&[&plant, "-o", &path, "--seed", seed, "-q"]);
        std::fs::read(path).unwrap()
    };
    let a = write("a.svg", "7");
    assert_eq!(a, write("b.svg", "7"));
    assert_ne!(a, write("c.svg", "8"));
    let word = |seed: &str| ok(&[&plant, "--string", "--seed", seed, "-q"]).0;
    assert_eq!(word("3"), word("3"));
    assert_ne!(word("3"), word("4"));
}

#[test]
fn interpretation_rules_change_the_drawing_not_the_word() {
    let dir = TempDir::new("homomorphism");
    let path = arg(&dir.path("h.lsys"));
    std::fs::write(
        &path,
        "n: 2\naxiom: A\nA -> AB\nhomomorphism:\nA -> F[+F]\nB -> F\n",
    )
    .unwrap();
    assert_eq!(ok(&[&path, "--string", "-q"]).0, "ABB\n");
    let svg = arg(&dir.path("h.svg"));
    let (_, err) = ok(&[&path, "-o", &svg]);
    assert!(err.contains(", 4 segments, 0 polygons, "), "{err}");
}

#[test]
fn syntax_errors_show_the_line_and_a_caret() {
    let dir = TempDir::new("syntax");
    let path = arg(&dir.path("bad.lsys"));
    std::fs::write(&path, "n: 2\naxiom: A\nA -> B(1 +)\n").unwrap();
    let err = fails(&[&path, "--string"]);
    assert_eq!(
        err,
        format!(
            "error: {path}:3:11: expected a number, a name or '(', found ')'\n3 | A -> B(1 +)\n  |           ^\n"
        )
    );
}

#[test]
fn limits_and_bad_arguments_are_one_line_errors() {
    let algae = example("algae.lsys");
    let err = fails(&[&algae, "-n", "40", "--max-modules", "1000", "--string"]);
    assert_eq!(
        err,
        format!(
            "error: {algae}: step 15 would make a word of 1,597 modules, over the limit of 1,000 (raise the limit, or derive fewer steps)\n"
        )
    );
    // A word that never grows must not make a huge `-n` run for billions of steps.
    let err = fails(&[&algae, "-n", "4000000000", "--string"]);
    assert_eq!(
        err,
        format!(
            "error: {algae}: 4,000,000,000 derivation steps asked for; at most 10,000 are allowed\n"
        )
    );
    // Tubes have a ring of vertices per point: a long line is refused before it is built.
    let dir = TempDir::new("vertices");
    let line = arg(&dir.path("line.lsys"));
    std::fs::write(&line, "n: 10\naxiom: F\nF -> FF\n").unwrap();
    let glb = arg(&dir.path("line.glb"));
    let err = fails(&[&line, "-o", &glb, "--max-vertices", "8199"]);
    assert_eq!(
        err,
        format!(
            "error: {line}: the model would have up to 8,200 vertices, over the limit of 8,199 (derive fewer steps, use fewer sides, draw lines, or draw an SVG)\n"
        )
    );
    assert!(!dir.path("line.glb").exists());
    ok(&[&line, "-o", &glb, "--max-vertices", "8200"]);
    // As lines, the same stroke is its 1025 points.
    let err = fails(&[&line, "--lines", "-o", &glb, "--max-vertices", "1024"]);
    assert_eq!(
        err,
        format!(
            "error: {line}: the model would have up to 1,025 vertices, over the limit of 1,024 (derive fewer steps or draw an SVG)\n"
        )
    );
    ok(&[&line, "--lines", "-o", &glb, "--max-vertices", "1025"]);
    // STL has no lines: refused before any work.
    let stl = arg(&dir.path("line.stl"));
    let err = fails(&[&line, "--lines", "-o", &stl]);
    assert_eq!(
        err,
        "error: STL holds triangles only; --lines needs a .glb or .obj output\n"
    );
    assert!(!dir.path("line.stl").exists());
    let err = fails(&[&algae, "-o", "out.png"]);
    assert_eq!(
        err,
        "error: unknown file format 'out.png': use .svg, .glb, .obj or .stl\n"
    );
    let err = fails(&["/nonexistent/plant.lsys", "--string"]);
    assert!(
        err.starts_with("error: cannot read /nonexistent/plant.lsys: "),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);
}
