//! Reading, parsing and compiling a grammar file, with its diagnostics printed rustc-style.

use std::path::Path;

use shapegram_eval::Program;
use shapegram_syntax::{Diagnostic, Dialect, SourceFile, ast};

use crate::{Failure, counted};

/// A grammar file after parsing and compiling.
pub struct Compiled {
    /// The parsed grammar (possibly incomplete when there were parse errors).
    pub grammar: ast::Grammar,
    /// The program, `None` when there were errors.
    pub program: Option<Program>,
    /// Number of errors.
    pub errors: usize,
    /// Number of warnings.
    pub warnings: usize,
}

impl Compiled {
    /// The program, or the failure `N errors in FILE` (the diagnostics have been printed).
    pub fn into_program(self, source: &SourceFile) -> Result<Program, Failure> {
        match self.program {
            Some(program) if self.errors == 0 => Ok(program),
            _ => Err(Failure::new(error_summary(self.errors, source.name()))),
        }
    }
}

/// `2 errors in house.cga`, the last line printed for a grammar with errors.
pub fn error_summary(errors: usize, file: &str) -> String {
    // A grammar without a program always has at least one error; say so even if the count is off.
    format!("{} in {file}", counted(errors.max(1), "error", "errors"))
}

/// Reads a grammar file, named by the path as given: UTF-8 text (a byte-order mark dropped),
/// or else Windows-1252, which CityEngine writes on Windows (Latin-1 files read the same but
/// for bytes 0x80–0x9F, which Latin-1 leaves to control characters). Reading it so prints a
/// warning when `warn` is set.
pub fn read(path: &Path, warn: bool) -> Result<SourceFile, Failure> {
    let name = path.display().to_string();
    let bytes =
        std::fs::read(path).map_err(|e| Failure::new(format!("cannot read {name}: {e}")))?;
    let text = match String::from_utf8(bytes) {
        Ok(mut text) => {
            if text.starts_with('\u{feff}') {
                text.drain(..'\u{feff}'.len_utf8());
            }
            text
        }
        Err(e) => {
            let at = e.utf8_error().valid_up_to();
            if warn {
                eprintln!(
                    "warning: {name} is not UTF-8 (byte {at}): read as Windows-1252, as CityEngine writes rule files on Windows"
                );
            }
            let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(e.as_bytes());
            text.into_owned()
        }
    };
    Ok(SourceFile::new(name, text))
}

/// Parses and compiles a grammar in the given notation (`None`: detect it from the text) and
/// prints its diagnostics on stderr: errors always, warnings when `print_warnings`. A grammar
/// with parse errors is not compiled, so that declarations the parser had to skip do not show up
/// again as unknown names.
pub fn compile(source: &SourceFile, print_warnings: bool, dialect: Option<Dialect>) -> Compiled {
    let parsed = match dialect {
        Some(dialect) => shapegram_syntax::parse_as(source, dialect),
        None => shapegram_syntax::parse(source),
    };
    let mut diagnostics = parsed.diagnostics;
    let program = if diagnostics.iter().any(Diagnostic::is_error) {
        None
    } else {
        let (program, more) = Program::compile(&parsed.grammar);
        diagnostics.extend(more);
        program
    };
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    let mut text = String::new();
    for d in &diagnostics {
        if d.is_error() || print_warnings {
            text.push_str(&source.render(d));
            text.push('\n');
        }
    }
    eprint!("{text}");
    Compiled {
        grammar: parsed.grammar,
        program,
        errors,
        warnings: diagnostics.len() - errors,
    }
}
