//! Goal grammars with their library: the files a library is made of, their names, and the
//! grammars compiled together into one program, as `shapegram derive --library` and the hosts'
//! runtime read them.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use shapegram_eval::{LibraryOptions, Program};
use shapegram_syntax::{Diagnostic, Dialect, SourceFile, ast};

/// The goal notation `source` is in: `dialect` when given and a goal notation, else the one its
/// text is in, else the native one for a `.goal` file without the marks of either; `None` for a
/// grammar that is not a goal grammar.
pub fn goal_dialect(source: &SourceFile, dialect: Option<Dialect>) -> Option<Dialect> {
    let goal = |d: Dialect| matches!(d, Dialect::Goal | Dialect::Michelangelo).then_some(d);
    match dialect {
        Some(d) => goal(d),
        None => goal(shapegram_syntax::detect(source.text()))
            .or_else(|| source.name().ends_with(".goal").then_some(Dialect::Goal)),
    }
}

/// The files of a goal grammar's library: the files given and the goal grammar files (`*.goal`)
/// in the folders given and their subfolders, sorted by path, each once, without `main` (so that
/// a grammar's own folder can be its library). A path that is neither a file nor a folder, or a
/// folder that cannot be read, is an error.
pub fn library_files(paths: &[PathBuf], main: &Path) -> Result<Vec<PathBuf>, String> {
    let main = std::fs::canonicalize(main).ok();
    let is_main = |path: &Path| std::fs::canonicalize(path).ok() == main;
    let mut files = Vec::new();
    let mut pending = Vec::new();
    for path in paths {
        check_library_path(path)?;
        if path.is_dir() {
            pending.push(path.clone());
        } else if !is_main(path) {
            files.push(path.clone());
        }
    }
    while let Some(folder) = pending.pop() {
        let entries = std::fs::read_dir(&folder)
            .map_err(|e| format!("cannot read the library folder {}: {e}", folder.display()))?;
        for entry in entries {
            let entry = entry.map_err(|e| format!("cannot read {}: {e}", folder.display()))?;
            let path = entry.path();
            // Links to folders are not followed: one could lead back up the tree.
            if entry.file_type().is_ok_and(|t| t.is_dir()) {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "goal") && !is_main(&path) {
                files.push(path);
            }
        }
    }
    files.sort();
    // A file reached twice (named, and in a folder) is one grammar.
    let mut seen = HashSet::new();
    files.retain(|f| seen.insert(std::fs::canonicalize(f).unwrap_or_else(|_| f.clone())));
    Ok(files)
}

/// Checks that `path` can be a library: a file, or a folder of goal grammars.
pub fn check_library_path(path: &Path) -> Result<(), String> {
    if path.is_dir() || path.is_file() {
        Ok(())
    } else {
        Err(format!(
            "the library {} is neither a file nor a folder",
            path.display()
        ))
    }
}

/// Two grammars of a library with one name: grammars are named by their file stems, and two of
/// one name would mix their rules' names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NameClash {
    /// The name both have.
    pub name: String,
    /// The file (or name) of the one met first.
    pub first: String,
    /// The file (or name) of the other.
    pub second: String,
}

impl NameClash {
    /// How to fix it.
    pub const HINT: &str = "grammars are named by their file names: rename one";
}

impl std::fmt::Display for NameClash {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "two library grammars are called `{}`: {} and {}",
            self.name, self.first, self.second
        )
    }
}

impl std::error::Error for NameClash {}

/// Checks that the grammars of a library, given by their file names (or paths), the main
/// grammar's first, have names of their own (see [`NameClash`]).
pub fn check_library_names<'a>(files: impl IntoIterator<Item = &'a str>) -> Result<(), NameClash> {
    let mut names: HashMap<String, &str> = HashMap::new();
    for file in files {
        let name = stem(file);
        if let Some(first) = names.insert(name.clone(), file) {
            return Err(NameClash {
                name,
                first: first.to_owned(),
                second: file.to_owned(),
            });
        }
    }
    Ok(())
}

/// A goal grammar and its library, parsed and compiled into one program.
pub struct CompiledLibrary {
    /// The main grammar, parsed (possibly incomplete when there were parse errors).
    pub grammar: ast::Grammar,
    /// The program, `None` when there were errors.
    pub program: Option<Program>,
    /// Errors and warnings, each with the file it is in (an index into `sources`).
    pub diagnostics: Vec<(usize, Diagnostic)>,
    /// The sources, the main grammar first: what errors of the derivation point into.
    pub sources: Vec<SourceFile>,
    /// Goal rules in all files.
    pub rules: usize,
}

impl CompiledLibrary {
    /// Number of errors.
    pub fn errors(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|(_, d)| d.is_error())
            .count()
    }
}

/// Parses and compiles a goal grammar (`sources[0]`, in `dialect` or the goal notation its text
/// is in) with its library (the rest, each in the notation of its own text). A grammar is named
/// by its file stem, or by its whole name from `options.repository_from` on (a repository's
/// `owner/name@version`). With parse errors nothing is compiled, so that declarations the
/// parser had to skip do not show up again as unknown names.
pub fn compile_library(
    sources: Vec<SourceFile>,
    dialect: Option<Dialect>,
    options: &LibraryOptions,
) -> CompiledLibrary {
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
    let rules = parsed.iter().map(|p| p.grammar.goal_rules.len()).sum();
    CompiledLibrary {
        grammar: parsed
            .into_iter()
            .next()
            .map(|p| p.grammar)
            .unwrap_or_default(),
        program,
        diagnostics,
        sources,
        rules,
    }
}

/// A grammar's name in a library: its file's stem.
fn stem(path: &str) -> String {
    Path::new(path)
        .file_stem()
        .map_or_else(|| path.to_owned(), |s| s.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn library_names_are_file_stems_and_must_differ() {
        assert_eq!(check_library_names(["chair.goal", "lib/wood.goal"]), Ok(()));
        assert_eq!(
            check_library_names(["chair.goal", "a/wood.goal", "b/wood.goal"]),
            Err(NameClash {
                name: "wood".to_owned(),
                first: "a/wood.goal".to_owned(),
                second: "b/wood.goal".to_owned(),
            })
        );
        let clash = check_library_names(["chair.goal", "lib/chair.goal"]).unwrap_err();
        assert_eq!(
            clash.to_string(),
            "two library grammars are called `chair`: chair.goal and lib/chair.goal"
        );
    }

    #[test]
    fn library_folders_are_searched_for_goal_grammars_without_the_main_one() {
        let root = std::env::temp_dir().join(format!("shapegram-library-{}", std::process::id()));
        for file in ["main.goal", "b/x.goal", "a/deep/y.goal", "a/notes.txt"] {
            let path = root.join(file);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, "").unwrap();
        }
        let main = root.join("main.goal");
        // The folder and a file in it: each file once, sorted, the main grammar left out.
        let files = library_files(&[root.clone(), root.join("b/x.goal")], &main).unwrap();
        assert_eq!(files, [root.join("a/deep/y.goal"), root.join("b/x.goal")]);
        let missing = root.join("missing");
        assert_eq!(
            library_files(std::slice::from_ref(&missing), &main),
            Err(format!(
                "the library {} is neither a file nor a folder",
                missing.display()
            ))
        );
        std::fs::remove_dir_all(root).unwrap();
    }
}
