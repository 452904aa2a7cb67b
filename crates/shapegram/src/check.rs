//! `shapegram check`: parse and compile grammar files and report their diagnostics.

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
        let compiled = grammar::compile(&source, !args.quiet_warnings, args.dialect.dialect());
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
