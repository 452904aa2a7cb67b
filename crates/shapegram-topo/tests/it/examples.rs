//! The shipped example grammars (`examples/topo_*`) are exactly what the demo code produces:
//! the project files as saved, the `.grammar` files as compiled. Run with `SHAPEGRAM_BLESS=1`
//! to rewrite them after changing a demo.

use std::path::PathBuf;

use shapegram_topo::{Grammar, Project, compile, demos};

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn check(name: &str, project: Project) {
    let project_path = examples().join(format!("{name}.sgproj.json"));
    let grammar_path = examples().join(format!("{name}.grammar"));
    let project_text = project.to_json();
    let grammar = compile(&project).unwrap();
    let grammar_text = grammar.to_json();
    if std::env::var_os("SHAPEGRAM_BLESS").is_some() {
        std::fs::write(&project_path, &project_text).unwrap();
        std::fs::write(&grammar_path, &grammar_text).unwrap();
    }
    let shipped_project = std::fs::read_to_string(&project_path).unwrap();
    let shipped_grammar = std::fs::read_to_string(&grammar_path).unwrap();
    assert!(
        shipped_project == project_text,
        "{} is out of date: run SHAPEGRAM_BLESS=1 cargo test -p shapegram-topo --test examples",
        project_path.display()
    );
    assert!(
        shipped_grammar == grammar_text,
        "{} is out of date: run SHAPEGRAM_BLESS=1 cargo test -p shapegram-topo --test examples",
        grammar_path.display()
    );
    let loaded = Project::from_json(&shipped_project).unwrap();
    assert_eq!(loaded, project);
    assert_eq!(compile(&loaded).unwrap(), grammar);
    assert_eq!(Grammar::from_json(&shipped_grammar).unwrap(), grammar);
}

#[test]
fn the_house_example_is_up_to_date() {
    check("topo_house", demos::house().unwrap());
}

#[test]
fn the_pyramid_example_is_up_to_date() {
    check("topo_pyramid", demos::mayan_pyramid().unwrap());
}

#[test]
fn the_spiral_steps_example_is_up_to_date() {
    check("topo_spiral_steps", demos::spiral_steps(true).unwrap());
}

#[test]
fn the_brick_house_example_is_up_to_date() {
    check("topo_brick_house", demos::brick_house().unwrap());
}

/// The project files as version 1 wrote them (the examples before materials and offset cuts),
/// kept byte for byte: they still open, as the same projects, and compile to the same grammars.
#[test]
fn version_1_projects_still_open() {
    let old = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/version1");
    for (name, project) in [
        ("topo_house", demos::house().unwrap()),
        ("topo_pyramid", demos::mayan_pyramid().unwrap()),
        ("topo_spiral_steps", demos::spiral_steps(true).unwrap()),
    ] {
        let text = std::fs::read_to_string(old.join(format!("{name}.sgproj.json"))).unwrap();
        assert!(text.contains("\n  \"version\": 1,\n"), "{name}");
        let loaded = Project::from_json(&text).unwrap();
        assert_eq!(loaded, project, "{name}");
        let grammar = std::fs::read_to_string(examples().join(format!("{name}.grammar"))).unwrap();
        assert_eq!(compile(&loaded).unwrap().to_json(), grammar, "{name}");
        // Saved again, it is a version 2 file that differs in its version alone.
        let saved = loaded.to_json();
        assert_eq!(
            saved,
            text.replace("\n  \"version\": 1,\n", "\n  \"version\": 2,\n"),
            "{name}"
        );
    }
}
