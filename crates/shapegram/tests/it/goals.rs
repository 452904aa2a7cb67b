//! `shapegram derive` and `check` on goal grammars with their libraries.

use crate::common;

use common::{TempDir, example, shapegram, stderr};
use serde_json::Value;

fn stats(args: &[&str]) -> Value {
    let output = shapegram(args);
    assert!(output.status.success(), "{}", stderr(&output));
    serde_json::from_slice(&output.stdout).unwrap()
}

fn path(name: &str) -> String {
    example(name).display().to_string()
}

#[test]
fn the_showroom_derives_with_its_libraries_and_counts_steps_rules_and_grammars() {
    let dir = TempDir::new("showroom");
    let out = dir.path("showroom.glb").display().to_string();
    let json = stats(&[
        "derive",
        &path("chairs/showroom.goal"),
        "--library",
        &path("chairs/designs"),
        "--library",
        &path("chairs/materials"),
        "-o",
        &out,
        "--stats",
        "-q",
    ]);
    let goals = &json["goals"];
    assert_eq!(goals["grammars_used"], 8);
    assert_eq!(goals["rules_used"], goals["rules"]);
    assert_eq!(goals["tags"]["chair"], json["leaves"]);
    let steps: u64 = goals["grammars"]
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_u64().unwrap())
        .sum();
    assert_eq!(goals["steps"].as_u64(), Some(steps));
    // Every node of the file carries its part's goals, tags and attributes.
    let glb = std::fs::read(&out).unwrap();
    let length = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let gltf: Value = serde_json::from_slice(&glb[20..20 + length]).unwrap();
    let nodes = gltf["nodes"].as_array().unwrap();
    let tagged = nodes
        .iter()
        .filter(|n| n["extras"]["shapegram"]["tags"].as_array().is_some())
        .count();
    assert_eq!(tagged, nodes.len() - 1, "all but the root");
    let leg = nodes
        .iter()
        .find(|n| n["extras"]["shapegram"]["attributes"]["Leg.Size"].is_number())
        .expect("a leg with its size");
    assert!(
        leg["extras"]["shapegram"]["tags"]
            .as_array()
            .unwrap()
            .contains(&Value::from("chair"))
    );
}

#[test]
fn an_error_in_a_library_grammar_is_shown_in_its_file() {
    let dir = TempDir::new("library-error");
    std::fs::write(dir.path("main.goal"), "axiom box size(1, 1, 1)\n").unwrap();
    std::fs::create_dir_all(dir.path("lib")).unwrap();
    std::fs::write(
        dir.path("lib/paint.goal"),
        "// paints boxes\nfulfills(box) if(scope.sx) --> color(\"#ff0000\")\n",
    )
    .unwrap();
    let output = shapegram(&[
        "derive",
        &dir.path("main.goal").display().to_string(),
        "--library",
        &dir.path("lib").display().to_string(),
    ]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(
        err.contains("error: expected a boolean condition, found a number"),
        "{err}"
    );
    assert!(err.contains("paint.goal:2:18"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn check_reads_goal_grammars_with_their_library_and_derive_refuses_a_library_for_cga() {
    let output = shapegram(&[
        "check",
        &path("chairs/metallic_chair.goal"),
        "--library",
        &path("chairs/chair.goal"),
        "--library",
        &path("chairs/materials"),
    ]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    assert!(
        err.ends_with(
            "metallic_chair.goal with a library of 4 files (12 goal rules, 0 warnings)\n"
        ),
        "{err}"
    );
    let output = shapegram(&[
        "derive",
        &path("house.cga"),
        "--library",
        &path("chairs/materials"),
    ]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        err.starts_with("error: ")
            && err.contains(
                "house.cga is not a goal grammar: --library gives goal grammars their rules"
            ),
        "{err}"
    );
}

#[test]
fn library_grammars_check_alone_and_goal_grammars_get_no_default_lot() {
    let output = shapegram(&["check", &path("chairs/materials/wood.goal")]);
    assert!(output.status.success(), "{}", stderr(&output));
    let dir = TempDir::new("no-lot");
    let grammar = dir.path("parcel.goal").display().to_string();
    std::fs::write(&grammar, "axiom parcel\nfulfills(parcel) --> extrude(3)\n").unwrap();
    let output = shapegram(&["derive", &grammar]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with(
            "error: the axiom `parcel` has no size, and there are no lots for it to start from"
        ),
        "{err}"
    );
    let output = shapegram(&["derive", &grammar, "--lot", "0,0 10,0 10,10 0,10", "-q"]);
    assert!(output.status.success(), "{}", stderr(&output));
}

#[test]
fn two_library_grammars_of_one_name_are_refused() {
    let dir = TempDir::new("same-name");
    for folder in ["a", "b"] {
        std::fs::create_dir_all(dir.path(folder)).unwrap();
        std::fs::write(
            dir.path(&format!("{folder}/wood.goal")),
            "fulfills(wooden) --> color(\"#8b5a2b\")\n",
        )
        .unwrap();
    }
    let output = shapegram(&[
        "derive",
        &path("chairs/chair.goal"),
        "--library",
        &dir.path("a").display().to_string(),
        "--library",
        &dir.path("b").display().to_string(),
    ]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with("error: two library grammars are called `wood`:"),
        "{err}"
    );
}

/// The GLB of the runtime's model (what the C ABI, Python and Godot derive).
fn runtime_glb(grammar: &std::path::Path, library: &[std::path::PathBuf]) -> Vec<u8> {
    use shapegram_runtime::{Derived, Grammar, Settings};
    let name = grammar.display().to_string();
    let text = std::fs::read_to_string(grammar).unwrap();
    let library = shapegram_runtime::read_library(library, grammar).unwrap();
    let loaded = Grammar::load_with_library(&name, &text, None, &library).unwrap();
    let Derived::Model(model) = loaded.derive(&Settings::default()).unwrap() else {
        panic!("a goal grammar derives a model");
    };
    let mut glb = Vec::new();
    shapegram_export::write_glb_to(&model, &Default::default(), &mut glb).unwrap();
    glb
}

/// A host loading a goal grammar with its library through the runtime gets the model
/// `derive --library` writes, byte for byte, and without it the model `derive` alone writes
/// (its goal `wooden` left open).
#[test]
fn the_runtime_derives_a_goal_grammar_with_its_library_as_derive_does() {
    let dir = TempDir::new("runtime-library");
    let chair = example("chairs/chair.goal");
    let materials = example("chairs/materials");
    let (chair_arg, materials_arg) = (path("chairs/chair.goal"), path("chairs/materials"));
    let out = dir.path("chair.glb").display().to_string();
    for library in [vec![materials.clone()], vec![]] {
        let mut command = vec!["derive", "-q", &chair_arg, "-o", &out];
        if !library.is_empty() {
            command.extend(["--library", &materials_arg]);
        }
        let output = shapegram(&command);
        assert!(output.status.success(), "{}", stderr(&output));
        let written = std::fs::read(&out).unwrap();
        assert!(
            runtime_glb(&chair, &library) == written,
            "the runtime's GLB differs from `shapegram {}`",
            command.join(" ")
        );
    }
    assert!(runtime_glb(&chair, &[materials]) != runtime_glb(&chair, &[]));
}
