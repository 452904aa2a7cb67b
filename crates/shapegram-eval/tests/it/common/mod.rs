//! Running grammar text through parser, compiler and engine.
#![allow(dead_code)]

pub mod generated;

use std::path::PathBuf;

use shapegram_eval::{
    Derivation, DeriveError, DeriveOptions, InitialShape, Program, Value, derive,
};
use shapegram_geom::DVec2;
use shapegram_syntax::{Dialect, SourceFile, parse};

/// The compiled program; panics with the rendered diagnostics on errors.
pub fn compile(text: &str) -> Program {
    let source = SourceFile::new("test.cga", text);
    let parsed = parse(&source);
    let render = |ds: &[shapegram_syntax::Diagnostic]| {
        ds.iter()
            .map(|d| source.render(d))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert!(
        !parsed.diagnostics.iter().any(|d| d.is_error()),
        "{}",
        render(&parsed.diagnostics)
    );
    let (program, diagnostics) = Program::compile(&parsed.grammar);
    program.unwrap_or_else(|| panic!("{}", render(&diagnostics)))
}

/// The diagnostics of compiling, rendered.
pub fn compile_errors(text: &str) -> Vec<String> {
    let source = SourceFile::new("test.cga", text);
    let parsed = parse(&source);
    let (_, diagnostics) = Program::compile(&parsed.grammar);
    parsed
        .diagnostics
        .iter()
        .chain(&diagnostics)
        .map(|d| source.render(d))
        .collect()
}

/// A `w` × `d` lot at the origin.
pub fn lot(w: f64, d: f64) -> InitialShape {
    InitialShape::from_xz(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(w, 0.0),
        DVec2::new(w, d),
        DVec2::new(0.0, d),
    ])
    .unwrap()
}

/// `count` lots of `w` × `d` in a row along x, each `step` from the last.
pub fn lots_in_a_row(count: u32, w: f64, d: f64, step: f64) -> Vec<InitialShape> {
    (0..count)
        .map(|i| {
            let x = f64::from(i) * step;
            InitialShape::from_xz(&[
                DVec2::new(x, 0.0),
                DVec2::new(x + w, 0.0),
                DVec2::new(x + w, d),
                DVec2::new(x, d),
            ])
            .unwrap()
        })
        .collect()
}

/// Derives `program` on `lots` in a pool of `threads` threads (results must not depend on it).
pub fn derive_on_threads(
    program: &Program,
    lots: &[InitialShape],
    options: &DeriveOptions,
    threads: usize,
) -> Derivation {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| derive(program, lots, options).unwrap())
}

/// Derives `text` on one lot with default options.
pub fn run(text: &str, lot: InitialShape) -> Derivation {
    try_run(text, lot, &DeriveOptions::default()).unwrap()
}

/// Derives `text` on one lot.
pub fn try_run(
    text: &str,
    lot: InitialShape,
    options: &DeriveOptions,
) -> Result<Derivation, DeriveError> {
    derive(&compile(text), &[lot], options)
}

/// Leaf names in order.
pub fn names(d: &Derivation) -> Vec<&str> {
    d.leaves.iter().map(|l| d.name(l.name)).collect()
}

/// The project's `examples/` folder.
pub fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Compiles grammar text, asserting that it has no diagnostics at all, not even warnings;
/// returns the program and the notation it was read in.
pub fn compile_clean(name: &str, text: &str) -> (Program, Dialect) {
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
    (program.expect("no errors"), parsed.grammar.dialect)
}

/// The grammar `examples/<name>`, compiled without diagnostics.
pub fn example(name: &str) -> Program {
    let path = examples().join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    compile_clean(name, &text).0
}

/// Goal grammars compiled as one library, the first the main one: `(name, text)` pairs, each
/// read as the file `name.goal` in the notation its text shows (the native one when it shows
/// none). Returns the program, or the rendered diagnostics when there are errors (or, when
/// `strict`, any diagnostic at all).
pub fn goal_library(files: &[(&str, &str)], strict: bool) -> Result<Program, String> {
    goal_library_with_repository(files, files.len(), strict)
}

/// [`goal_library`] where the grammars from `repository_from` on came from a repository.
pub fn goal_library_with_repository(
    files: &[(&str, &str)],
    repository_from: usize,
    strict: bool,
) -> Result<Program, String> {
    let sources: Vec<SourceFile> = files
        .iter()
        .map(|(n, t)| SourceFile::new(format!("{n}.goal"), *t))
        .collect();
    let parsed: Vec<_> = sources
        .iter()
        .map(|s| {
            let dialect = match shapegram_syntax::detect(s.text()) {
                d @ (Dialect::Goal | Dialect::Michelangelo) => d,
                _ => Dialect::Goal,
            };
            shapegram_syntax::parse_as(s, dialect)
        })
        .collect();
    let mut diagnostics: Vec<(usize, shapegram_syntax::Diagnostic)> = parsed
        .iter()
        .enumerate()
        .flat_map(|(k, p)| p.diagnostics.iter().map(move |d| (k, d.clone())))
        .collect();
    let mut program = None;
    if !diagnostics.iter().any(|(_, d)| d.is_error()) {
        let grammars: Vec<(&str, &shapegram_syntax::ast::Grammar)> = files
            .iter()
            .zip(&parsed)
            .map(|((n, _), p)| (*n, &p.grammar))
            .collect();
        let options = shapegram_eval::LibraryOptions {
            repository_from,
            open: false,
        };
        let (compiled, more) = Program::compile_library_with(&grammars, &options);
        program = compiled;
        diagnostics.extend(more);
    }
    let shown: Vec<String> = diagnostics
        .iter()
        .filter(|(_, d)| strict || d.is_error())
        .map(|(k, d)| sources[*k].render(d))
        .collect();
    match program {
        Some(program) if shown.is_empty() => Ok(program),
        _ => Err(shown.join("\n")),
    }
}

/// The basic chair of the goal grammar paper (seed 003, Figure 2 left) in the native notation.
pub const NATIVE_CHAIR: &str = r#"
local "split-legs"
axiom chair, wooden size(0.4, 0.8, 0.4)

fulfills(chair) -->
    split(y) { ~0.4 : set(@Leg.Size, rand(0.03, 0.05)) +support
             | ~0.05 : +seat
             | ~0.55 : +lean }

using is(chair) {
    fulfills(support) --> split(x) { @Leg.Size : +"split-legs" | ~1 : void | @Leg.Size : +"split-legs" }
    fulfills("split-legs") --> split(z) { @Leg.Size : +leg | ~1 : void | @Leg.Size : +leg }
    fulfills(lean) --> s('1, '1, 0.04)
}
"#;

/// A grammar that makes wooden things brown.
pub const WOOD: &str = r##"fulfills(wooden) --> color("#8b5a2b")"##;

/// The `(key, number)` reports of `text` derived on `lot`; booleans count as 0 or 1.
pub fn numeric_reports(text: &str, lot: InitialShape) -> Vec<(String, f64)> {
    let d = try_run(text, lot, &DeriveOptions::default()).unwrap();
    d.reports
        .into_iter()
        .map(|(k, v)| match v {
            Value::Number(n) => (k, n),
            Value::Bool(b) => (k, f64::from(u8::from(b))),
            v => panic!("{v:?}"),
        })
        .collect()
}

/// The reported numbers under `key`.
pub fn of(reports: &[(String, f64)], key: &str) -> Vec<f64> {
    reports
        .iter()
        .filter(|(k, _)| k == key)
        .map(|(_, v)| *v)
        .collect()
}

/// Asserts two lists of numbers agree within 1e-9.
pub fn assert_close(actual: &[f64], expected: &[f64]) {
    assert_eq!(actual.len(), expected.len(), "{actual:?} != {expected:?}");
    for (a, e) in actual.iter().zip(expected) {
        assert!((a - e).abs() < 1e-9, "{actual:?} != {expected:?}");
    }
}
