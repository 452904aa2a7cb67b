//! The CityEngine corpus: real CGA rule files and rule packages that are not part of the
//! repository (see the README). Tests over it find it through one setting and show up as
//! ignored, never as passed, when it is absent.
//!
//! The corpus folder holds `cityengine-cga/` (rule sources) and `cityengine-rpk/` (whole rule
//! packages with their assets and PRT's reference output). It is found by:
//! 1. the environment variable [`SETTING`], which must name such a folder (a wrong path is an
//!    error, so CI can never skip the corpus by accident), else
//! 2. `../shared/anchors` beside the repository, when that folder exists, else
//! 3. nowhere: corpus tests are ignored and the harness says how to run them.
//!
//! A test file over the corpus sets `harness = false` in its crate's `Cargo.toml` and ends with
//! [`corpus_tests!`], naming its test functions.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use libtest_mimic::{Arguments, Failed, Trial};

/// The environment variable naming the corpus folder.
pub const SETTING: &str = "SHAPEGRAM_CORPUS";

/// The corpus's subfolders; both must be present.
const PARTS: [&str; 2] = ["cityengine-cga", "cityengine-rpk"];

/// A located corpus folder.
#[derive(Debug, Clone)]
pub struct Corpus {
    root: PathBuf,
}

impl Corpus {
    /// The folder that holds `cityengine-cga/` and `cityengine-rpk/`.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The CGA rule sources, one folder per package.
    pub fn cga(&self) -> PathBuf {
        self.root.join("cityengine-cga")
    }

    /// The rule packages: `.rpk` archives, their extracted contents and `prt-reference.json`.
    pub fn rpk(&self) -> PathBuf {
        self.root.join("cityengine-rpk")
    }

    /// Every file under `dir` (recursively) whose extension is `extension`, sorted.
    pub fn files(dir: &Path, extension: &str) -> Vec<PathBuf> {
        let mut files = Vec::new();
        let mut stack = vec![dir.to_path_buf()];
        while let Some(path) = stack.pop() {
            if path.is_dir() {
                let entries =
                    std::fs::read_dir(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                stack.extend(entries.map(|e| e.expect("a readable folder entry").path()));
            } else if path.extension().is_some_and(|e| e == extension) {
                files.push(path);
            }
        }
        files.sort();
        files
    }

    /// Every `.cga` file of `cityengine-cga/`, sorted.
    pub fn cga_files(&self) -> Vec<PathBuf> {
        Self::files(&self.cga(), "cga")
    }
}

/// Finds the corpus: `Ok(None)` when no setting names it and no default folder exists, an error
/// when the setting (or the default folder) is not a complete corpus.
pub fn locate() -> Result<Option<Corpus>, String> {
    locate_with(
        std::env::var_os(SETTING)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from),
    )
}

/// [`locate`] with the setting's value given.
fn locate_with(setting: Option<PathBuf>) -> Result<Option<Corpus>, String> {
    let (root, source) = match setting {
        Some(path) => (path, format!("{SETTING} names")),
        None => {
            let beside = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/anchors");
            if !beside.is_dir() {
                return Ok(None);
            }
            (beside, "the default corpus folder is".to_string())
        }
    };
    if !root.is_dir() {
        return Err(format!(
            "{source} {}, which is not a folder: point {SETTING} at the folder that holds {} and {}",
            root.display(),
            PARTS[0],
            PARTS[1]
        ));
    }
    if let Some(missing) = PARTS.iter().find(|part| !root.join(part).is_dir()) {
        return Err(format!(
            "{source} {}, which has no {missing}/ folder: point {SETTING} at the folder that holds {} and {}",
            root.display(),
            PARTS[0],
            PARTS[1]
        ));
    }
    let root = root
        .canonicalize()
        .map_err(|e| format!("{}: {e}", root.display()))?;
    Ok(Some(Corpus { root }))
}

/// A test over the corpus: it passes by returning and fails by panicking, as `#[test]`s do.
pub type CorpusTest = fn(&Corpus);

/// Runs `tests` under libtest's command line (filters, `--ignored`, `--list` all work). Without a
/// corpus they are reported as ignored, with a line on how to run them; with a broken setting
/// every test fails with the reason.
pub fn run(tests: &[(&str, CorpusTest)]) -> ExitCode {
    let args = Arguments::from_args();
    let located = locate();
    match &located {
        Ok(None) if !args.list => eprintln!(
            "note: {} corpus tests ignored: no CityEngine corpus (set {SETTING} to the folder that holds {} and {}; see the README)",
            tests.len(),
            PARTS[0],
            PARTS[1]
        ),
        _ => {}
    }
    let located = Arc::new(located);
    let trials = tests
        .iter()
        .map(|&(name, test)| {
            let located = Arc::clone(&located);
            let ignored = matches!(*located, Ok(None));
            Trial::test(name, move || match &*located {
                Ok(Some(corpus)) => {
                    test(corpus);
                    Ok(())
                }
                Ok(None) => Err(Failed::from(format!(
                    "no CityEngine corpus: set {SETTING} to the folder that holds {} and {}",
                    PARTS[0], PARTS[1]
                ))),
                Err(message) => Err(Failed::from(message.as_str())),
            })
            .with_ignored_flag(ignored)
        })
        .collect();
    libtest_mimic::run(&args, trials).exit_code()
}

/// Defines `main` for a test file over the corpus, running the named [`CorpusTest`]s.
#[macro_export]
macro_rules! corpus_tests {
    ($($test:ident),+ $(,)?) => {
        fn main() -> ::std::process::ExitCode {
            $crate::run(&[$((stringify!($test), $test as $crate::CorpusTest)),+])
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("shapegram-corpus-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_complete_folder_is_the_corpus() {
        let dir = scratch("complete");
        for part in PARTS {
            std::fs::create_dir(dir.join(part)).unwrap();
        }
        let corpus = locate_with(Some(dir.clone())).unwrap().unwrap();
        assert_eq!(
            corpus.cga(),
            dir.canonicalize().unwrap().join("cityengine-cga")
        );
        std::fs::write(dir.join("cityengine-cga/b.cga"), "").unwrap();
        std::fs::create_dir(dir.join("cityengine-cga/p")).unwrap();
        std::fs::write(dir.join("cityengine-cga/p/a.cga"), "").unwrap();
        std::fs::write(dir.join("cityengine-cga/p/a.obj"), "").unwrap();
        let names: Vec<_> = corpus
            .cga_files()
            .iter()
            .map(|p| p.strip_prefix(corpus.cga()).unwrap().to_path_buf())
            .collect();
        assert_eq!(names, [PathBuf::from("b.cga"), PathBuf::from("p/a.cga")]);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn a_setting_that_names_no_folder_is_an_error() {
        let missing = std::env::temp_dir().join("shapegram-corpus-nowhere");
        let message = locate_with(Some(missing.clone())).unwrap_err();
        assert_eq!(
            message,
            format!(
                "SHAPEGRAM_CORPUS names {}, which is not a folder: point SHAPEGRAM_CORPUS at the folder that holds cityengine-cga and cityengine-rpk",
                missing.display()
            )
        );
    }

    #[test]
    fn a_folder_without_both_parts_is_an_error() {
        let dir = scratch("partial");
        std::fs::create_dir(dir.join("cityengine-cga")).unwrap();
        let message = locate_with(Some(dir.clone())).unwrap_err();
        assert!(
            message.contains("which has no cityengine-rpk/ folder"),
            "{message}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}
