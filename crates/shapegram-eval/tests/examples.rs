//! Every grammar in `examples/` compiles without errors and derives the model it promises.

mod common;

use std::path::PathBuf;

use shapegram_eval::{DeriveOptions, Program, derive};
use shapegram_syntax::{SourceFile, parse};

fn example(name: &str) -> Program {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let source = SourceFile::new(name, text);
    let parsed = parse(&source);
    let (program, diagnostics) = Program::compile(&parsed.grammar);
    let all: Vec<String> = parsed
        .diagnostics
        .iter()
        .chain(&diagnostics)
        .map(|d| source.render(d))
        .collect();
    assert!(all.is_empty(), "{}", all.join("\n"));
    program.unwrap()
}

#[test]
fn office() {
    let program = example("office.cga");
    let d = derive(
        &program,
        &[common::lot(20.0, 30.0)],
        &DeriveOptions::default(),
    )
    .unwrap();
    assert_eq!(d.stats.leaves, 1047);
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    // Four facades of 8 floors; the 16 m wide tower faces hold 5 tiles, the 24 m ones 7.
    assert_eq!(count("Floor"), Some(32));
    assert_eq!(count("Tile"), Some(8 * 2 * (5 + 7)));
    assert_eq!(count("Shop"), Some(3));
    let bounds = d.to_model().bounds().unwrap();
    // Podium 5 m + 8 floors of 3.4 m + a 1.2 m roof box.
    assert!((bounds.max.y - 33.4).abs() < 1e-9, "{:?}", bounds.max);
    assert!((bounds.size().x - 20.0).abs() < 1e-9 && (bounds.size().z - 30.0).abs() < 1e-9);
}
