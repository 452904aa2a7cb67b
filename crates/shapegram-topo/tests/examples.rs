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
