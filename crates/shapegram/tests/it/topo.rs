//! End-to-end tests of `shapegram topo`: run the shipped topological grammars to models, compile
//! their projects, and the failures users will meet.

use crate::common;

use common::{TempDir, example, shapegram};
use shapegram_topo::{Grammar, GrammarMesh, GrammarState};

/// Runs a command that must succeed, returning its stderr.
fn ok<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> String {
    let output = shapegram(args);
    let err = String::from_utf8(output.stderr).unwrap();
    assert!(output.status.success(), "failed: {err}");
    err
}

/// Runs a command that must fail with exit code 1 and one line `error: <expected>`.
fn fails<S: AsRef<std::ffi::OsStr>>(args: &[S], expected: &str) {
    let output = shapegram(args);
    let err = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(1), "stderr: {err}");
    assert_eq!(err, format!("error: {expected}\n"));
    assert!(output.stdout.is_empty());
}

/// The triangles the library makes for the same run, for comparison with the CLI's file.
fn expected_triangles(grammar: &str, symbol: &str, seed: u64, generations: u32) -> usize {
    let text = std::fs::read_to_string(example(grammar)).unwrap();
    let grammar = Grammar::from_json(&text).unwrap();
    let mut state = GrammarState::new(&grammar, symbol)
        .unwrap()
        .with_seed(seed)
        .with_generations(generations);
    state.generate_all().unwrap();
    GrammarMesh::new(&state).triangle_count()
}

#[test]
fn the_house_example_runs_to_a_glb_as_in_the_issue() {
    let dir = TempDir::new("house");
    let out = dir.path("house.glb");
    let grammar = example("topo_house.grammar");
    let err = ok(&[
        "topo".as_ref(),
        grammar.as_os_str(),
        "--symbol".as_ref(),
        "House".as_ref(),
        "--generations".as_ref(),
        "8".as_ref(),
        "--seed".as_ref(),
        "0x2a".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let triangles = expected_triangles("topo_house.grammar", "House", 0x2a, 8);
    assert_eq!(
        err,
        format!(
            "wrote {}: 8 generations from House: 220 shapes (220 terminal), {triangles} \
             triangles\n",
            out.display()
        )
    );
    let model = shapegram_export::load(&out).unwrap();
    let read: usize = model.parts.iter().map(|p| p.mesh.face_count()).sum();
    assert_eq!(read, triangles);
    // Same seed, same bytes.
    let again = dir.path("again.glb");
    ok(&[
        "topo".as_ref(),
        grammar.as_os_str(),
        "--symbol".as_ref(),
        "House".as_ref(),
        "--seed".as_ref(),
        "42".as_ref(),
        "-q".as_ref(),
        "-o".as_ref(),
        again.as_os_str(),
    ]);
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&again).unwrap());
}

#[test]
fn projects_run_directly_and_write_stl_and_obj() {
    let dir = TempDir::new("formats");
    let project = example("topo_pyramid.sgproj.json");
    for name in ["pyramid.stl", "pyramid.obj"] {
        let out = dir.path(name);
        let err = ok(&[
            "topo".as_ref(),
            project.as_os_str(),
            "--generations".as_ref(),
            "4".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        assert!(
            err.ends_with("4 generations from Pyramid: 9 shapes (8 terminal), 92 triangles\n"),
            "{err}"
        );
        let model = shapegram_export::load(&out).unwrap();
        let triangles: usize = model.parts.iter().map(|p| p.mesh.face_count()).sum();
        assert_eq!(triangles, 92);
    }
    assert_eq!(
        expected_triangles("topo_pyramid.grammar", "Pyramid", 0, 4),
        92
    );
}

#[test]
fn compiling_a_project_reproduces_the_shipped_grammar() {
    let dir = TempDir::new("compile");
    let out = dir.path("house.grammar");
    let project = example("topo_house.sgproj.json");
    let err = ok(&[
        "topo".as_ref(),
        "compile".as_ref(),
        project.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(
        err,
        format!(
            "wrote {}: 22 symbols (15 non-terminal), 18 rules\n",
            out.display()
        )
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        std::fs::read(example("topo_house.grammar")).unwrap()
    );
}

#[test]
fn compiling_never_overwrites_the_project() {
    let dir = TempDir::new("overwrite");
    let project = dir.path("steps.sgproj.json");
    std::fs::copy(example("topo_spiral_steps.sgproj.json"), &project).unwrap();
    let before = std::fs::read(&project).unwrap();
    fails(
        &[
            "topo".as_ref(),
            "compile".as_ref(),
            project.as_os_str(),
            "-o".as_ref(),
            project.as_os_str(),
        ],
        &format!(
            "refusing to overwrite the project {} with its grammar: choose another -o",
            project.display()
        ),
    );
    assert_eq!(std::fs::read(&project).unwrap(), before);
}

#[test]
fn bad_inputs_fail_with_one_located_line() {
    let dir = TempDir::new("bad");
    let broken = dir.path("broken.grammar");
    std::fs::write(
        &broken,
        "{\n  \"format\": \"shapegram-topo-grammar\",\n  oops\n}",
    )
    .unwrap();
    fails(
        &["topo".as_ref(), broken.as_os_str()],
        &format!("{}:3:3: key must be a string", broken.display()),
    );
    let edited = dir.path("edited.grammar");
    let text = std::fs::read_to_string(example("topo_spiral_steps.grammar")).unwrap();
    std::fs::write(&edited, text.replace("\"weight\": 1.0", "\"weight\": -1.0")).unwrap();
    fails(
        &["topo".as_ref(), edited.as_os_str()],
        &format!(
            "{}: rules[0].weight: -1 is not a positive number",
            edited.display()
        ),
    );
    let grammar = example("topo_spiral_steps.grammar");
    fails(
        &[
            "topo".as_ref(),
            grammar.as_os_str(),
            "--symbol".as_ref(),
            "B".as_ref(),
        ],
        "the grammar has no symbol 'B' (symbols: A, Step)",
    );
    let missing = dir.path("missing.grammar");
    let output = shapegram(&["topo".as_ref(), missing.as_os_str()]);
    let err = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(
        err.starts_with(&format!("error: cannot read {}: ", missing.display())),
        "{err}"
    );
    fails(
        &["topo"],
        "missing GRAMMAR: `shapegram topo GRAMMAR.grammar -o model.glb` or `shapegram topo \
         compile PROJECT -o GRAMMAR.grammar`",
    );
}

#[test]
fn runaway_grammars_stop_at_the_shape_limit() {
    let grammar = example("topo_house.grammar");
    fails(
        &[
            "topo".as_ref(),
            grammar.as_os_str(),
            "--max-shapes".as_ref(),
            "50".as_ref(),
        ],
        "generation 4 would make more than 50 shapes, most of them 'WindowColumn' (symbols \
         that keep producing themselves never stop: use fewer generations or a higher shape \
         limit)",
    );
}

#[test]
fn seeds_are_checked_by_the_parser() {
    let grammar = example("topo_house.grammar");
    let output = shapegram(&[
        "topo".as_ref(),
        grammar.as_os_str(),
        "--seed".as_ref(),
        "0x1000000000000".as_ref(),
    ]);
    assert_eq!(output.status.code(), Some(2));
    let err = String::from_utf8(output.stderr).unwrap();
    assert!(
        err.contains("seeds are 48-bit: at most 0xffffffffffff"),
        "{err}"
    );
}

#[test]
fn the_brick_house_reaches_glb_with_its_textures_and_tiled_uvs() {
    let dir = TempDir::new("brick");
    let out = dir.path("brick.glb");
    let grammar = example("topo_brick_house.grammar");
    let err = ok(&[
        "topo".as_ref(),
        grammar.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(
        err,
        format!(
            "wrote {}: 3 generations from House: 44 shapes (44 terminal), 520 triangles\n",
            out.display()
        )
    );
    let model = shapegram_export::load(&out).unwrap();
    let textures_dir = example("textures");
    let mut textured_triangles = 0;
    for (name, tile) in [("brick.png", [1.2, 0.6]), ("tiles.png", [0.8, 0.8])] {
        let image = std::fs::read(textures_dir.join(name)).unwrap();
        let parts: Vec<_> = model
            .parts
            .iter()
            .filter(|p| p.texture.as_ref().is_some_and(|t| t.path.ends_with(name)))
            .collect();
        assert!(!parts.is_empty(), "{name}");
        for part in parts {
            let texture = part.texture.as_ref().unwrap();
            assert_eq!(texture.image.as_deref(), Some(&image[..]), "{name}");
            assert_eq!(part.uvs.len(), part.mesh.vertex_count());
            // Every corner's uv is its position along the face's axes in tiles.
            for face in part.mesh.faces() {
                let [a, b, c] = [face[0], face[1], face[2]].map(|i| part.mesh.position(i));
                let normal = (b - a).cross(c - a).normalize();
                for &i in face {
                    let expected = shapegram_topo::planar_uv(
                        part.mesh.position(i),
                        normal,
                        shapegram_geom::DVec2::from_array(tile),
                    );
                    assert!((part.uvs[i as usize] - expected).abs().max_element() < 1e-4);
                }
                textured_triangles += 1;
            }
        }
    }
    let text = std::fs::read_to_string(&grammar).unwrap();
    let grammar = Grammar::from_json(&text).unwrap();
    let mut state = GrammarState::new(&grammar, "House").unwrap();
    state.generations = 8;
    state.generate_all().unwrap();
    let mesh = GrammarMesh::new(&state);
    let expected: usize = mesh
        .parts
        .iter()
        .filter(|p| {
            p.material
                .is_some_and(|m| mesh.materials[m as usize].texture.is_some())
        })
        .map(|p| p.triangles.len())
        .sum();
    assert_eq!(textured_triangles, expected);
}

#[test]
fn a_missing_texture_is_a_warning_and_its_faces_keep_their_colour() {
    let dir = TempDir::new("brick-without-textures");
    let grammar = dir.path("brick.grammar");
    std::fs::copy(example("topo_brick_house.grammar"), &grammar).unwrap();
    let out = dir.path("brick.glb");
    let err = ok(&[
        "topo".as_ref(),
        grammar.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let missing = |name: &str| {
        format!(
            "warning: {}: cannot read the texture {}: No such file or directory (os error 2) \
             (its faces are drawn in their colour)\n",
            grammar.display(),
            dir.path("textures").join(name).display()
        )
    };
    assert!(
        err.starts_with(&(missing("brick.png") + &missing("tiles.png"))),
        "{err}"
    );
    let model = shapegram_export::load(&out).unwrap();
    assert!(model.parts.iter().all(|p| p.texture.is_none()));
    assert!(
        model
            .parts
            .iter()
            .any(|p| p.material.as_deref() == Some("RoofTiles"))
    );
}

/// The corners of the parts of one material: each position with its uv as glTF has it (v down),
/// and the names of the parts' images.
type TexturedCorners = (Vec<([f32; 3], [f32; 2])>, Vec<String>);

/// Corners and image names sorted, each once (a GLB may share a corner between faces).
fn sorted_corners(
    mut corners: Vec<([f32; 3], [f32; 2])>,
    mut paths: Vec<String>,
) -> TexturedCorners {
    corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
    corners.dedup();
    paths.sort();
    paths.dedup();
    (corners, paths)
}

#[test]
fn hosts_get_the_uvs_and_images_the_brick_houses_glb_has() {
    let dir = TempDir::new("brick-runtime");
    let out = dir.path("brick.glb");
    let grammar = example("topo_brick_house.grammar");
    ok(&[
        "topo".as_ref(),
        grammar.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let glb = shapegram_export::read_glb(&std::fs::read(&out).unwrap()).unwrap();
    let text = std::fs::read_to_string(&grammar).unwrap();
    let runtime =
        shapegram_runtime::Grammar::load(&grammar.display().to_string(), &text, None).unwrap();
    let derived = runtime
        .derive(&shapegram_runtime::Settings::default())
        .unwrap();
    let mut buffers = shapegram_export::Buffers::default();
    derived.fill(&mut buffers);
    // Distinct corners: the walls' and gables' bricks, the four roof planes' tiles.
    for (material, count) in [("Brick", 111), ("RoofTiles", 16)] {
        let (mut corners, mut paths) = (Vec::new(), Vec::new());
        for part in glb
            .parts
            .iter()
            .filter(|p| p.material.as_deref() == Some(material))
        {
            let texture = part.texture.as_ref().expect("a textured part");
            paths.push(texture.path.to_string());
            for (i, uv) in part.uvs.iter().enumerate() {
                let p = part.mesh.position(i as u32).as_vec3().to_array();
                corners.push((p, [uv.x as f32, (1.0 - uv.y) as f32]));
            }
        }
        let written = sorted_corners(corners, paths);
        let (mut corners, mut paths) = (Vec::new(), Vec::new());
        for part in &buffers.parts {
            if derived.part_material(part.part) != Some(material) {
                continue;
            }
            let texture = part.texture.expect("a textured part") as usize;
            // The GLB names an image by its file's name alone.
            let path = &buffers.textures[texture].path;
            paths.push(path.rsplit('/').next().unwrap().to_owned());
            for i in part.first_vertex..part.first_vertex + part.vertex_count {
                corners.push((buffers.positions[i as usize], buffers.uvs[i as usize]));
            }
        }
        let hosts = sorted_corners(corners, paths);
        assert_eq!(hosts.0.len(), count, "{material}");
        assert_eq!(hosts, written, "{material}");
    }
}
