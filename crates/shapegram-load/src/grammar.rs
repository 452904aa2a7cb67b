//! Reading grammar files and the files they import, and compiling them into a program.

use std::path::Path;

use shapegram_eval::Program;
use shapegram_syntax::{Diagnostic, Dialect, SourceFile, ast};

use crate::files::Files;

/// A grammar file's text, and the warning reading it gave.
pub struct Read {
    /// The text, named by the path as given.
    pub source: SourceFile,
    /// Set when the file was not UTF-8 and was read as Windows-1252.
    pub warning: Option<String>,
}

/// Reads a grammar file, named by the path as given: UTF-8 text (a byte-order mark dropped),
/// or else Windows-1252, which CityEngine writes on Windows (Latin-1 files read the same but
/// for bytes 0x80–0x9F, which Latin-1 leaves to control characters), with a warning.
pub fn read(path: &Path) -> Result<Read, String> {
    read_in(&Files::Disk, path)
}

/// [`read`] for a file of `files`, named as `files` displays it (`package.rpk!/rules/a.cga`).
pub fn read_in(files: &Files, path: &Path) -> Result<Read, String> {
    let name = files.display(path);
    let bytes = files.read(path)?;
    let (text, warning) = match String::from_utf8(bytes) {
        Ok(mut text) => {
            if text.starts_with('\u{feff}') {
                text.drain(..'\u{feff}'.len_utf8());
            }
            (text, None)
        }
        Err(e) => {
            let at = e.utf8_error().valid_up_to();
            let warning = format!(
                "{name} is not UTF-8 (byte {at}): read as Windows-1252, as CityEngine writes rule files on Windows"
            );
            let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(e.as_bytes());
            (text.into_owned(), Some(warning))
        }
    };
    Ok(Read {
        source: SourceFile::new(name, text),
        warning,
    })
}

/// A grammar file after parsing and compiling, with the files it imports.
pub struct Compiled {
    /// The parsed grammar (possibly incomplete when there were parse errors).
    pub grammar: ast::Grammar,
    /// The program, `None` when there were errors.
    pub program: Option<Program>,
    /// Errors and warnings, each with the file it is in (an index into `sources`).
    pub diagnostics: Vec<(usize, Diagnostic)>,
    /// The files read: the grammar, then the files it imports (what derivation errors point
    /// into).
    pub sources: Vec<SourceFile>,
    /// Warnings from reading imported files (see [`read`]), in the order they were read.
    pub read_warnings: Vec<String>,
}

impl Compiled {
    /// Number of errors.
    pub fn errors(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|(_, d)| d.is_error())
            .count()
    }
}

/// Parses and compiles a grammar in the given notation (`None`: detect it from the text), with
/// the files it imports (see [`import_path`]). A grammar with parse errors is not compiled, so
/// that declarations the parser had to skip do not show up again as unknown names.
pub fn compile(source: &SourceFile, dialect: Option<Dialect>) -> Compiled {
    compile_in(source, dialect, &Files::Disk, Path::new(source.name()))
}

/// [`compile`] for a grammar read from `path` in `files` (see [`read_in`]): its imports are
/// looked for there.
pub fn compile_in(
    source: &SourceFile,
    dialect: Option<Dialect>,
    files: &Files,
    path: &Path,
) -> Compiled {
    compile_parsed(source, parse(source, dialect), files, path)
}

/// [`compile_in`] in the grammar's CGA style `style` ([`ast::Grammar::with_style`]): its
/// declarations laid over the default style's, the default style itself for `Default`. A
/// style the grammar does not declare is an error (the message names the styles there are);
/// the warnings that the chosen styles are not derived are left out.
pub fn compile_in_style(
    source: &SourceFile,
    dialect: Option<Dialect>,
    files: &Files,
    path: &Path,
    style: &str,
) -> Result<Compiled, String> {
    let mut parsed = parse(source, dialect);
    let styled = parsed.grammar.with_style(style)?;
    let chosen = style_chain(&parsed.grammar, style);
    parsed
        .diagnostics
        .retain(|d| d.is_error() || !chosen.contains(&d.span));
    parsed.grammar = styled;
    Ok(compile_parsed(source, parsed, files, path))
}

/// The spans of style `name` and of the styles it extends.
fn style_chain(grammar: &ast::Grammar, name: &str) -> Vec<shapegram_syntax::Span> {
    let mut spans = Vec::new();
    let mut next = Some(name);
    while let Some(style) = next.and_then(|n| grammar.styles.iter().find(|s| s.name.name == n)) {
        if spans.contains(&style.span) {
            break;
        }
        spans.push(style.span);
        next = style.base.as_ref().map(|b| b.name.as_str());
    }
    spans
}

/// Parses a grammar in the given notation (`None`: detect it from the text).
fn parse(source: &SourceFile, dialect: Option<Dialect>) -> shapegram_syntax::Parsed {
    match dialect {
        Some(dialect) => shapegram_syntax::parse_as(source, dialect),
        None => shapegram_syntax::parse(source),
    }
}

/// Compiles a parsed grammar with the files it imports.
fn compile_parsed(
    source: &SourceFile,
    parsed: shapegram_syntax::Parsed,
    files: &Files,
    path: &Path,
) -> Compiled {
    let mut diagnostics: Vec<(usize, Diagnostic)> =
        parsed.diagnostics.into_iter().map(|d| (0, d)).collect();
    let mut sources = vec![source.clone()];
    let mut read_warnings = Vec::new();
    let program = if diagnostics.iter().any(|(_, d)| d.is_error()) {
        None
    } else if parsed.grammar.imports.is_empty() {
        let (program, more) = Program::compile(&parsed.grammar);
        diagnostics.extend(more.into_iter().map(|d| (0, d)));
        program
    } else {
        let imported = load_imports(files, path, &parsed.grammar);
        diagnostics.extend(imported.diagnostics);
        sources.extend(imported.sources);
        read_warnings = imported.warnings;
        if diagnostics.iter().any(|(_, d)| d.is_error()) {
            None
        } else {
            let files: Vec<&ast::Grammar> = std::iter::once(&parsed.grammar)
                .chain(&imported.grammars)
                .collect();
            let graph = shapegram_eval::ImportGraph {
                files: &files,
                links: &imported.links,
            };
            let (mut program, more) = Program::compile_imports(graph);
            diagnostics.extend(more);
            if let Some(program) = &mut program {
                let folder = |file: &Path| file.parent().unwrap_or(Path::new("")).to_path_buf();
                let main = folder(path);
                let folders = std::iter::once(String::new())
                    .chain(
                        imported
                            .paths
                            .iter()
                            .map(|p| crate::files::relative(&main, &folder(p))),
                    )
                    .collect();
                program.set_file_folders(folders);
            }
            program
        }
    };
    Compiled {
        grammar: parsed.grammar,
        program,
        diagnostics,
        sources,
        read_warnings,
    }
}

/// The files a grammar imports, read and parsed, each once.
struct Imported {
    /// The imported files, in the order they were found (file `i + 1` of the import graph).
    sources: Vec<SourceFile>,
    grammars: Vec<ast::Grammar>,
    /// For the grammar and each imported file, the file each of its imports names.
    links: Vec<Vec<usize>>,
    /// Diagnostics with their file (0: the grammar).
    diagnostics: Vec<(usize, Diagnostic)>,
    /// Warnings from reading the files.
    warnings: Vec<String>,
    /// Where each imported file is, in the order of `sources`.
    paths: Vec<std::path::PathBuf>,
}

/// Reads every file `grammar` imports, directly or through others, in CGA. An import names a
/// path relative to the importing file's folder, or to one of the folders above it (the
/// project, where `rules/` and `assets/` are, or the workspace for `/Project/…` paths): the
/// nearest that has the file wins. A file that cannot be found or read is an error at the
/// import that names it.
fn load_imports(files: &Files, path: &Path, grammar: &ast::Grammar) -> Imported {
    let mut imported = Imported {
        sources: Vec::new(),
        grammars: Vec::new(),
        links: Vec::new(),
        diagnostics: Vec::new(),
        warnings: Vec::new(),
        paths: Vec::new(),
    };
    let mut index: std::collections::HashMap<std::path::PathBuf, usize> =
        std::collections::HashMap::new();
    index.insert(files.canonical(path), 0);
    // Files whose imports are still to be followed: (file index, its path).
    let mut pending = vec![(0usize, path.to_path_buf())];
    while let Some((file, path)) = pending.pop() {
        let imports = if file == 0 {
            grammar.imports.clone()
        } else {
            imported.grammars[file - 1].imports.clone()
        };
        let mut links = Vec::new();
        let mut found = Vec::new();
        for import in &imports {
            let Some(target) = files.import_path(&path, &import.path.value) else {
                imported.diagnostics.push((
                    file,
                    Diagnostic::error(
                        format!("cannot find the imported file \"{}\"", import.path.value),
                        import.path.span,
                    )
                    .with_hint("a path is looked for next to the importing file, then in each folder above it (the project, the workspace)"),
                ));
                links.push(usize::MAX);
                continue;
            };
            let key = files.canonical(&target);
            if let Some(&known) = index.get(&key) {
                links.push(known);
                continue;
            }
            let text = match read_in(files, &target) {
                Ok(read) => {
                    imported.warnings.extend(read.warning);
                    read.source
                }
                Err(message) => {
                    imported
                        .diagnostics
                        .push((file, Diagnostic::error(message, import.path.span)));
                    links.push(usize::MAX);
                    continue;
                }
            };
            let parsed = shapegram_syntax::parse_as(&text, Dialect::Cga);
            let id = imported.sources.len() + 1;
            imported
                .diagnostics
                .extend(parsed.diagnostics.into_iter().map(|d| (id, d)));
            imported.sources.push(text);
            imported.paths.push(target.clone());
            imported.grammars.push(parsed.grammar);
            index.insert(key, id);
            links.push(id);
            found.push((id, target));
        }
        if imported.links.len() <= file {
            imported.links.resize(file + 1, Vec::new());
        }
        imported.links[file] = links;
        pending.extend(found);
    }
    let files = imported.sources.len() + 1;
    imported.links.resize(files, Vec::new());
    imported
}

/// Where an import's file is on disk (see [`Files::import_path`]).
pub fn import_path(from: &Path, path: &str) -> Option<std::path::PathBuf> {
    Files::Disk.import_path(from, path)
}
