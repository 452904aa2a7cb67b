//! Reading, parsing and compiling a grammar file, with its diagnostics printed rustc-style.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use shapegram_eval::{LibraryOptions, Program};
use shapegram_load::{FileAssets, Files, MissingAssets, NameClash, PackageError, RulePackage};
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

/// A grammar as the command line names it: a grammar file, or a rule file of a rule package
/// (`.rpk`), with where its imports and assets are.
pub struct Input {
    /// The grammar's text, named as messages name it (`package.rpk!/rules/a.cga` in a package).
    pub source: SourceFile,
    /// Where the grammar, its imports and its assets are read from.
    pub files: Files,
    /// The grammar's path in `files`.
    pub path: PathBuf,
}

impl Input {
    /// The assets of the grammar's derivation: files found as CityEngine finds them, beside
    /// the grammar, in its project, in the workspace (see [`FileAssets`]).
    pub fn assets(&self, missing: MissingAssets) -> FileAssets {
        match &self.files {
            Files::Disk => FileAssets::new(
                self.path.parent().unwrap_or(Path::new("")).to_path_buf(),
                missing,
            ),
            Files::Package(package) => {
                FileAssets::in_package(Arc::clone(package), &self.path.to_string_lossy(), missing)
            }
        }
    }
}

/// The grammar at `path`: the file itself, or for a rule package the rule file `rule_file`
/// names, else the one PRT runs ([`RulePackage::rule_file`]). `--rule-file` is only for
/// packages.
pub fn open(path: &Path, rule_file: Option<&str>, warn: bool) -> Result<Input, Failure> {
    if !shapegram_load::is_package(path) {
        if rule_file.is_some() {
            return Err(Failure::usage(format!(
                "--rule-file picks a rule file of a rule package (.rpk); {} is a grammar file",
                path.display()
            )));
        }
        return Ok(Input {
            source: read(path, warn)?,
            files: Files::Disk,
            path: path.to_path_buf(),
        });
    }
    let package = open_package(path)?;
    let entry = package.rule_file(rule_file).map_err(package_failure)?;
    read_package_file(package, entry, warn)
}

/// Every rule source of the rule package at `path` (`rules/**/*.cga`), in the order of their
/// paths.
pub fn open_package_sources(path: &Path, warn: bool) -> Result<Vec<Input>, Failure> {
    let package = open_package(path)?;
    let sources: Vec<String> = package
        .runnable_sources()
        .map_err(package_failure)?
        .into_iter()
        .map(str::to_owned)
        .collect();
    sources
        .into_iter()
        .map(|entry| read_package_file(Arc::clone(&package), entry, warn))
        .collect()
}

/// Reads the rule package at `path` into memory.
fn open_package(path: &Path) -> Result<Arc<RulePackage>, Failure> {
    RulePackage::open(path)
        .map(Arc::new)
        .map_err(package_failure)
}

/// The rule file `entry` of `package`, read.
fn read_package_file(
    package: Arc<RulePackage>,
    entry: String,
    warn: bool,
) -> Result<Input, Failure> {
    let files = Files::Package(package);
    let path = PathBuf::from(entry);
    let read = shapegram_load::read_in(&files, &path).map_err(Failure::new)?;
    if warn && let Some(warning) = &read.warning {
        eprintln!("warning: {warning}");
    }
    Ok(Input {
        source: read.source,
        files,
        path,
    })
}

/// A package's error as the command's failure, with its hint.
fn package_failure(error: PackageError) -> Failure {
    Failure::new(error.message).with_hints(error.hint)
}

/// Parses and compiles a grammar in the given notation (`None`: detect it from the text) with
/// its imports, read from where the grammar is ([`shapegram_load::compile_in`]), and prints its
/// diagnostics on stderr: errors always, warnings when `print_warnings`.
pub fn compile(input: &Input, print_warnings: bool, dialect: Option<Dialect>) -> Compiled {
    let compiled = shapegram_load::compile_in(&input.source, dialect, &input.files, &input.path);
    print_compiled(compiled, print_warnings)
}

/// [`compile`] in the grammar's CGA style `style` (see [`shapegram_load::compile_in_style`]);
/// a style the grammar does not declare is a usage error.
pub fn compile_style(
    input: &Input,
    print_warnings: bool,
    dialect: Option<Dialect>,
    style: &str,
) -> Result<Compiled, Failure> {
    let compiled =
        shapegram_load::compile_in_style(&input.source, dialect, &input.files, &input.path, style)
            .map_err(|message| Failure::usage(format!("--style: {message}")))?;
    Ok(print_compiled(compiled, print_warnings))
}

/// Prints a compiled grammar's diagnostics on stderr: errors always, warnings when
/// `print_warnings`.
fn print_compiled(compiled: shapegram_load::Compiled, print_warnings: bool) -> Compiled {
    let (compiled, diagnostics) = summarize(compiled, print_warnings);
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
    let input = Input {
        source: source.clone(),
        files: Files::Disk,
        path: PathBuf::from(source.name()),
    };
    compile_silently_in(&input, warn, dialect)
}

/// [`compile_silently`] for a grammar that may come from a rule package.
pub fn compile_silently_in(
    input: &Input,
    warn: bool,
    dialect: Option<Dialect>,
) -> (Compiled, Vec<(usize, Diagnostic)>) {
    let compiled = shapegram_load::compile_in(&input.source, dialect, &input.files, &input.path);
    summarize(compiled, warn)
}

/// A compiled grammar with its diagnostics counted; `warn` prints the warnings of reading its
/// imported files.
fn summarize(
    compiled: shapegram_load::Compiled,
    warn: bool,
) -> (Compiled, Vec<(usize, Diagnostic)>) {
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
/// `.goal` extension (see [`shapegram_load::goal_dialect`]).
pub fn is_goal_grammar(source: &SourceFile, dialect: Option<Dialect>) -> bool {
    shapegram_load::goal_dialect(source, dialect).is_some()
}

/// A goal grammar (`source`, read from `main`) and the grammars of its library, read: the main
/// grammar first.
pub fn read_library(
    source: SourceFile,
    main: &Path,
    library: &[PathBuf],
    warn: bool,
) -> Result<Vec<SourceFile>, Failure> {
    let mut sources = vec![source];
    for path in library_files(library, main)? {
        sources.push(read(&path, warn)?);
    }
    Ok(sources)
}

/// The library a goal grammar derives with ([`shapegram_load::library_files`]), its grammars'
/// names checked before any is read.
fn library_files(paths: &[PathBuf], main: &Path) -> Result<Vec<PathBuf>, Failure> {
    let files = shapegram_load::library_files(paths, main).map_err(Failure::new)?;
    let names: Vec<String> = std::iter::once(main)
        .chain(files.iter().map(PathBuf::as_path))
        .map(|path| path.display().to_string())
        .collect();
    shapegram_load::check_library_names(names.iter().map(String::as_str)).map_err(|clash| {
        Failure::new(clash.to_string()).with_hints([NameClash::HINT.to_owned()])
    })?;
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

/// [`compile_library_with`] without printing ([`shapegram_load::compile_library`]): the
/// diagnostics come back with the index of the source each is in (0: the main grammar).
pub fn compile_library_silently(
    sources: Vec<SourceFile>,
    dialect: Option<Dialect>,
    options: &LibraryOptions,
) -> (CompiledLibrary, Vec<(usize, Diagnostic)>) {
    let compiled = shapegram_load::compile_library(sources, dialect, options);
    let errors = compiled.errors();
    let compiled_library = CompiledLibrary {
        program: compiled.program,
        sources: compiled.sources,
        errors,
        warnings: compiled.diagnostics.len() - errors,
        rules: compiled.rules,
    };
    (compiled_library, compiled.diagnostics)
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
