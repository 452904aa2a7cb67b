//! `shapegram check`: parse and compile grammar files and report their diagnostics.

use std::path::Path;

use shapegram_syntax::SourceFile;

use crate::cli::CheckArgs;
use crate::grammar::{self, Input, error_summary};
use crate::{Failure, counted};

/// Checks every file, printing its diagnostics and one result line; fails if any file has
/// errors (or cannot be read).
pub fn run(args: &CheckArgs) -> Result<(), Failure> {
    let mut failed = 0;
    for path in &args.files {
        let inputs = if shapegram_load::is_package(path) {
            grammar::open_package_sources(path, !args.quiet_warnings)
        } else {
            grammar::open(path, None, !args.quiet_warnings).map(|input| vec![input])
        };
        let inputs = match inputs {
            Ok(inputs) => inputs,
            Err(failure) => {
                failure.print();
                failed += 1;
                continue;
            }
        };
        for input in inputs {
            failed += usize::from(!check(input, path, args)?);
        }
    }
    if failed > 0 {
        Err(Failure::reported())
    } else {
        Ok(())
    }
}

/// Checks one grammar, printing its diagnostics and result line; returns whether it has no
/// errors.
fn check(input: Input, path: &Path, args: &CheckArgs) -> Result<bool, Failure> {
    let dialect = args.dialect.dialect();
    if grammar::is_goal_grammar(&input.source, dialect) {
        return check_goals(input.source, path, args);
    }
    let source = &input.source;
    let compiled = grammar::compile(&input, !args.quiet_warnings, dialect);
    if compiled.program.is_some() && compiled.errors == 0 {
        eprintln!(
            "ok: {} ({}, {}, {})",
            source.name(),
            counted(compiled.grammar.rules.len(), "rule", "rules"),
            counted(compiled.grammar.attrs.len(), "attribute", "attributes"),
            counted(compiled.warnings, "warning", "warnings"),
        );
        Ok(true)
    } else {
        eprintln!("error: {}", error_summary(compiled.errors, source.name()));
        Ok(false)
    }
}

/// Checks a goal grammar with its library; returns whether it has no errors.
fn check_goals(source: SourceFile, path: &Path, args: &CheckArgs) -> Result<bool, Failure> {
    let sources = grammar::read_library(source, path, &args.library, !args.quiet_warnings)?;
    let library = sources.len() - 1;
    let compiled = grammar::compile_library(sources, !args.quiet_warnings, args.dialect.dialect());
    let name = compiled.sources[0].name();
    if compiled.program.is_some() && compiled.errors == 0 {
        let with = match library {
            0 => String::new(),
            n => format!(" with a library of {}", counted(n, "file", "files")),
        };
        eprintln!(
            "ok: {name}{with} ({}, {})",
            counted(compiled.rules, "goal rule", "goal rules"),
            counted(compiled.warnings, "warning", "warnings"),
        );
        Ok(true)
    } else {
        eprintln!("error: {}", error_summary(compiled.errors, name));
        Ok(false)
    }
}
