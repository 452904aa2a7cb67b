//! End to end: `shapegram studio` as a child process on a free port, over real HTTP, with the
//! engine of `shapegram derive`: the address on the first line, models and counts as `derive`
//! makes them, diagnostics with their lines and columns, assets found beside the file.

use std::ffi::OsStr;

use crate::common;
use crate::studio_child::{self, Studio};

use common::{TempDir, example, shapegram, stderr};
use serde_json::{Value, json};

fn start(files: &[&std::path::Path]) -> Studio {
    let args: Vec<&OsStr> = files.iter().map(|f| f.as_os_str()).collect();
    studio_child::start(&args)
}

/// A request from the studio's page: the status and JSON body.
fn request(studio: &Studio, method: &str, path: &str, body: Option<Value>) -> (u16, Value) {
    studio_child::send(&studio.addr, method, path, body.as_ref())
}

fn derive(studio: &Studio, path: &std::path::Path, text: &str) -> Value {
    let (status, answer) = request(
        studio,
        "POST",
        "/api/derive",
        Some(json!({"path": path, "text": text})),
    );
    assert_eq!(status, 200, "{answer}");
    answer
}

#[test]
fn the_studio_derives_text_as_derive_does_the_file() {
    let dir = TempDir::new("studio-derive");
    let house = dir.path("house.cga");
    std::fs::copy(example("house.cga"), &house).unwrap();
    let house = std::fs::canonicalize(&house).unwrap();
    let studio = start(&[&house]);
    let text = std::fs::read_to_string(&house).unwrap();
    let answer = derive(&studio, &house, &text);
    let stats = shapegram(&["derive", "-q", "--stats", house.to_str().unwrap()]);
    let stats: Value = serde_json::from_slice(&stats.stdout).unwrap();
    assert_eq!(
        (&answer["ok"], &answer["shapes"], &answer["leaves"]),
        (&json!(true), &stats["shapes"], &stats["leaves"])
    );
    assert_eq!(answer["diagnostics"], json!([]));
    // base64 of the GLB header's first six bytes: `glTF`, then version 2 (as u32 LE).
    assert!(answer["glb"].as_str().unwrap().starts_with("Z2xURgIA"));
    // The text, not the file: a third storey adds shapes; the file stays as it was.
    let taller = derive(
        &studio,
        &house,
        &text.replace("attr storeys    = 2", "attr storeys    = 3"),
    );
    assert!(taller["shapes"].as_u64() > answer["shapes"].as_u64());
    assert_eq!(std::fs::read_to_string(&house).unwrap(), text);
}

#[test]
fn diagnostics_come_with_lines_and_columns() {
    let dir = TempDir::new("studio-diagnostics");
    let file = dir.path("lot.cga");
    std::fs::write(&file, "Lot --> X.\n").unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&[&file]);
    // A parse error.
    let answer = derive(&studio, &file, "// first\nLot --> extrude(3 Foo) X.\n");
    assert_eq!(answer["ok"], false);
    assert_eq!(answer["glb"], Value::Null);
    assert_eq!(
        answer["diagnostics"],
        json!([{
            "severity": "error",
            "message": "expected `,` or `)` in the argument list, found `Foo`",
            "label": "expected `,` or `)` here",
            "hints": [],
            "line": 2, "column": 19, "end_line": 2, "end_column": 22,
        }])
    );
    // An error while deriving, at its operation: an asset that is not beside the file.
    let answer = derive(&studio, &file, "Lot -->\n    i(\"missing.obj\")\n");
    let diagnostics = answer["diagnostics"].as_array().unwrap();
    assert_eq!(diagnostics.len(), 1, "{answer}");
    let missing = &diagnostics[0];
    assert_eq!(
        (
            &missing["severity"],
            &missing["line"],
            &missing["column"],
            &missing["end_line"],
            &missing["end_column"]
        ),
        (&json!("error"), &json!(2), &json!(7), &json!(2), &json!(20))
    );
    assert!(
        missing["message"]
            .as_str()
            .unwrap()
            .starts_with("cannot insert `missing.obj`: cannot read "),
        "{missing}"
    );
    // Once it is there, it is found beside the file.
    std::fs::copy(example("roof.obj"), dir.path("missing.obj")).unwrap();
    let answer = derive(&studio, &file, "Lot -->\n    i(\"missing.obj\")\n");
    assert_eq!(
        (&answer["ok"], &answer["diagnostics"]),
        (&json!(true), &json!([]))
    );
}

#[test]
fn the_studio_listens_on_loopback_only() {
    let output = shapegram(&[
        "studio",
        "--listen",
        "0.0.0.0:0",
        example("house.cga").to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        "error: --listen 0.0.0.0:0: the studio listens on a loopback address only (127.0.0.1), since it writes your files\n"
    );
    let dir = TempDir::new("studio-not-grammar");
    let notes = dir.path("notes.txt");
    std::fs::write(&notes, "not a grammar").unwrap();
    let output = shapegram(&["studio", "--listen", "127.0.0.1:0", notes.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {} is not a grammar file (.cga, .mul, .sgl, .goal, .lsys, .cave, .grammar), a rule package (.rpk) or a topological grammar project (.sgproj.json)\n",
            notes.display()
        )
    );
}

/// The model or drawing of an answer, decoded.
fn glb_of(answer: &Value) -> Vec<u8> {
    use base64::Engine as _;
    let glb = answer["glb"]
        .as_str()
        .unwrap_or_else(|| panic!("no GLB: {answer}"));
    base64::engine::general_purpose::STANDARD
        .decode(glb)
        .unwrap()
}

/// Every kind of grammar derives in the studio as its command derives the file: a 2D L-system
/// as the SVG of `shapegram lsystem -o x.svg`, a 3D one, a cave and topological grammars (one
/// with textures) as the GLB their commands write (byte for byte), and a goal grammar with its folder as library
/// as `derive --library FOLDER` counts it.
#[test]
fn every_kind_derives_as_its_command_does() {
    let dir = TempDir::new("studio-kinds");
    let copy = |name: &str, to: &str| {
        let path = dir.path(to);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::copy(example(name), &path).unwrap();
        std::fs::canonicalize(&path).unwrap()
    };
    let island = copy("koch-island.lsys", "koch-island.lsys");
    let tree = copy("tree-3d.lsys", "tree-3d.lsys");
    let grotto = copy("grotto.cave", "grotto.cave");
    let house = copy("topo_house.grammar", "topo_house.grammar");
    let brick_house = copy("topo_brick_house.grammar", "topo_brick_house.grammar");
    for image in ["brick.png", "tiles.png"] {
        copy(&format!("textures/{image}"), &format!("textures/{image}"));
    }
    let chair = copy("chairs/chair.goal", "chairs/chair.goal");
    for material in ["fabric", "metal", "wood"] {
        copy(
            &format!("chairs/materials/{material}.goal"),
            &format!("chairs/materials/{material}.goal"),
        );
    }
    let studio = start(&[&island, &chair]);
    let text = |path: &std::path::Path| std::fs::read_to_string(path).unwrap();
    let out = |name: &str| dir.path(name).to_str().unwrap().to_owned();

    // 2D: the SVG `shapegram lsystem` writes, no GLB.
    let answer = derive(&studio, &island, &text(&island));
    shapegram(&[
        "lsystem",
        "-q",
        island.to_str().unwrap(),
        "-o",
        &out("island.svg"),
    ]);
    assert_eq!(
        (&answer["ok"], &answer["glb"], &answer["diagnostics"]),
        (&json!(true), &Value::Null, &json!([]))
    );
    assert_eq!(
        answer["svg"].as_str().unwrap(),
        std::fs::read_to_string(out("island.svg")).unwrap()
    );
    assert_eq!(
        answer["summary"],
        json!("3 steps, 3803 modules, 2048 segments, 0 polygons")
    );

    // 3D, a cave, a topological grammar: their commands' GLB files.
    for (path, command) in [
        (&tree, vec!["lsystem", "-q"]),
        (&grotto, vec!["cave", "-q"]),
        (&house, vec!["topo", "-q"]),
        (&brick_house, vec!["topo", "-q"]),
    ] {
        let answer = derive(&studio, path, &text(path));
        assert_eq!(answer["svg"], Value::Null, "{}", path.display());
        let written = out("written.glb");
        let mut args = command.clone();
        args.extend([path.to_str().unwrap(), "-o", &written]);
        shapegram(&args);
        let file = std::fs::read(&written).unwrap();
        assert!(
            glb_of(&answer) == file,
            "{} differs from {command:?}",
            path.display()
        );
        assert_eq!(answer["glb_bytes"], json!(file.len()));
    }
    // The brick house's textures, read beside it, are in its GLB.
    let answer = derive(&studio, &brick_house, &text(&brick_house));
    let images = shapegram_export::read_glb(&glb_of(&answer))
        .unwrap()
        .parts
        .iter()
        .filter_map(|p| Some(p.texture.as_ref()?.image.as_ref()?.len()))
        .collect::<std::collections::BTreeSet<_>>();
    let sizes = ["brick.png", "tiles.png"].map(|image| {
        std::fs::metadata(dir.path("textures").join(image))
            .unwrap()
            .len() as usize
    });
    assert_eq!(images, sizes.into());

    // A goal grammar with the goal grammars of its folder (and subfolders) as its library.
    let answer = derive(&studio, &chair, &text(&chair));
    let stats = shapegram(&[
        "derive",
        "-q",
        "--stats",
        chair.to_str().unwrap(),
        "--library",
        chair.parent().unwrap().to_str().unwrap(),
    ]);
    let stats: Value = serde_json::from_slice(&stats.stdout).unwrap();
    assert_eq!(
        (&answer["ok"], &answer["shapes"], &answer["leaves"]),
        (&json!(true), &stats["shapes"], &stats["leaves"])
    );
    assert!(
        answer["summary"]
            .as_str()
            .unwrap()
            .ends_with("library of 3 files")
    );
}

/// Downloads of every kind are the files its command writes: OBJ (with its MTL) and STL of a 2D
/// L-system (its tubes, not the SVG shown), a 3D one, a cave, a topological grammar and a goal
/// grammar with its folder as library, byte for byte.
#[test]
fn every_kind_exports_what_its_command_writes() {
    use base64::Engine as _;
    let dir = TempDir::new("studio-kind-exports");
    let copy = |name: &str| {
        let path = dir.path(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::copy(example(name), &path).unwrap();
        std::fs::canonicalize(&path).unwrap()
    };
    let grammars = [
        (copy("koch-island.lsys"), vec!["lsystem"]),
        (copy("tree-3d.lsys"), vec!["lsystem"]),
        (copy("grotto.cave"), vec!["cave"]),
        (copy("topo_house.grammar"), vec!["topo"]),
        (copy("chairs/chair.goal"), vec!["derive", "--library"]),
    ];
    for material in ["fabric", "metal", "wood"] {
        copy(&format!("chairs/materials/{material}.goal"));
    }
    let studio = start(&[&grammars[0].0, &grammars[4].0]);
    let cli = dir.path("cli");
    std::fs::create_dir(&cli).unwrap();
    for (path, command) in &grammars {
        let stem = path.file_stem().unwrap().to_str().unwrap();
        for (format, names) in [
            ("stl", vec![format!("{stem}.stl")]),
            ("obj", vec![format!("{stem}.obj"), format!("{stem}.mtl")]),
        ] {
            let written = cli.join(&names[0]);
            let mut args = vec![command[0], "-q", path.to_str().unwrap()];
            if command.len() > 1 {
                args.extend([command[1], path.parent().unwrap().to_str().unwrap()]);
            }
            args.extend(["-o", written.to_str().unwrap()]);
            shapegram(&args);
            let text = std::fs::read_to_string(path).unwrap();
            let (status, answer) = request(
                &studio,
                "POST",
                "/api/export",
                Some(json!({"path": path, "text": text, "format": format})),
            );
            assert_eq!(status, 200, "{stem}.{format}: {answer}");
            let files = answer["files"].as_array().unwrap();
            let got: Vec<&str> = files.iter().map(|f| f["name"].as_str().unwrap()).collect();
            assert_eq!(got, names);
            for f in files {
                let bytes = base64::engine::general_purpose::STANDARD
                    .decode(f["data"].as_str().unwrap())
                    .unwrap();
                let name = f["name"].as_str().unwrap();
                assert!(
                    bytes == std::fs::read(cli.join(name)).unwrap(),
                    "{name} differs from `shapegram {}`",
                    command[0]
                );
            }
        }
    }
}

/// Mistakes in every kind come back at their line and column, as the parsers report them.
#[test]
fn mistakes_in_every_kind_have_lines_and_columns() {
    let dir = TempDir::new("studio-kind-errors");
    let mut files = Vec::new();
    for name in ["plant.lsys", "cave.cave", "topo.grammar", "goals.goal"] {
        std::fs::write(dir.path(name), "").unwrap();
        files.push(std::fs::canonicalize(dir.path(name)).unwrap());
    }
    let studio = start(&[&files[0]]);
    let place = |answer: &Value| {
        let d = &answer["diagnostics"][0];
        (
            answer["ok"].clone(),
            d["severity"].clone(),
            d["line"].clone(),
            d["column"].clone(),
        )
    };
    let error_at =
        |line: usize, column: usize| (json!(false), json!("error"), json!(line), json!(column));
    let plant = derive(&studio, &files[0], "n: 2\naxiom: F\nF -> F(1,\n");
    assert_eq!(place(&plant), error_at(3, 10), "{plant}");
    let cave = derive(&studio, &files[1], "lod 4\nadd box(1, 0, 1)\n");
    assert_eq!(place(&cave), error_at(2, 5), "{cave}");
    assert_eq!(
        cave["diagnostics"][0]["message"],
        json!("invalid box size y 0: expected a finite number greater than 0")
    );
    let topo = derive(&studio, &files[2], "{\n  \"format\": 3,,\n}\n");
    assert_eq!(place(&topo), error_at(2, 13), "{topo}");
    assert_eq!(
        topo["diagnostics"][0]["message"],
        json!("invalid type: integer `3`, expected a string")
    );
    let goals = derive(
        &studio,
        &files[3],
        "axiom chair size(1, 1, 1)\nfulfills(chair) --> s(1, 1\n",
    );
    assert_eq!(place(&goals), error_at(2, 22), "{goals}");
    assert_eq!(goals["diagnostics"][0]["message"], json!("unclosed `(`"));
    // A problem without a place in the text: a field of the wrong type, named by its path.
    let house = std::fs::read_to_string(example("topo_house.grammar")).unwrap();
    let topo = derive(
        &studio,
        &files[2],
        &house.replace("\"version\": 1", "\"version\": 3"),
    );
    assert_eq!(topo["diagnostics"], json!([]));
    assert_eq!(
        topo["error"],
        json!(format!(
            "{}: version: version 3 is not supported (this build reads versions 1 to 2)",
            files[2].display()
        ))
    );
}
/// The GLB of an answer: its JSON chunk, and its triangles by glTF mesh and primitive.
fn glb_triangles(answer: &Value) -> (Value, Vec<Vec<u64>>) {
    let glb = glb_of(answer);
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let document: Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let triangles = document["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|mesh| {
            let primitives = mesh["primitives"].as_array().unwrap();
            primitives
                .iter()
                .map(|p| {
                    let accessor = p["indices"].as_u64().unwrap() as usize;
                    document["accessors"][accessor]["count"].as_u64().unwrap() / 3
                })
                .collect()
        })
        .collect();
    (document, triangles)
}

fn derive_with(studio: &Studio, path: &std::path::Path, text: &str, extra: Value) -> Value {
    let mut body = json!({"path": path, "text": text});
    body.as_object_mut()
        .unwrap()
        .extend(extra.as_object().unwrap().clone());
    let (status, answer) = request(studio, "POST", "/api/derive", Some(body));
    assert_eq!(status, 200, "{answer}");
    answer
}

const BLOCKS: &str = "attr h = 6
Lot --> extrude(h) Mass
Mass --> split(x) { 5 : Red | ~1 : Blue | 5 : Red }
Red --> color(\"#ff0000\")
Blue --> set(h, 2) color(\"#0000ff\") Top
Top --> color(\"#0000ff\")
";

#[test]
fn the_tree_names_every_shape_and_each_triangle_its_leaf() {
    let dir = TempDir::new("studio-tree");
    let file = dir.path("blocks.cga");
    std::fs::write(&file, BLOCKS).unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&[&file]);
    // Without asking, no tree.
    assert_eq!(derive(&studio, &file, BLOCKS).get("tree"), None);
    let answer = derive_with(&studio, &file, BLOCKS, json!({"tree": true}));
    let tree = &answer["tree"];
    // Each part of the split is a shape named after the shape split (Mass), whose successor
    // is the shape its rule (Red, Blue) rewrites.
    assert_eq!(
        tree["symbols"],
        json!(["Lot", "Mass", "Red", "Blue", "Top"])
    );
    assert_eq!(tree["parent"], json!([-1, 0, 1, 2, 1, 4, 1, 6, 5]));
    assert_eq!(tree["symbol"], json!([0, 1, 1, 2, 1, 3, 1, 2, 4]));
    assert_eq!(tree["rule"], json!([0, 1, -1, 2, -1, 3, -1, 2, 4]));
    assert_eq!(answer["shapes"], json!(9));
    // Lot, Mass, the parts' rules, Top's: four generations.
    assert_eq!(tree["generations"], json!(4));
    // Each rule with where it starts and ends (lines and columns, 1-based, end exclusive).
    assert_eq!(
        tree["rules"][3],
        json!({"name": "Blue", "line": 5, "column": 1, "end_line": 5, "end_column": 40})
    );
    // `set(h, 2)` gives the Blue shape's successor its own values.
    assert_eq!(tree["attr_names"], json!(["h"]));
    assert_eq!(tree["attr_values"], json!([["6"], ["2"]]));
    assert_eq!(tree["attrs"], json!([0, 0, 0, 0, 0, 0, 0, 0, 1]));
    // The Blue shape's scope at birth: from x = 5, 10 m wide, 6 m high, 30 m deep.
    let scopes = tree["scopes"].as_array().unwrap();
    assert_eq!(scopes.len(), 9 * 15);
    assert_eq!(
        scopes[5 * 15..6 * 15].to_vec(),
        [5, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 10, 6, 30]
            .map(|v| json!(f64::from(v)))
            .to_vec()
    );
    // Red: one primitive holding both red blocks (12 triangles each), blue the other.
    assert_eq!(
        tree["primitives"],
        json!([
            {"mesh": 0, "primitive": 0, "runs": [3, 12, 7, 12]},
            {"mesh": 0, "primitive": 1, "runs": [8, 12]},
        ])
    );
    let (_, triangles) = glb_triangles(&answer);
    assert_eq!(triangles, [vec![24, 12]]);
}

#[test]
fn every_triangle_of_the_house_belongs_to_a_leaf_of_the_tree() {
    let dir = TempDir::new("studio-tree-house");
    let house = dir.path("house.cga");
    std::fs::copy(example("house.cga"), &house).unwrap();
    let house = std::fs::canonicalize(&house).unwrap();
    let studio = start(&[&house]);
    let text = std::fs::read_to_string(&house).unwrap();
    let answer = derive_with(&studio, &house, &text, json!({"tree": true}));
    let tree = &answer["tree"];
    let parents = tree["parent"].as_array().unwrap();
    assert_eq!(parents.len() as u64, answer["shapes"].as_u64().unwrap());
    let mut has_children = vec![false; parents.len()];
    for p in parents.iter().filter_map(Value::as_i64).filter(|&p| p >= 0) {
        has_children[p as usize] = true;
    }
    let (_, triangles) = glb_triangles(&answer);
    let mut leaves = std::collections::BTreeSet::new();
    let mut mapped = 0;
    for primitive in tree["primitives"].as_array().unwrap() {
        let runs = primitive["runs"].as_array().unwrap();
        let mut sum = 0;
        for run in runs.chunks(2) {
            let node = run[0].as_i64().unwrap();
            assert!(node >= 0 && !has_children[node as usize], "node {node}");
            leaves.insert(node);
            sum += run[1].as_u64().unwrap();
        }
        let (mesh, index) = (primitive["mesh"].as_u64(), primitive["primitive"].as_u64());
        assert_eq!(
            sum,
            triangles[mesh.unwrap() as usize][index.unwrap() as usize]
        );
        mapped += 1;
    }
    assert_eq!(mapped, triangles.iter().map(Vec::len).sum::<usize>());
    assert_eq!(leaves.len() as u64, answer["leaves"].as_u64().unwrap());
}

#[test]
fn generations_stop_the_derivation_early() {
    let dir = TempDir::new("studio-generations");
    let file = dir.path("blocks.cga");
    std::fs::write(&file, BLOCKS).unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&[&file]);
    let counts = |n: u32| {
        let answer = derive_with(
            &studio,
            &file,
            BLOCKS,
            json!({"tree": true, "generations": n}),
        );
        let (_, triangles) = glb_triangles(&answer);
        (
            answer["shapes"].as_u64().unwrap(),
            answer["leaves"].as_u64().unwrap(),
            answer["tree"]["generations"].as_u64().unwrap(),
            triangles.iter().flatten().sum::<u64>(),
        )
    };
    // The lot alone (a rectangle), the block, its three parts (each a part and its successor),
    // the blue part's successor, and its rule applied: the shapes left show as their boxes.
    assert_eq!(counts(0), (1, 1, 0, 2));
    assert_eq!(counts(1), (2, 1, 1, 12));
    assert_eq!(counts(2), (8, 3, 2, 36));
    assert_eq!(counts(3), (9, 3, 3, 36));
    assert_eq!(counts(4), (9, 3, 4, 36));
    assert_eq!(counts(9), (9, 3, 4, 36));
    let (status, answer) = request(
        &studio,
        "POST",
        "/api/derive",
        Some(json!({"path": file, "text": BLOCKS, "generations": 10_001})),
    );
    assert_eq!(status, 422);
    assert_eq!(
        answer["error"],
        json!("generations: 10001 is more than the 10000 a derivation may have")
    );
}

#[test]
fn joints_are_posed_as_derive_poses_them() {
    let dir = TempDir::new("studio-pose");
    let file = dir.path("excavator.cga");
    std::fs::copy(example("excavator.cga"), &file).unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&[&file]);
    let text = std::fs::read_to_string(&file).unwrap();
    let rest = derive(&studio, &file, &text);
    let (document, _) = glb_triangles(&rest);
    let boom = document["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"].as_str().unwrap().starts_with("Boom"))
        .unwrap();
    let name = boom["extras"]["shapegram"]["joint"]["section"]
        .as_str()
        .unwrap();
    let pose = json!({name: {"rotation": [0, 0, 45]}});
    let posed = derive_with(&studio, &file, &text, json!({"pose": pose}));
    let (document, _) = glb_triangles(&posed);
    let boom = document["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["extras"]["shapegram"]["joint"]["section"] == json!(name))
        .unwrap();
    assert_eq!(
        boom["extras"]["shapegram"]["joint"]["pose_rotation_deg"],
        json!([0.0, 0.0, 45.0])
    );
    // Out of the boom's limits (-40° to 60° about z): refused with the joint's name.
    let refused = derive_with(
        &studio,
        &file,
        &text,
        json!({"pose": {name: {"rotation": [0, 0, 90]}}}),
    );
    assert_eq!(refused["ok"], json!(false));
    let error = refused["error"].as_str().unwrap();
    assert!(error.starts_with(&format!("pose: {name}: ")), "{error}");
}

/// A rule package opened in the studio: its rule file listed by its path in the package, read
/// from the archive, derived with the package's assets as `derive package.rpk` derives it (the
/// same counts, the same GLB byte for byte), its attributes in the panel with their
/// annotations; never saved.
#[test]
fn a_rule_package_derives_in_the_studio_as_derive_does_the_package() {
    use base64::Engine as _;
    let dir = TempDir::new("studio-package");
    let package = dir.path("town.rpk");
    std::fs::copy(example("town.rpk"), &package).unwrap();
    let package = std::fs::canonicalize(&package).unwrap();
    let studio = start(&[&package]);
    let (status, list) = request(&studio, "GET", "/api/files", None);
    assert_eq!(status, 200, "{list}");
    let rule = format!("{}!/rules/town.cga", package.display());
    assert_eq!(
        list["files"],
        json!([{"path": rule, "name": "town.rpk!/rules/town.cga", "given": true, "read_only": true}])
    );
    let query = format!("/api/file?path={}", rule.replace(' ', "%20"));
    let (status, file) = request(&studio, "GET", &query, None);
    assert_eq!(status, 200, "{file}");
    let text = file["text"].as_str().unwrap().to_owned();
    assert!(text.contains("attr height = 9"), "{text}");

    let answer = derive(&studio, std::path::Path::new(&rule), &text);
    let stats = shapegram(&["derive", "-q", "--stats", package.to_str().unwrap()]);
    let stats: Value = serde_json::from_slice(&stats.stdout).unwrap();
    assert_eq!(
        (&answer["ok"], &answer["shapes"], &answer["leaves"]),
        (&json!(true), &stats["shapes"], &stats["leaves"])
    );
    assert_eq!(answer["diagnostics"], json!([]));
    let attrs: Vec<(&str, &Value, &Value, bool)> = answer["attrs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            (
                a["name"].as_str().unwrap(),
                &a["value"],
                &a["range"],
                a["color"].as_bool().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        attrs,
        [
            (
                "height",
                &json!(9.0),
                &json!({"min": 3.0, "max": 30.0, "step": 0.0}),
                false
            ),
            (
                "roofAngle",
                &json!(30.0),
                &json!({"min": 10.0, "max": 60.0, "step": 0.0}),
                false
            ),
            ("roofColor", &json!("#8a3b2e"), &Value::Null, true),
        ]
    );

    // The panel's value, exported, is `derive --attr`'s GLB, the package's texture embedded.
    let out = dir.path("town.glb");
    let derived = shapegram(&[
        "derive",
        "-q",
        package.to_str().unwrap(),
        "--attr",
        "height=20",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(derived.status.success(), "{}", stderr(&derived));
    let (status, exported) = request(
        &studio,
        "POST",
        "/api/export",
        Some(json!({"path": rule, "text": text, "attrs": {"height": 20}, "format": "glb"})),
    );
    assert_eq!(status, 200, "{exported}");
    let glb = base64::engine::general_purpose::STANDARD
        .decode(exported["files"][0]["data"].as_str().unwrap())
        .unwrap();
    assert_eq!(glb, std::fs::read(&out).unwrap());

    let (status, refused) = request(
        &studio,
        "PUT",
        "/api/file",
        Some(json!({"path": rule, "text": "Lot --> X.\n"})),
    );
    assert_eq!(status, 403, "{refused}");
    assert_eq!(
        std::fs::read(&package).unwrap(),
        std::fs::read(example("town.rpk")).unwrap()
    );
}
