//! A goal grammar and its library as `shapegram derive … --library` takes them: the input is
//! split into files at lines `---` (the first the main grammar), each read in the notation its
//! text shows (the native one when it shows none), compiled as one library and derived under
//! small limits, the model measured and written.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_eval::Program;
use shapegram_fuzz::{default_lot, finish, render, small_limits};
use shapegram_syntax::{Diagnostic, Dialect, SourceFile, detect, parse_as};

fuzz_target!(|text: &str| {
    let sources: Vec<SourceFile> = text
        .split("\n---\n")
        .take(8)
        .enumerate()
        .map(|(i, part)| SourceFile::new(format!("g{i}.goal"), part))
        .collect();
    let parsed: Vec<_> = sources
        .iter()
        .map(|s| {
            let dialect = match detect(s.text()) {
                d @ (Dialect::Goal | Dialect::Michelangelo) => d,
                _ => Dialect::Goal,
            };
            parse_as(s, dialect)
        })
        .collect();
    let mut failed = false;
    for (p, s) in parsed.iter().zip(&sources) {
        render(s, &p.diagnostics);
        failed |= p.diagnostics.iter().any(Diagnostic::is_error);
    }
    if failed {
        return;
    }
    let names: Vec<String> = (0..sources.len()).map(|i| format!("g{i}")).collect();
    let grammars: Vec<_> = names
        .iter()
        .map(String::as_str)
        .zip(parsed.iter().map(|p| &p.grammar))
        .collect();
    let (program, diagnostics) = Program::compile_library(&grammars);
    for (k, d) in &diagnostics {
        render(&sources[*k], std::slice::from_ref(d));
    }
    let Some(program) = program else {
        return;
    };
    let mut options = small_limits();
    options.max_steps = 5_000;
    match shapegram_eval::derive(&program, &[default_lot()], &options) {
        Ok(derivation) => finish(&derivation.to_model()),
        Err(error) => {
            if let Some(diagnostic) = error.to_diagnostic() {
                let source = error
                    .file
                    .and_then(|k| sources.get(k))
                    .unwrap_or(&sources[0]);
                render(source, &[diagnostic]);
            }
        }
    }
});
