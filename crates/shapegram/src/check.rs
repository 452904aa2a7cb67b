//! `shapegram check`: parse and compile grammar files and report their diagnostics.

use std::path::Path;

use shapegram_syntax::SourceFile;

use crate::cli::CheckArgs;
use crate::grammar::{self, error_summary};
use crate::{Failure, counted};

/// Checks every file, printing its diagnostics and one result line; fails if any file has
/// errors (or cannot be read).
pub fn run(args: &CheckArgs) -> Result<(), Failure> {
    let mut failed = 0;
    for path in &args.files {
        let source = match grammar::read(path, !args.quiet_warnings) {
            Ok(source) => source,
            Err(failure) => {
                if let Some(message) = failure.message {
                    eprintln!("error: {message}");
                }
                failed += 1;
                continue;
            }
        };
        let dialect = args.dialect.dialect();
        if grammar::is_goal_grammar(&source, dialect) {
            failed += usize::from(!check_goals(source, path, args)?);
            continue;
        }
        let compiled = grammar::compile(&source, !args.quiet_warnings, dialect);
        if compiled.program.is_some() && compiled.errors == 0 {
            eprintln!(
                "ok: {} ({}, {}, {})",
                source.name(),
                counted(compiled.grammar.rules.len(), "rule", "rules"),
                counted(compiled.grammar.attrs.len(), "attribute", "attributes"),
                counted(compiled.warnings, "warning", "warnings"),
            );
        } else {
            eprintln!("error: {}", error_summary(compiled.errors, source.name()));
            failed += 1;
        }
    }
    if failed > 0 {
        Err(Failure::reported())
    } else {
        Ok(())
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
