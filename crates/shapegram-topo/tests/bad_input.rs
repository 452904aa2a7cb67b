//! Corrupt and hand-edited grammar and project files: clear errors with locations, no panics.

use proptest::prelude::*;
use serde_json::{Value, json};
use shapegram_topo::{Grammar, GrammarState, Project, compile, demos};

fn spiral_grammar() -> Value {
    let text = compile(&demos::spiral_steps(true).unwrap())
        .unwrap()
        .to_json();
    serde_json::from_str(&text).unwrap()
}

fn grammar_error(value: &Value) -> String {
    Grammar::from_json(&value.to_string())
        .unwrap_err()
        .to_string()
}

fn project_error(value: &Value) -> String {
    Project::from_json(&value.to_string())
        .unwrap_err()
        .to_string()
}

#[test]
fn json_syntax_errors_give_line_and_column() {
    assert_eq!(
        Grammar::from_json("").unwrap_err().to_string(),
        "1:0: EOF while parsing a value"
    );
    assert_eq!(
        Grammar::from_json("{\n  \"format\": 3\n}")
            .unwrap_err()
            .to_string(),
        "2:13: invalid type: integer `3`, expected a string"
    );
    assert_eq!(
        Project::from_json("{\"format\": \"x\",}")
            .unwrap_err()
            .to_string(),
        "1:16: trailing comma"
    );
}

#[test]
fn the_format_and_version_are_checked_first() {
    let mut g = spiral_grammar();
    g["format"] = json!("shapegram-topo-project");
    assert_eq!(
        grammar_error(&g),
        "format: 'shapegram-topo-project' is not a topological grammar (expected \
         'shapegram-topo-grammar')"
    );
    let mut g = spiral_grammar();
    g["version"] = json!(2);
    assert_eq!(
        grammar_error(&g),
        "version: version 2 is not supported (this build reads version 1)"
    );
    let mut g = spiral_grammar();
    g["extra"] = json!(1);
    assert!(grammar_error(&g).contains("unknown field `extra`"));
}

#[test]
fn indices_out_of_range_are_located() {
    let mut g = spiral_grammar();
    g["rules"][0]["sub_shapes"][1]["vertices"][3] = json!(999);
    assert_eq!(
        grammar_error(&g),
        "rules[0].sub_shapes[1].vertices[3]: vertex 999 does not exist (the rule has 8 shape and \
         8 virtual vertices)"
    );
    let mut g = spiral_grammar();
    g["rules"][0]["virtual_vertices"][0] = json!([0, 9, 0.5]);
    assert_eq!(
        grammar_error(&g),
        "rules[0].virtual_vertices[0].to: vertex 9 does not exist yet (8 shape vertices and 0 \
         earlier virtual vertices)"
    );
    let mut g = spiral_grammar();
    g["rules"][0]["sub_shapes"][0]["symbol"] = json!(7);
    assert_eq!(
        grammar_error(&g),
        "rules[0].sub_shapes[0].symbol: symbol 7 does not exist (there are 2)"
    );
    let mut g = spiral_grammar();
    g["symbols"][0]["rules"] = json!([0, 1]);
    assert_eq!(
        grammar_error(&g),
        "symbols[0].rules[1]: rule 1 does not exist (there are 1)"
    );
    let mut g = spiral_grammar();
    g["shapes"][0]["vertices"].as_array_mut().unwrap().pop();
    assert_eq!(
        grammar_error(&g),
        "shapes[0].vertices: 7 positions for a symbol of 8 vertices"
    );
}

#[test]
fn broken_topology_names_the_symbol_and_edge() {
    let mut g = spiral_grammar();
    g["symbols"][1]["faces"].as_array_mut().unwrap().pop();
    assert_eq!(
        grammar_error(&g),
        "symbols[1].faces: edge 5 → 4: only one face runs along it (the surface has a hole)"
    );
    let mut g = spiral_grammar();
    g["symbols"][0]["faces"][0] = json!([0, 3, 2]);
    assert!(grammar_error(&g).starts_with("symbols[0].faces: edge "));
}

#[test]
fn bad_numbers_and_names_are_refused() {
    let mut g = spiral_grammar();
    g["rules"][0]["weight"] = json!(0.0);
    assert_eq!(
        grammar_error(&g),
        "rules[0].weight: 0 is not a positive number"
    );
    let mut g = spiral_grammar();
    g["symbols"][1]["name"] = json!("A");
    assert_eq!(
        grammar_error(&g),
        "symbols[1].name: the name 'A' is used twice"
    );
    let mut g = spiral_grammar();
    g["symbols"][1]["color"] = json!("#zz0000");
    assert_eq!(
        grammar_error(&g),
        "symbols[1].color: '#zz0000' is not a colour like '#3a6ea5'"
    );
    let mut g = spiral_grammar();
    g["symbols"][1]["face_colors"] = json!([null, "#ffffff"]);
    assert_eq!(
        grammar_error(&g),
        "symbols[1].face_colors: 2 colours for 6 faces (give one per face, null for none)"
    );
    let text = spiral_grammar().to_string().replace("4.0", "1e999");
    assert!(
        Grammar::from_json(&text)
            .unwrap_err()
            .to_string()
            .contains("number out of range")
    );
}

fn spiral_project() -> Value {
    serde_json::from_str(&demos::spiral_steps(true).unwrap().to_json()).unwrap()
}

#[test]
fn project_files_report_the_tree_path() {
    let mut p = spiral_project();
    p["rules"][0]["tree"]["cut"]["above"]["cut"]["point"] = json!([50.0, 0.0, 0.0]);
    assert_eq!(
        project_error(&p),
        "rules[0].tree.above: the cutting plane does not pass through the shape's interior (it \
         misses the shape, touches it or runs along a face)"
    );
    let mut p = spiral_project();
    p["rules"][0]["tree"]["cut"]["below"]["symbol"]["name"] = json!("B");
    assert_eq!(
        project_error(&p),
        "rules[0].tree.below: there is no symbol 'B'"
    );
    let mut p = spiral_project();
    p["rules"][0]["tree"]["cut"]["below"]["symbol"]["anchor"] = json!([9, 0]);
    assert_eq!(
        project_error(&p),
        "rules[0].tree.below: the anchor (face 9, corner 0) is not on the shape"
    );
    let mut p = spiral_project();
    p["rules"][0]["tree"]["cut"]["step"] = json!(1);
    assert_eq!(
        project_error(&p),
        "rules[0].tree: cut steps must number the rule's cuts 0 to 1 once each; found step 1"
    );
    let mut p = spiral_project();
    p["symbols"][0]["vertices"][7] = json!([4.0, 4.0, 5.0]);
    assert_eq!(project_error(&p), "symbols[0]: face 5 is not planar");
    let mut p = spiral_project();
    p["rules"][0]["symbol"] = json!("Nope");
    assert_eq!(
        project_error(&p),
        "rules[0].symbol: there is no symbol 'Nope'"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Replacing digits of a valid grammar gives a valid grammar or an error, and whatever
    /// loads also generates and meshes without panicking.
    #[test]
    fn edited_grammars_never_panic(edits in proptest::collection::vec((0usize..100_000, 0u8..10), 1..4)) {
        let mut text = compile(&demos::spiral_steps(true).unwrap()).unwrap().to_json().into_bytes();
        let digits: Vec<usize> = (0..text.len()).filter(|&i| text[i].is_ascii_digit()).collect();
        for (at, digit) in edits {
            text[digits[at % digits.len()]] = b'0' + digit;
        }
        let text = String::from_utf8(text).unwrap();
        if let Ok(grammar) = Grammar::from_json(&text) {
            if let Some(name) = grammar.symbol_names().first().map(|s| s.to_string()) {
                if let Ok(state) = GrammarState::new(&grammar, &name) {
                    let mut state = state.with_generations(4);
                    state.max_shapes = 1000;
                    let _ = state.generate_all();
                    let _ = shapegram_topo::GrammarMesh::new(&state).to_model();
                }
            }
        }
    }

    /// The same for project files.
    #[test]
    fn edited_projects_never_panic(edits in proptest::collection::vec((0usize..100_000, 0u8..10), 1..4)) {
        let mut text = demos::spiral_steps(true).unwrap().to_json().into_bytes();
        let digits: Vec<usize> = (0..text.len()).filter(|&i| text[i].is_ascii_digit()).collect();
        for (at, digit) in edits {
            text[digits[at % digits.len()]] = b'0' + digit;
        }
        let text = String::from_utf8(text).unwrap();
        if let Ok(project) = Project::from_json(&text) {
            let _ = compile(&project);
        }
    }
}
