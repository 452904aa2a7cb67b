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
    g["version"] = json!(3);
    assert_eq!(
        grammar_error(&g),
        "version: version 3 is not supported (this build reads versions 1 to 2)"
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
    // Coefficients off the edge, and coordinates so large that areas overflow, would make
    // faces vanish from the meshes without a word.
    let mut g = spiral_grammar();
    g["rules"][0]["virtual_vertices"][1][2] = json!(1e300);
    assert_eq!(
        grammar_error(&g),
        "rules[0].virtual_vertices[1].t: 1e300 is not between 0 and 1"
    );
    let mut g = spiral_grammar();
    g["shapes"][0]["vertices"][2] = json!([4.0, 4.0, 4e307]);
    assert_eq!(
        grammar_error(&g),
        "shapes[0].vertices[2]: a coordinate beyond ±1e15"
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
        if let Ok(grammar) = Grammar::from_json(&text)
            && let Some(name) = grammar.symbol_names().first().map(|s| s.to_string())
                && let Ok(state) = GrammarState::new(&grammar, &name) {
                    let mut state = state.with_generations(4);
                    state.max_shapes = 1000;
                    let _ = state.generate_all();
                    let _ = shapegram_topo::GrammarMesh::new(&state).to_model();
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

/// Runs `work` on another thread and fails the test if it takes longer than `seconds`: the
/// inputs below take milliseconds to check in linear time and minutes in quadratic time.
fn finishes_within<T: Send + 'static>(
    seconds: u64,
    work: impl FnOnce() -> T + Send + 'static,
) -> T {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || send.send(work()));
    receive
        .recv_timeout(std::time::Duration::from_secs(seconds))
        .expect("checking took too long (is a check quadratic in the input size?)")
}

/// A pyramid over an `n`-gon: faces (base first, then the sides) and positions.
fn pyramid(n: u32) -> (Vec<Vec<u32>>, Vec<[f64; 3]>) {
    let mut faces = vec![(0..n).rev().collect::<Vec<_>>()];
    faces.extend((0..n).map(|i| vec![i, (i + 1) % n, n]));
    let mut positions: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let angle = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            [angle.cos(), 0.0, -angle.sin()]
        })
        .collect();
    positions.push([0.0, 1.0, 0.0]);
    (faces, positions)
}

#[test]
fn huge_faces_and_lists_are_checked_in_linear_time() {
    // A face of 300,000 corners: checking its corners pairwise took minutes.
    let mut g = spiral_grammar();
    let (faces, _) = pyramid(300_000);
    g["symbols"].as_array_mut().unwrap().push(json!({
        "name": "Big", "vertex_count": 300_001, "faces": faces, "rules": []
    }));
    let text = g.to_string();
    let grammar = finishes_within(20, move || Grammar::from_json(&text)).unwrap();
    assert_eq!(grammar.symbols[2].faces[0].len(), 300_000);

    // 100,000 rules of one symbol, and 100,000 symbols: each rule was looked for in its
    // symbol's list, each name compared with every earlier one.
    let base = Grammar::from_json(&spiral_grammar().to_string()).unwrap();
    let mut many_rules = base.clone();
    many_rules.rules = vec![base.rules[0].clone(); 100_000];
    many_rules.symbols[0].rules = (0..100_000).collect();
    let mut many_symbols = base.clone();
    for k in 0..100_000 {
        let mut symbol = base.symbols[1].clone();
        symbol.name = Some(format!("S{k}"));
        many_symbols.symbols.push(symbol);
    }
    let results = finishes_within(20, move || [many_rules.validate(), many_symbols.validate()]);
    assert_eq!(results, [Ok(()), Ok(())]);
}

#[test]
fn repeated_corners_and_rules_are_refused() {
    let mut g = spiral_grammar();
    g["symbols"][0]["faces"][0] = json!([0, 3, 0, 1]);
    assert_eq!(
        grammar_error(&g),
        "symbols[0].faces: face 0: vertex 0 appears twice"
    );
    // A rule listed twice would be chosen twice as often as its weight says.
    let mut g = spiral_grammar();
    g["symbols"][0]["rules"] = json!([0, 0]);
    assert_eq!(
        grammar_error(&g),
        "symbols[0].rules[1]: rule 0 is listed twice"
    );
}

/// A project of one symbol, a pyramid over a `n`-gon, and `rules`.
fn pyramid_project(n: u32, rules: Vec<Value>) -> Value {
    let (faces, vertices) = pyramid(n);
    json!({
        "format": "shapegram-topo-project",
        "version": 1,
        "symbols": [{ "name": "P", "vertices": vertices, "faces": faces, "anchor": [0, 0] }],
        "rules": rules,
    })
}

#[test]
fn projects_too_big_for_memory_are_refused() {
    // Every rule copies its symbol's shape: 1,100 rules of a 2,001-vertex symbol would hold
    // 2.2 million vertices (a 60 kB file may name 40,000 rules of a larger one).
    let rule = json!({ "name": "r", "symbol": "P", "weight": 1.0, "tree": "terminal" });
    let p = pyramid_project(2000, vec![rule; 1100]);
    assert_eq!(
        project_error(&p),
        "rules[1048]: the rules' sub-shapes would hold more than 2097152 vertices together \
         (hand-made projects hold thousands)"
    );
    // Every cut adds two parts: 1,047 rules hold 2,095,047 vertices, the next one's root
    // 2,001 more, and its cut (a frustum and a pyramid) 6,001 more.
    let rule = json!({ "name": "r", "symbol": "P", "weight": 1.0, "tree": "terminal" });
    let mut rules = vec![rule; 1048];
    rules[1047]["tree"] = json!({ "cut": {
        "step": 0, "point": [0.0, 0.5, 0.0], "normal": [0.0, 1.0, 0.0],
        "below": "terminal", "above": "terminal" } });
    assert_eq!(
        project_error(&pyramid_project(2000, rules.clone())),
        "rules[1047].tree: the rules' sub-shapes would hold more than 2097152 vertices \
         together (hand-made projects hold thousands)"
    );
    // Three rules fewer (2,097,046 vertices) load.
    rules.drain(..3);
    let project = Project::from_json(&pyramid_project(2000, rules).to_string()).unwrap();
    assert_eq!(project.rules[1044].tree.nodes().len(), 3);
}

fn brick_grammar() -> Value {
    let text = compile(&demos::brick_house().unwrap()).unwrap().to_json();
    serde_json::from_str(&text).unwrap()
}

fn brick_project() -> Value {
    serde_json::from_str(&demos::brick_house().unwrap().to_json()).unwrap()
}

#[test]
fn bad_materials_and_offset_cuts_in_grammars_are_located() {
    let mut g = brick_grammar();
    g["materials"][0]["tile"] = json!([0.0, 1.0]);
    assert_eq!(
        grammar_error(&g),
        "materials[0]: material 'Brick': the tile size 0 × 1 must be two positive numbers of \
         metres"
    );
    let mut g = brick_grammar();
    g["materials"][1]["name"] = json!("Brick");
    assert_eq!(
        grammar_error(&g),
        "materials[1].name: the name 'Brick' is used twice"
    );
    let mut g = brick_grammar();
    g["materials"][2]["color"] = json!("stone");
    assert_eq!(
        grammar_error(&g),
        "materials[2].color: 'stone' is not a colour like '#3a6ea5'"
    );
    let mut g = brick_grammar();
    g["rules"][1]["sub_shapes"][0]["materials"][0] = json!(9);
    assert_eq!(
        grammar_error(&g),
        "rules[1].sub_shapes[0].materials[0]: material 9 does not exist (there are 4)"
    );
    let mut g = brick_grammar();
    g["rules"][1]["sub_shapes"][0]["from_faces"] = json!([0, 1]);
    assert_eq!(
        grammar_error(&g),
        "rules[1].sub_shapes[0].from_faces: 2 entries for 5 faces (give one per face, null for \
         none)"
    );
    let mut g = brick_grammar();
    g["rules"][1]["offset_cuts"][0]["distance"] = json!(-1.0);
    assert_eq!(
        grammar_error(&g),
        "rules[1].offset_cuts[0].distance: -1 is not a positive number of metres"
    );
    let mut g = brick_grammar();
    g["rules"][1]["offset_cuts"][1]["vertices"] = json!([6, 7]);
    assert_eq!(
        grammar_error(&g),
        "rules[1].offset_cuts[1].vertices: the vertices must be consecutive, ascending and after \
         the previous cut's"
    );
    let mut g = brick_grammar();
    g["rules"][1]["offset_cuts"][0]["face"] = json!([5, 6, 40]);
    assert_eq!(
        grammar_error(&g),
        "rules[1].offset_cuts[0].face[2]: vertex 40 does not exist before the cut (14 do)"
    );
}

/// The JSON path of the first cut with an offset under `node`, as project errors write it.
fn first_offset(node: &Value, path: String) -> Option<String> {
    let cut = node.get("cut")?;
    if cut.get("offset").is_some() {
        return Some(path);
    }
    first_offset(&cut["below"], format!("{path}.below"))
        .or_else(|| first_offset(&cut["above"], format!("{path}.above")))
}

/// The value at a project error's tree path under `root`.
fn at_path<'a>(root: &'a mut Value, path: &str) -> &'a mut Value {
    path.split('.')
        .filter(|s| !s.is_empty())
        .fold(root, |node, side| &mut node["cut"][side])
}

#[test]
fn bad_materials_and_offset_cuts_in_projects_are_located() {
    let mut p = brick_project();
    p["version"] = json!(3);
    assert_eq!(
        project_error(&p),
        "version: version 3 is not supported (this build reads versions 1 to 2)"
    );
    let mut p = brick_project();
    p["materials"][0]["color"] = Value::Null;
    p["materials"][0]["texture"] = Value::Null;
    assert_eq!(
        project_error(&p),
        "materials[0]: material 'Brick' needs a colour or a texture"
    );
    let mut p = brick_project();
    p["rules"][1]["face_materials"][0]["material"] = json!("Marble");
    assert_eq!(
        project_error(&p),
        "rules[1].face_materials[0]: there is no material 'Marble'"
    );
    let mut p = brick_project();
    p["rules"][1]["face_materials"][0]["face"] = json!(12);
    let node = p["rules"][1]["face_materials"][0]["node"].clone();
    assert_eq!(
        project_error(&p),
        format!("rules[1].face_materials[0]: node {node} has no face 12 (it has 6)")
    );
    // An offset whose plane is not the saved one: the file was edited by hand.
    let mut p = brick_project();
    let path = first_offset(&p["rules"][1]["tree"], String::new()).unwrap();
    at_path(&mut p["rules"][1]["tree"], &path)["cut"]["offset"]["distance"] = json!(0.5);
    assert_eq!(
        project_error(&p),
        format!("rules[1].tree{path}: the plane is not 0.5 m inside face 2 of the shape it cuts")
    );
    let mut p = brick_project();
    at_path(&mut p["rules"][1]["tree"], &path)["cut"]["offset"]["distance"] = json!(20.0);
    assert!(
        project_error(&p).starts_with(&format!(
            "rules[1].tree{path}: the cutting plane does not pass through"
        )),
        "{}",
        project_error(&p)
    );
}
