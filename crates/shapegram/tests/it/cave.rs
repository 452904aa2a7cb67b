//! End-to-end tests of `shapegram cave`: the paper's experiment and the examples through the
//! binary, metrics as JSON, byte-identical output, and the errors users will meet.

use std::process::{Command, Output};

use crate::common;

use common::{TempDir, check_glb_encodings, example};
use serde_json::Value;
use shapegram_implicit::text::parse;
use shapegram_implicit::{CaveParams, MeshOptions, Metrics, generate, mesh};

fn shapegram<S: AsRef<std::ffi::OsStr>>(args: &[S], threads: Option<&str>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_shapegram"));
    command.arg("cave").args(args);
    if let Some(n) = threads {
        command.env("RAYON_NUM_THREADS", n);
    }
    command.output().unwrap()
}

/// Runs `shapegram cave ARGS`, which must succeed; returns (stdout, stderr).
fn ok<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> (String, String) {
    let output = shapegram(args, None);
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(output.status.success(), "{stderr}");
    (String::from_utf8(output.stdout).unwrap(), stderr)
}

/// Runs `shapegram cave ARGS`, which must fail with exactly the one line `error: MESSAGE`.
fn fails<S: AsRef<std::ffi::OsStr>>(args: &[S], message: &str) {
    let output = shapegram(args, None);
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr, format!("error: {message}\n"));
    assert!(output.stdout.is_empty());
}

#[test]
fn the_papers_experiment_with_stats() {
    let dir = TempDir::new("paper");
    let out = dir.path("cave.glb");
    let (stdout, stderr) = ok(&["-o".as_ref(), out.as_os_str(), "--stats".as_ref()]);
    // The library's own run of the same parameters.
    let cave = generate(&CaveParams::default()).unwrap();
    let meshing = mesh(cave.solid(), &MeshOptions::with_cell_size(0.1)).unwrap();
    let metrics = Metrics::measure(&meshing, cave.builder.elements());
    let [x, y, z] = meshing.grid.cells;
    assert!(stderr.starts_with(&format!(
        "wrote {}: 12 productions, {} primitives, {} triangles, grid {x} × {y} × {z} (L_D 10), ",
        out.display(),
        metrics.elements,
        metrics.triangles
    )));
    let json: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(json["source"], "generator");
    assert_eq!(json["lod"], 10);
    assert_eq!(json["cell_size"], 0.1);
    assert_eq!(
        (
            json["productions"].as_u64(),
            json["classic"].as_u64(),
            json["morphic"].as_u64()
        ),
        (Some(12), Some(10), Some(2))
    );
    assert_eq!(json["triangles"].as_u64(), Some(metrics.triangles as u64));
    assert_eq!(json["vertices"].as_u64(), Some(metrics.vertices as u64));
    assert_eq!(json["area"].as_f64(), Some(metrics.area));
    assert_eq!(json["volume_mesh"].as_f64(), Some(metrics.mesh_volume));
    assert_eq!(json["volume_voxels"].as_f64(), Some(metrics.voxel_volume));
    assert_eq!(json["watertight"], true);
    let cf = json["convexity_factor"].as_f64().unwrap();
    assert!((40.0..=75.0).contains(&cf), "{cf}");
    // The file read back: the same triangles, closed, smooth-shaded with one normal per shared
    // vertex (the mesher's own vertices, none duplicated per triangle).
    let model = shapegram_export::load(&out).unwrap();
    let part = &model.parts[0];
    assert_eq!(part.mesh.vertex_count(), metrics.vertices);
    assert_eq!(part.normals.len(), metrics.vertices);
    assert!(part.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-6));
    let back = model.merged_mesh().welded(0.0);
    assert_eq!(back.face_count(), metrics.triangles);
    assert!(back.is_watertight());
}

#[test]
fn flags_and_the_example_file_make_the_same_bytes() {
    let dir = TempDir::new("same");
    let (a, b) = (dir.path("flags.glb"), dir.path("file.glb"));
    let flags = [
        "--lod",
        "10",
        "--classic",
        "10",
        "--morphic",
        "2",
        "--direction",
        "+x",
        "--morph",
        "52",
        "--per-shape",
        "3",
        "--seed",
        "1",
        "-q",
        "-o",
    ];
    let mut args: Vec<&std::ffi::OsStr> = flags.iter().map(|s| s.as_ref()).collect();
    args.push(a.as_os_str());
    let (_, stderr) = ok(&args);
    assert_eq!(stderr, "");
    let file = example("cave_paper_experiment.cave");
    ok(&[
        file.as_os_str(),
        "-q".as_ref(),
        "-o".as_ref(),
        b.as_os_str(),
    ]);
    assert!(
        std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
        "the files differ"
    );
}

#[test]
fn output_is_identical_for_any_thread_count() {
    let dir = TempDir::new("threads");
    let run = |threads: &str| {
        let out = dir.path(&format!("t{threads}.glb"));
        let output = shapegram(
            &[
                "--seed".as_ref(),
                "5".as_ref(),
                "--direction".as_ref(),
                "-z".as_ref(),
                "-q".as_ref(),
                "-o".as_ref(),
                out.as_os_str(),
            ],
            Some(threads),
        );
        assert!(output.status.success());
        std::fs::read(out).unwrap()
    };
    let one = run("1");
    assert!(run("2") == one && run("3") == one, "the files differ");
}

#[test]
fn example_files_write_closed_models() {
    let dir = TempDir::new("examples");
    for (name, lod) in [("grotto.cave", 14), ("cave_paper_lod32.cave", 32)] {
        let out = dir.path(&format!("{name}.stl"));
        let (stdout, _) = ok(&[
            example(name).as_os_str(),
            "--stats".as_ref(),
            "-q".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        let json: Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(json["lod"], lod, "{name}");
        assert_eq!(json["watertight"], true, "{name}");
        // The library agrees on the count.
        let program = parse(&std::fs::read_to_string(example(name)).unwrap()).unwrap();
        let run = program.run(None).unwrap();
        let m = mesh(
            run.builder.solid(),
            &MeshOptions::with_cell_size(1.0 / f64::from(lod)),
        )
        .unwrap();
        assert_eq!(
            json["triangles"].as_u64(),
            Some(m.mesh.face_count() as u64),
            "{name}"
        );
        let back = shapegram_export::load(&out)
            .unwrap()
            .merged_mesh()
            .welded(0.0);
        assert_eq!(back.face_count(), m.mesh.face_count());
        assert!(back.is_watertight(), "{name}");
    }
    // --lod overrides the file's level of detail; --seed its seed.
    let (stdout, _) = ok(&[
        example("grotto.cave").as_os_str(),
        "--lod".as_ref(),
        "4".as_ref(),
        "--seed".as_ref(),
        "3".as_ref(),
        "--stats".as_ref(),
        "-q".as_ref(),
    ]);
    let json: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(
        (
            json["lod"].as_u64(),
            json["seed"].as_u64(),
            json["cell_size"].as_f64()
        ),
        (Some(4), Some(3), Some(0.25))
    );
}

#[test]
fn quantize_and_meshopt_write_the_same_cave_smaller() {
    let dir = TempDir::new("encodings");
    let paths = ["float", "quantized", "compressed"].map(|name| dir.path(&format!("{name}.glb")));
    let flags: [&[&str]; 3] = [&[], &["--quantize"], &["--meshopt"]];
    for (path, flags) in paths.iter().zip(flags) {
        let mut args = vec![
            example("grotto.cave").into_os_string(),
            "--lod".into(),
            "6".into(),
        ];
        args.extend(flags.iter().map(Into::into));
        args.extend(["-q".into(), "-o".into(), path.clone().into_os_string()]);
        ok(&args);
    }
    check_glb_encodings(&paths[0], &paths[1], &paths[2]);
    let size = |k: usize| std::fs::metadata(&paths[k]).unwrap().len();
    assert!(size(1) * 4 < size(0) * 3, "{} against {}", size(1), size(0));
    assert!(size(2) < size(1), "{} against {}", size(2), size(1));
    // The cave is smooth: it keeps its normals in every encoding.
    let back = shapegram_export::load(&paths[1]).unwrap();
    assert_eq!(
        back.parts[0].normals.len(),
        back.parts[0].mesh.vertex_count()
    );
}

#[test]
fn without_output_nothing_is_written() {
    let (stdout, stderr) = ok(&["--classic", "3", "--morphic", "0", "--lod", "4"]);
    assert_eq!(stdout, "");
    assert!(
        stderr.starts_with("grew the cave (no output file): 3 productions, "),
        "{stderr}"
    );
}

#[test]
fn bad_input_is_one_line_errors() {
    fails(
        &["--lod", "0"],
        "invalid level of detail 0: expected 1 to 32",
    );
    fails(
        &["--lod", "33"],
        "invalid level of detail 33: expected 1 to 32",
    );
    fails(
        &["--morph", "101"],
        "invalid morphing parameter 101%: expected 0 to 100",
    );
    fails(
        &["--morph", "NaN"],
        "invalid morphing parameter NaN%: expected 0 to 100",
    );
    fails(
        &["--per-shape", "11"],
        "invalid productions per shape 11: expected 0 to 10",
    );
    fails(
        &["--classic", "0", "--morphic", "0"],
        "invalid number of productions 0 (classic + morphic): expected 1 to 1000",
    );
    fails(
        &["--direction", "up"],
        "invalid direction 'up': expected -x, +x, -y, +y, -z, +z or random",
    );
    fails(
        &["-o", "cave.png"],
        "unknown file format 'cave.png': use .glb, .obj or .stl",
    );
    let dir = TempDir::new("bad");
    let file = dir.path("bad.cave");
    std::fs::write(&file, "lod 10\nadd sphere(1)\nadd box(1, 0, 1) at +x\n").unwrap();
    let name = file.display();
    fails(
        &[file.as_os_str()],
        &format!("{name}:3:5: invalid box size y 0: expected a finite number greater than 0"),
    );
    std::fs::write(&file, "add sphere(1) at +w\n").unwrap();
    fails(
        &[file.as_os_str()],
        &format!("{name}:1:18: invalid direction '+w': expected -x, +x, -y, +y, -z, +z or random"),
    );
    std::fs::write(&file, [0x61, 0xff, 0x0a]).unwrap();
    fails(
        &[file.as_os_str()],
        &format!("cannot read {name}: not UTF-8 text (invalid byte at offset 1)"),
    );
    fails(
        &[file.as_os_str(), "--classic".as_ref(), "3".as_ref()],
        "--classic does not apply to a .cave file: write `generate classic N` in the file",
    );
    let missing = dir.path("missing.cave");
    let output = shapegram(&[missing.as_os_str()], None);
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(
        stderr.starts_with(&format!("error: cannot read {}: ", missing.display())),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1);
}
