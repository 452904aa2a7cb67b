//! Checking a grammar on upload, with the engine's own parser and compiler, and computing its
//! rule index (research §4.2): a version is stored only when it compiles on its own as a goal
//! grammar; compile errors come back with their line and column.

use serde::Serialize;
use shapegram_eval::{LibraryOptions, Program};
use shapegram_syntax::{Diagnostic, SourceFile};
use utoipa::ToSchema;

use crate::store::IndexedRule;

/// Largest grammar text, in bytes.
pub const MAX_GRAMMAR_BYTES: usize = 256 * 1024;

/// A diagnostic of the parser or compiler.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct Problem {
    /// `error` or `warning`.
    pub severity: &'static str,
    pub message: String,
    /// 1-based line of the start of the span.
    pub line: usize,
    /// 1-based column (in characters) of the start of the span.
    pub column: usize,
    pub hints: Vec<String>,
}

/// A grammar that compiled: its rule index and warnings.
pub struct Checked {
    pub rules: Vec<IndexedRule>,
    pub warnings: Vec<Problem>,
}

fn problem(source: &SourceFile, d: &Diagnostic) -> Problem {
    let (line, column) = source.line_col(d.span.start);
    Problem {
        severity: if d.is_error() { "error" } else { "warning" },
        message: d.message.clone(),
        line,
        column,
        hints: d.hints.clone(),
    }
}

/// Parses (detecting the notation) and compiles `text` as a goal grammar on its own.
/// Errors: every diagnostic, errors first.
pub fn check(full_name: &str, text: &str) -> Result<Checked, Vec<Problem>> {
    let source = SourceFile::new(full_name, text);
    let parsed = shapegram_syntax::parse(&source);
    let mut diagnostics = parsed.diagnostics;
    let mut keys = None;
    if !diagnostics.iter().any(Diagnostic::is_error) {
        // On its own: a library grammar (rules without axioms, as most published grammars
        // are) compiles as well as one with axioms; and open, since other grammars will set
        // the attributes it reads.
        let options = LibraryOptions {
            repository_from: 1,
            open: true,
        };
        let (program, more) =
            Program::compile_library_with(&[(full_name, &parsed.grammar)], &options);
        diagnostics.extend(more.into_iter().map(|(_, d)| d));
        keys = program.as_ref().and_then(Program::goal_rule_keys);
        if program.is_some() && keys.is_none() {
            diagnostics.push(Diagnostic::error(
                "not a goal grammar: the repository stores goal grammars (see docs/goals.md)",
                shapegram_syntax::Span::new(0, 0),
            ));
        }
    }
    let mut problems: Vec<Problem> = diagnostics.iter().map(|d| problem(&source, d)).collect();
    problems.sort_by_key(|p| (p.severity != "error", p.line, p.column));
    match keys {
        Some(keys) if !problems.iter().any(|p| p.severity == "error") => Ok(Checked {
            rules: keys
                .into_iter()
                .enumerate()
                .map(|(i, k)| IndexedRule {
                    index: i as i64,
                    positive: k.positive,
                    negative: k.negative,
                    local: k.local,
                    conditional: k.conditional,
                })
                .collect(),
            warnings: problems,
        }),
        _ => {
            if problems.is_empty() {
                problems.push(Problem {
                    severity: "error",
                    message: "the grammar does not compile".into(),
                    line: 1,
                    column: 1,
                    hints: Vec::new(),
                });
            }
            Err(problems)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_have_lines_and_columns() {
        let errors = check(
            "ana/chair",
            "axiom chair size(1, 1, 1)\n\nfulfills(chair) --> split(\n",
        )
        .err()
        .expect("errors");
        assert_eq!(errors[0].severity, "error");
        assert_eq!(errors[0].line, 3, "{errors:?}");
    }

    #[test]
    fn a_goal_grammar_is_indexed() {
        let checked = check("ana/paint", "fulfills(wooden) --> color(\"#8B5A2B\")").unwrap();
        assert_eq!(checked.rules.len(), 1);
        assert_eq!(checked.rules[0].positive, ["g:wooden"]);
    }

    #[test]
    fn symbol_grammars_are_refused() {
        assert!(check("ana/lot", "Lot --> extrude(10) Mass").is_err());
    }
}
