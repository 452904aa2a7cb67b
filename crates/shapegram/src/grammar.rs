//! Reading, parsing and compiling a grammar file, with its diagnostics printed rustc-style.

use std::path::Path;

use shapegram_eval::{LibraryOptions, Program};
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
    /// The files read: the grammar, then the files it imports (what derivation errors point
    /// into).
    pub sources: Vec<SourceFile>,
}

impl Compiled {
    /// The program and the files read, or the failure `N errors in FILE` (the diagnostics have
    /// been printed).
    pub fn into_program(self) -> Result<(Program, Vec<SourceFile>), Failure> {
        match self.program {
            Some(program) if self.errors == 0 => Ok((program, self.sources)),
            _ => Err(Failure::new(error_summary(
                self.errors,
                self.sources[0].name(),
            ))),
        }
    }
}

/// `2 errors in house.cga`, the last line printed for a grammar with errors.
pub fn error_summary(errors: usize, file: &str) -> String {
    // A grammar without a program always has at least one error; say so even if the count is off.
    format!("{} in {file}", counted(errors.max(1), "error", "errors"))
}

/// Reads a grammar file (see [`shapegram_load::read`]), printing its warning when `warn` is set.
pub fn read(path: &Path, warn: bool) -> Result<SourceFile, Failure> {
    let read = shapegram_load::read(path).map_err(Failure::new)?;
    if warn && let Some(warning) = &read.warning {
        eprintln!("warning: {warning}");
    }
    Ok(read.source)
}

/// Parses and compiles a grammar in the given notation (`None`: detect it from the text) with
/// its imports ([`shapegram_load::compile`]) and prints its diagnostics on stderr: errors always,
/// warnings when `print_warnings`.
pub fn compile(source: &SourceFile, print_warnings: bool, dialect: Option<Dialect>) -> Compiled {
    let (compiled, diagnostics) = compile_silently(source, print_warnings, dialect);
    let mut text = String::new();
    for (file, d) in &diagnostics {
        if d.is_error() || print_warnings {
            text.push_str(&compiled.sources[*file].render(d));
            text.push('\n');
        }
    }
    eprint!("{text}");
    compiled
}

/// [`compile`] without printing: the diagnostics come back with the index of the source each
/// is in (0: the grammar). `warn` prints the warning for an imported file read as Windows-1252.
pub fn compile_silently(
    source: &SourceFile,
    warn: bool,
    dialect: Option<Dialect>,
) -> (Compiled, Vec<(usize, Diagnostic)>) {
    let compiled = shapegram_load::compile(source, dialect);
    if warn {
        for warning in &compiled.read_warnings {
            eprintln!("warning: {warning}");
        }
    }
    let errors = compiled.errors();
    let diagnostics = compiled.diagnostics;
    let compiled = Compiled {
        grammar: compiled.grammar,
        program: compiled.program,
        errors,
        warnings: diagnostics.len() - errors,
        sources: compiled.sources,
    };
    (compiled, diagnostics)
}

/// A goal grammar and its library, compiled into one program.
pub struct CompiledLibrary {
    /// The program, `None` when there were errors.
    pub program: Option<Program>,
    /// The sources, the main grammar first: what errors of the derivation point into.
    pub sources: Vec<SourceFile>,
    /// Number of errors.
    pub errors: usize,
    /// Number of warnings.
    pub warnings: usize,
    /// Goal rules in all files.
    pub rules: usize,
}

/// Whether `source` is a goal grammar: in `dialect` when given, else by its text, or by its
/// `.goal` extension.
pub fn is_goal_grammar(source: &SourceFile, dialect: Option<Dialect>) -> bool {
    goal_dialect(source, dialect).is_some()
}

/// The goal notation `source` is in (see [`is_goal_grammar`]); a `.goal` file without the
/// marks of either is read in the native one.
fn goal_dialect(source: &SourceFile, dialect: Option<Dialect>) -> Option<Dialect> {
    let goal = |d: Dialect| matches!(d, Dialect::Goal | Dialect::Michelangelo).then_some(d);
    match dialect {
        Some(d) => goal(d),
        None => goal(shapegram_syntax::detect(source.text()))
            .or_else(|| source.name().ends_with(".goal").then_some(Dialect::Goal)),
    }
}

/// A goal grammar (`source`, read from `main`) and the grammars of its library, read: the main
/// grammar first.
pub fn read_library(
    source: SourceFile,
    main: &Path,
    library: &[std::path::PathBuf],
    warn: bool,
) -> Result<Vec<SourceFile>, Failure> {
    let mut sources = vec![source];
    for path in library_files(library, main)? {
        sources.push(read(&path, warn)?);
    }
    Ok(sources)
}

/// The library a goal grammar derives with: the files given and the goal grammar files
/// (`*.goal`) in the folders given and their subfolders, sorted by path, without `main`.
fn library_files(
    paths: &[std::path::PathBuf],
    main: &Path,
) -> Result<Vec<std::path::PathBuf>, Failure> {
    let main_path = main;
    let main = std::fs::canonicalize(main).ok();
    let mut files = Vec::new();
    let mut pending = Vec::new();
    for path in paths {
        if path.is_dir() {
            pending.push(path.clone());
        } else if path.is_file() {
            if std::fs::canonicalize(path).ok() != main {
                files.push(path.clone());
            }
        } else {
            return Err(Failure::new(format!(
                "the library {} is neither a file nor a folder",
                path.display()
            )));
        }
    }
    while let Some(folder) = pending.pop() {
        let entries = std::fs::read_dir(&folder).map_err(|e| {
            Failure::new(format!(
                "cannot read the library folder {}: {e}",
                folder.display()
            ))
        })?;
        for entry in entries {
            let entry = entry
                .map_err(|e| Failure::new(format!("cannot read {}: {e}", folder.display())))?;
            let path = entry.path();
            // Links to folders are not followed: one could lead back up the tree.
            if entry.file_type().is_ok_and(|t| t.is_dir()) {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "goal")
                && std::fs::canonicalize(&path).ok() != main
            {
                files.push(path);
            }
        }
    }
    files.sort();
    // A file reached twice (named, and in a folder) is one grammar.
    let mut seen = std::collections::HashSet::new();
    files.retain(|f| seen.insert(std::fs::canonicalize(f).unwrap_or_else(|_| f.clone())));
    // Grammars are named by their file stems: two of one name would mix their rules' names.
    let mut stems: std::collections::HashMap<String, &Path> = std::collections::HashMap::new();
    stems.insert(stem(&main_path.display().to_string()), main_path);
    for file in &files {
        let name = stem(&file.display().to_string());
        if let Some(other) = stems.insert(name.clone(), file) {
            return Err(Failure::new(format!(
                "two library grammars are called `{name}`: {} and {}",
                other.display(),
                file.display()
            ))
            .with_hints(vec![
                "grammars are named by their file names: rename one".to_owned(),
            ]));
        }
    }
    Ok(files)
}

/// Parses and compiles a goal grammar (`sources[0]`) with its library (the rest), printing
/// the diagnostics of every file as [`compile`] does. A file's grammar is named by its file
/// stem.
pub fn compile_library(
    sources: Vec<SourceFile>,
    print_warnings: bool,
    dialect: Option<Dialect>,
) -> CompiledLibrary {
    let options = LibraryOptions::closed(sources.len());
    compile_library_with(sources, print_warnings, dialect, &options)
}

/// [`compile_library`] for a library that `options` says more of: the grammars from a
/// repository (named `owner/name@version`, their warnings not printed: they are not the
/// user's to fix) and whether others may join it.
pub fn compile_library_with(
    sources: Vec<SourceFile>,
    print_warnings: bool,
    dialect: Option<Dialect>,
    options: &LibraryOptions,
) -> CompiledLibrary {
    let (compiled, diagnostics) = compile_library_silently(sources, dialect, options);
    let mut text = String::new();
    for (i, d) in &diagnostics {
        if d.is_error() || (print_warnings && *i < options.repository_from) {
            text.push_str(&compiled.sources[*i].render(d));
            text.push('\n');
        }
    }
    eprint!("{text}");
    compiled
}

/// [`compile_library_with`] without printing: the diagnostics come back with the index of the
/// source each is in (0: the main grammar).
pub fn compile_library_silently(
    sources: Vec<SourceFile>,
    dialect: Option<Dialect>,
    options: &LibraryOptions,
) -> (CompiledLibrary, Vec<(usize, Diagnostic)>) {
    let parsed: Vec<shapegram_syntax::Parsed> = sources
        .iter()
        .enumerate()
        .map(|(i, source)| {
            let forced = if i == 0 { dialect } else { None };
            let dialect = goal_dialect(source, forced).unwrap_or(Dialect::Goal);
            shapegram_syntax::parse_as(source, dialect)
        })
        .collect();
    let mut diagnostics: Vec<(usize, Diagnostic)> = parsed
        .iter()
        .enumerate()
        .flat_map(|(i, p)| p.diagnostics.iter().map(move |d| (i, d.clone())))
        .collect();
    let names: Vec<String> = sources
        .iter()
        .enumerate()
        .map(|(i, s)| {
            if i < options.repository_from {
                stem(s.name())
            } else {
                s.name().to_owned()
            }
        })
        .collect();
    let program = if diagnostics.iter().any(|(_, d)| d.is_error()) {
        None
    } else {
        let grammars: Vec<(&str, &ast::Grammar)> = names
            .iter()
            .zip(&parsed)
            .map(|(n, p)| (n.as_str(), &p.grammar))
            .collect();
        let (program, more) = Program::compile_library_with(&grammars, options);
        diagnostics.extend(more);
        program
    };
    let errors = diagnostics.iter().filter(|(_, d)| d.is_error()).count();
    let compiled = CompiledLibrary {
        program,
        warnings: diagnostics.len() - errors,
        errors,
        rules: parsed.iter().map(|p| p.grammar.goal_rules.len()).sum(),
        sources,
    };
    (compiled, diagnostics)
}

/// `chair.goal` or `chair.goal and its library of 3 files`.
pub fn library_name(sources: &[SourceFile]) -> String {
    match sources.len() {
        1 => sources[0].name().to_owned(),
        n => format!(
            "{} and its library of {}",
            sources[0].name(),
            counted(n - 1, "file", "files")
        ),
    }
}

/// A grammar's name in a library: its file's stem.
fn stem(path: &str) -> String {
    Path::new(path)
        .file_stem()
        .map_or_else(|| path.to_owned(), |s| s.to_string_lossy().into_owned())
}
