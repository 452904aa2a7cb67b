//! The runtime as a host uses it: every kind of grammar loads and derives into consistent
//! buffers, the same settings give the same buffers, and bad input gives errors of the right
//! kind with their place.

use std::path::{Path, PathBuf};

use shapegram_eval::Value;
use shapegram_export::Buffers;
use shapegram_geom::DVec3;
use shapegram_runtime::{
    AttrType, Error, ErrorKind, Grammar, Kind, Settings, check_library_path, lot, read_library,
};

fn example_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn example(name: &str) -> (String, String) {
    let path = example_path(name);
    let text = std::fs::read_to_string(&path).expect("the example exists");
    (path.display().to_string(), text)
}

fn buffers(grammar: &Grammar, settings: &Settings) -> Buffers {
    let mut buffers = Buffers::default();
    grammar
        .derive(settings)
        .expect("the grammar derives")
        .fill(&mut buffers);
    buffers
}

/// Indices in range, whole triangles, and parts that tile the index buffer in order.
fn assert_consistent(buffers: &Buffers) {
    assert_eq!(buffers.positions.len(), buffers.normals.len());
    assert_eq!(buffers.indices.len() % 3, 0);
    assert!(!buffers.indices.is_empty());
    let vertices = buffers.positions.len() as u32;
    assert!(buffers.indices.iter().all(|&i| i < vertices));
    let mut next = 0;
    for part in &buffers.parts {
        assert_eq!(part.first_index, next);
        next += part.index_count;
    }
    assert_eq!(next as usize, buffers.indices.len());
}

#[test]
fn every_kind_of_grammar_derives_into_consistent_buffers() {
    for (file, kind) in [
        (
            "house.cga",
            Kind::Shape(Some(shapegram_syntax::Dialect::Cga)),
        ),
        (
            "mueller2006_fig12.mul",
            Kind::Shape(Some(shapegram_syntax::Dialect::Muller2006)),
        ),
        (
            "sgl_tree.sgl",
            Kind::Shape(Some(shapegram_syntax::Dialect::Sgl)),
        ),
        ("tree-3d.lsys", Kind::LSystem),
        ("grotto.cave", Kind::Cave),
        ("topo_house.grammar", Kind::Topo),
    ] {
        assert_eq!(Kind::of_name(file), Some(kind), "{file}");
        let (name, text) = example(file);
        let grammar = Grammar::load(&name, &text, None).expect(file);
        assert_consistent(&buffers(&grammar, &Settings::default()));
    }
}

#[test]
fn the_same_settings_give_the_same_buffers_and_attributes_change_them() {
    let (name, text) = example("house.cga");
    let grammar = Grammar::load(&name, &text, None).unwrap();
    let two = buffers(&grammar, &Settings::default());
    assert_eq!(two, buffers(&grammar, &Settings::default()));
    let three = Settings {
        attrs: vec![("storeys".to_owned(), Value::Number(3.0))],
        ..Settings::default()
    };
    grammar.check_attr("storeys", &Value::Number(3.0)).unwrap();
    let taller = buffers(&grammar, &three);
    let top = |b: &Buffers| b.positions.iter().map(|p| p[1]).fold(f32::MIN, f32::max);
    assert!(
        top(&taller) > top(&two) + 2.9,
        "{} vs {}",
        top(&taller),
        top(&two)
    );
}

#[test]
fn bad_input_gives_errors_of_their_kind_with_their_place() {
    let error = Grammar::load("broken.cga", "Lot --> extrude(3\n", None)
        .err()
        .expect("a syntax error");
    assert_eq!(error.kind, ErrorKind::Grammar);
    assert!(error.message.contains("broken.cga:1:"), "{}", error.message);

    let (name, text) = example("house.cga");
    let grammar = Grammar::load(&name, &text, None).unwrap();
    let unknown = grammar
        .check_attr("storey", &Value::Number(1.0))
        .unwrap_err();
    assert_eq!(unknown.kind, ErrorKind::UnknownAttribute);
    assert_eq!(
        unknown.message,
        "the grammar has no attribute `storey` (did you mean `storeys`?)"
    );
    let typed = grammar
        .check_attr("storeys", &Value::Str("two".into()))
        .unwrap_err();
    assert_eq!(typed.kind, ErrorKind::AttributeType);
    assert_eq!(
        typed.message,
        format!("{name}:8:6: the attribute `storeys` is a number, not a string")
    );
}

#[test]
fn attributes_are_declared_with_their_literal_defaults_and_places() {
    let (name, text) = example("house.cga");
    let grammar = Grammar::load(&name, &text, None).unwrap();
    let declared: Vec<(&str, Option<Value>, Option<AttrType>, String)> = grammar
        .attrs()
        .iter()
        .map(|a| {
            (
                a.name.as_str(),
                a.default.clone(),
                a.ty(),
                a.location.clone(),
            )
        })
        .collect();
    assert_eq!(
        declared,
        [
            ("storeys", Value::Number(2.0), AttrType::Number, 8),
            ("storeyH", Value::Number(3.0), AttrType::Number, 9),
            ("roofAngle", Value::Number(35.0), AttrType::Number, 10),
            ("wallColor", Value::string("#e8dcc4"), AttrType::String, 11),
            ("roofColor", Value::string("#8b3a2f"), AttrType::String, 12),
        ]
        .map(|(n, v, t, line)| (n, Some(v), Some(t), format!("{name}:{line}:6")))
    );
    // Negated literals are literals; anything else is known only by deriving.
    let text = "attr low = -2\nattr off = !true\nattr wide = low * 2\nLot --> X.\n";
    let grammar = Grammar::load("a.cga", text, None).unwrap();
    let defaults: Vec<_> = grammar.attrs().iter().map(|a| a.default.clone()).collect();
    assert_eq!(
        defaults,
        [Some(Value::Number(-2.0)), Some(Value::Bool(false)), None]
    );
    assert_eq!(grammar.attrs()[2].location, "a.cga:3:6");
    let (name, text) = example("tree-3d.lsys");
    assert!(
        Grammar::load(&name, &text, None)
            .unwrap()
            .attrs()
            .is_empty()
    );
}

/// The kinds whose parsers give one place have it on the error, with the bare message, for
/// editors to mark; a CGA-style grammar's errors stay in the message.
#[test]
fn errors_with_one_place_carry_it() {
    let place = |error: Error| {
        let place = error.place.expect("a place");
        (place.line, place.column, place.message)
    };
    let lsystem = Grammar::load("plant.lsys", "n: 2\naxiom: F\nF -> F(1,\n", None).err();
    assert_eq!(
        place(lsystem.expect("a syntax error")),
        (
            3,
            10,
            "expected a number, a name or '(', found the end of the line".to_owned()
        )
    );
    // A cave's sizes are checked as it grows.
    let cave = Grammar::load("cave.cave", "lod 4\nadd box(1, 0, 1)\n", None).unwrap();
    let grown = cave.derive(&Settings::default()).err();
    assert_eq!(
        place(grown.expect("a bad size")),
        (
            2,
            5,
            "invalid box size y 0: expected a finite number greater than 0".to_owned()
        )
    );
    let topo = Grammar::load("topo.grammar", "{\n  \"format\": 3\n}\n", None).err();
    assert_eq!(
        place(topo.expect("a type error")),
        (
            2,
            13,
            "invalid type: integer `3`, expected a string".to_owned()
        )
    );
    let cga = Grammar::load("broken.cga", "Lot --> extrude(3\n", None).err();
    assert_eq!(cga.expect("a syntax error").place, None);
}

#[test]
fn lots_are_checked_before_deriving() {
    let message = |corners: &[[f64; 3]]| {
        let footprint = corners.iter().map(|&c| DVec3::from_array(c)).collect();
        lot(footprint).map(|_| ()).map_err(|e| (e.kind, e.message))
    };
    let invalid = |m: &str| Err((ErrorKind::InvalidArgument, m.to_owned()));
    assert_eq!(
        message(&[[0.0; 3], [1.0, 0.0, 0.0]]),
        invalid("a lot needs 3 corners or more, not 2")
    );
    assert_eq!(
        message(&[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]),
        invalid("the lot has no area")
    );
    assert_eq!(
        message(&[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, f64::NAN]]),
        invalid("a lot's corner is not finite")
    );
    assert_eq!(
        message(&[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 1.0]]),
        Ok(())
    );
}

/// The kinds that are not CGA-style stop at the control's cancellation with a `Cancelled`
/// error: an L-system before a step, a cave before a meshing block, a topological grammar
/// before a generation (CGA-style rules: `shapegram-ffi`'s tests/threads.rs).
#[test]
fn every_kind_stops_when_cancelled() {
    for (file, kind) in [
        ("tree-3d.lsys", Some(Kind::LSystem)),
        ("grotto.cave", Some(Kind::Cave)),
        ("topo_house.grammar", Some(Kind::Topo)),
    ] {
        let (name, text) = example(file);
        let grammar = Grammar::load(&name, &text, kind).unwrap();
        let settings = Settings::default();
        settings.control.cancel();
        let error = grammar.derive(&settings).err().expect(file);
        assert_eq!(
            (error.kind, error.message.as_str()),
            (ErrorKind::Cancelled, "the derivation was cancelled"),
            "{file}"
        );
    }
}

/// A cancellation from another thread stops meshing in the middle: a sphere of radius 20 at 32
/// cells per metre (ten million triangles, minutes unoptimised) ends with `Cancelled` instead.
#[test]
fn a_cave_is_cancelled_while_it_is_meshed() {
    let grammar = Grammar::load("big.cave", "lod 32\nadd sphere(20)\n", Some(Kind::Cave)).unwrap();
    let settings = Settings::default();
    let error = std::thread::scope(|scope| {
        let worker = scope.spawn(|| grammar.derive(&settings));
        std::thread::sleep(std::time::Duration::from_millis(300));
        settings.control.cancel();
        worker.join().unwrap().err().expect("cancelled")
    });
    assert_eq!(error.kind, ErrorKind::Cancelled, "{}", error.message);
}

/// The world frame of joint `j` from the buffers' joint transformations, root down.
fn joint_world(buffers: &Buffers, j: u32) -> shapegram_geom::DAffine3 {
    use shapegram_geom::{DQuat, DVec3};
    let joint = &buffers.joints[j as usize];
    let local = shapegram_geom::DAffine3::from_rotation_translation(
        DQuat::from_array(joint.rotation.map(f64::from)),
        DVec3::from_array(joint.translation.map(f64::from)),
    );
    match joint.parent {
        Some(parent) => joint_world(buffers, parent) * local,
        None => local,
    }
}

/// The excavator's buffers carry its skeleton: a host that turns the joints as another
/// derivation does (the boom, stick and bucket angles changed) moves every vertex to where
/// that derivation puts it, through the joints' frames alone.
#[test]
fn the_buffers_carry_the_skeleton_a_host_poses() {
    let (name, text) = example("excavator.cga");
    let grammar = Grammar::load(&name, &text, None).unwrap();
    let derived = buffers(&grammar, &Settings::default());
    assert_consistent(&derived);
    assert_eq!(derived.vertex_joints.len(), derived.positions.len());
    let names: Vec<&str> = derived.joints.iter().map(|j| j.name.as_str()).collect();
    let find = |rule: &str| {
        let found = names
            .iter()
            .position(|n| n.starts_with(&format!("{rule}_")));
        found.unwrap_or_else(|| panic!("no {rule} in {names:?}"))
    };
    let boom = &derived.joints[find("Boom")];
    assert!(find("Stick") > find("Boom") && find("Bucket") > find("Stick"));
    assert_eq!(boom.rotation_limits_deg[2], [-40.0, 60.0]);
    assert_eq!(boom.pose_rotation_deg, [0.0, 0.0, 35.0]);
    assert!(derived.joints[0].parent.is_none());
    assert!(
        derived
            .joints
            .iter()
            .enumerate()
            .all(|(i, j)| j.parent.is_none_or(|p| (p as usize) < i)),
        "parents come before their children"
    );
    assert!(
        derived
            .vertex_joints
            .iter()
            .all(|&j| (j as usize) < derived.joints.len())
    );

    let settings = Settings {
        attrs: vec![
            ("boomAngle".into(), Value::Number(-20.0)),
            ("stickAngle".into(), Value::Number(-30.0)),
            ("bucketAngle".into(), Value::Number(10.0)),
        ],
        ..Settings::default()
    };
    let posed = buffers(&grammar, &settings);
    assert_eq!(posed.positions.len(), derived.positions.len());
    assert_eq!(posed.vertex_joints, derived.vertex_joints);
    let mut moved = 0;
    for (v, (&j, (p0, p1))) in derived
        .vertex_joints
        .iter()
        .zip(derived.positions.iter().zip(&posed.positions))
        .enumerate()
    {
        let motion = joint_world(&posed, j) * joint_world(&derived, j).inverse();
        let p0 = DVec3::from_array(p0.map(f64::from));
        let p1 = DVec3::from_array(p1.map(f64::from));
        let host = motion.transform_point3(p0);
        assert!(
            host.distance(p1) < 1e-4,
            "vertex {v} on joint {j}: the host puts it at {host}, the derivation at {p1}"
        );
        moved += usize::from(p0.distance(p1) > 0.1);
    }
    assert!(moved > 100, "only {moved} vertices moved");
}

/// `examples/chairs/chair.goal` with the library `read_library` reads from `paths`.
fn chair_with(paths: &[PathBuf]) -> Grammar {
    let (name, text) = example("chairs/chair.goal");
    let library = read_library(paths, Path::new(&name)).expect("the library reads");
    Grammar::load_with_library(&name, &text, None, &library).expect("the chair loads")
}

/// A part's colour as the grammar writes it.
fn hex(color: [f32; 4]) -> String {
    let [r, g, b] = [color[0], color[1], color[2]].map(|c| (c * 255.0).round() as u8);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// `shapegram derive examples/chairs/chair.goal --library examples/chairs/materials --stats`
/// makes 72 triangles in 3 parts whose six leaves `wood.goal` paints brown; without the library
/// the same geometry, its goal `wooden` left open, in the default grey. (The shapegram crate's
/// tests/goals.rs checks the GLB of this derivation against the command's byte for byte.)
#[test]
fn a_goal_grammar_derives_with_its_library_as_the_command_does() {
    let materials = example_path("chairs/materials");
    let (chair, _) = example("chairs/chair.goal");
    let library = read_library(std::slice::from_ref(&materials), Path::new(&chair)).unwrap();
    let names: Vec<&str> = library.iter().map(|(name, _)| name.as_str()).collect();
    let file = |stem: &str| materials.join(stem).display().to_string();
    assert_eq!(
        names,
        [file("fabric.goal"), file("metal.goal"), file("wood.goal")]
    );

    let with = buffers(&chair_with(&[materials]), &Settings::default());
    assert_consistent(&with);
    assert_eq!(
        (with.positions.len(), with.indices.len(), with.parts.len()),
        (144, 3 * 72, 3)
    );
    let colors = |b: &Buffers| b.parts.iter().map(|p| hex(p.color)).collect::<Vec<_>>();
    assert_eq!(colors(&with), ["#8b5a2b"; 3]);

    let alone = buffers(&chair_with(&[]), &Settings::default());
    assert_eq!(
        (&alone.positions, &alone.indices),
        (&with.positions, &with.indices)
    );
    assert_eq!(colors(&alone), ["#cccccc"; 3]);
}

/// A grammar's own folder is its library without it, as `--library` reads it.
#[test]
fn a_goal_grammar_is_left_out_of_its_own_folder() {
    let (chair, _) = example("chairs/chair.goal");
    let folder = PathBuf::from(&chair).with_file_name("");
    let library = read_library(&[folder], Path::new(&chair)).unwrap();
    assert_eq!(library.len(), 9);
    assert!(library.iter().all(|(name, _)| name != &chair));
    assert!(
        library
            .iter()
            .any(|(name, _)| name.ends_with("metallic_chair.goal"))
    );
}

#[test]
fn an_error_in_a_library_file_names_the_file_line_and_column() {
    let folder = std::env::temp_dir().join(format!("shapegram-runtime-lib-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let paint = folder.join("paint.goal");
    std::fs::write(
        &paint,
        "// paints boxes\nfulfills(box) --> color(\"#ff0000\"\n",
    )
    .unwrap();
    let library = read_library(std::slice::from_ref(&paint), Path::new("main.goal"));
    std::fs::remove_dir_all(&folder).unwrap();
    let error = Grammar::load_with_library(
        "main.goal",
        "axiom box size(1, 1, 1)\n",
        None,
        &library.unwrap(),
    )
    .err()
    .expect("a syntax error");
    assert_eq!(error.kind, ErrorKind::Grammar);
    assert!(
        error.message.starts_with("error: unclosed `(`\n")
            && error
                .message
                .contains(&format!("--> {}:2:24\n", paint.display())),
        "{}",
        error.message
    );
}

#[test]
fn a_library_is_refused_for_other_grammars_and_for_names_used_twice() {
    let wood = (
        "wood.goal".to_owned(),
        "fulfills(wooden) --> color(\"#8b5a2b\")\n".to_owned(),
    );
    for file in ["house.cga", "tree-3d.lsys"] {
        let (name, text) = example(file);
        let error = Grammar::load_with_library(&name, &text, None, std::slice::from_ref(&wood))
            .err()
            .expect(file);
        assert_eq!(
            (error.kind, error.message),
            (
                ErrorKind::Grammar,
                format!("{name} is not a goal grammar: a library gives goal grammars their rules")
            )
        );
    }
    let (name, text) = example("chairs/chair.goal");
    let twice = [
        ("a/wood.goal".to_owned(), wood.1.clone()),
        ("b/wood.goal".to_owned(), wood.1.clone()),
    ];
    let error = Grammar::load_with_library(&name, &text, None, &twice)
        .err()
        .expect("two grammars called wood");
    assert_eq!(
        (error.kind, error.message.as_str()),
        (
            ErrorKind::Grammar,
            "two library grammars are called `wood`: a/wood.goal and b/wood.goal \
             (grammars are named by their file names: rename one)"
        )
    );
}

#[test]
fn a_library_path_that_is_missing_is_an_io_error() {
    let missing = PathBuf::from("no/such/library");
    let expected = (
        ErrorKind::Io,
        "the library no/such/library is neither a file nor a folder".to_owned(),
    );
    let error = check_library_path(&missing).unwrap_err();
    assert_eq!((error.kind, error.message), expected);
    let error = read_library(&[missing], Path::new("main.goal")).unwrap_err();
    assert_eq!((error.kind, error.message), expected);
}

/// The corners of part `part` of `buffers` facing along `normal` whose position satisfies `on`,
/// each with its uv, sorted by position.
fn corners_with_uvs(
    buffers: &Buffers,
    part: usize,
    normal: [f32; 3],
    on: impl Fn([f32; 3]) -> bool,
) -> Vec<([f32; 3], [f32; 2])> {
    let range = &buffers.parts[part];
    let mut corners: Vec<_> = (range.first_vertex..range.first_vertex + range.vertex_count)
        .map(|i| i as usize)
        .filter(|&i| buffers.normals[i] == normal && on(buffers.positions[i]))
        .map(|i| (buffers.positions[i], buffers.uvs[i]))
        .collect();
    corners.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    corners
}

#[test]
fn the_brick_house_reaches_the_buffers_with_its_uvs_and_textures() {
    let (name, text) = example("topo_brick_house.grammar");
    let grammar = Grammar::load(&name, &text, None).unwrap();
    let derived = grammar.derive(&Settings::default()).unwrap();
    let mut buffers = Buffers::default();
    derived.fill(&mut buffers);
    assert_consistent(&buffers);
    // Each image once, named as the grammar names it, read beside the grammar.
    let paths: Vec<&str> = buffers.textures.iter().map(|t| &*t.path).collect();
    assert_eq!(paths, ["textures/brick.png", "textures/tiles.png"]);
    for texture in &buffers.textures {
        let file = std::fs::read(example_path(&texture.path)).unwrap();
        assert_eq!(
            texture.image.as_deref(),
            Some(&file[..]),
            "{}",
            texture.path
        );
    }
    // Parts keep their materials' names; the textured ones point at their images.
    let materials: Vec<(Option<&str>, Option<u32>)> = buffers
        .parts
        .iter()
        .map(|p| (derived.part_material(p.part), p.texture))
        .collect();
    assert_eq!(
        materials,
        [
            (Some("Brick"), Some(0)),
            (Some("RoofTiles"), Some(1)),
            (Some("Stone"), None),
            (Some("Stone"), None),
            (None, None),
            (Some("Brick"), Some(0)),
            (Some("Glass"), None),
        ]
    );
    assert_eq!(buffers.uvs.len(), buffers.positions.len());
    // The roof's brick gable ends come first. The main block's, at x = 0, faces −x: u runs
    // along z and v up y, in tiles of 1.2 × 0.6 m, v turned down as glTF has it:
    // (z / 1.2, 1 − y / 0.6).
    let gable = corners_with_uvs(&buffers, 0, [-1.0, 0.0, 0.0], |p| p[0] == 0.0);
    assert_eq!(
        gable,
        [
            ([0.0, 4.55, 0.0], [0.0, -6.5833335]),
            ([0.0, 4.55, 8.0], [6.6666665, -6.5833335]),
            ([0.0, 7.0, 4.0], [3.3333333, -10.666667]),
        ]
    );
    for (p, uv) in &gable {
        let expected = [p[2] / 1.2, 1.0 - p[1] / 0.6];
        assert!((uv[0] - expected[0]).abs() < 1e-6 && (uv[1] - expected[1]).abs() < 1e-6);
    }
    // The vertices of untextured parts have (0, 0).
    for part in buffers.parts.iter().filter(|p| p.texture.is_none()) {
        let vertices = part.first_vertex as usize..(part.first_vertex + part.vertex_count) as usize;
        assert!(buffers.uvs[vertices].iter().all(|&uv| uv == [0.0; 2]));
    }
}

#[test]
fn a_topological_grammar_whose_textures_are_missing_keeps_its_materials_colours() {
    let (name, text) = example("topo_brick_house.grammar");
    let elsewhere = Path::new(&name)
        .with_file_name("no-such-folder")
        .join("topo_brick_house.grammar");
    let grammar = Grammar::load(&elsewhere.display().to_string(), &text, None).unwrap();
    let derived = grammar.derive(&Settings::default()).unwrap();
    let mut buffers = Buffers::default();
    derived.fill(&mut buffers);
    assert!(buffers.textures.is_empty() && buffers.uvs.is_empty());
    assert!(buffers.parts.iter().all(|p| p.texture.is_none()));
    let roof = buffers
        .parts
        .iter()
        .find(|p| derived.part_material(p.part) == Some("RoofTiles"))
        .expect("the roof's part");
    assert_eq!(roof.color, [192.0 / 255.0, 98.0 / 255.0, 74.0 / 255.0, 1.0]);
    // Nothing else changes: the same triangles as with the images.
    let (name, _) = example("topo_brick_house.grammar");
    let textured = buffers_of(&name, &text);
    assert_eq!(
        (&buffers.positions, &buffers.indices),
        (&textured.positions, &textured.indices)
    );
}

fn buffers_of(name: &str, text: &str) -> Buffers {
    buffers(
        &Grammar::load(name, text, None).unwrap(),
        &Settings::default(),
    )
}
