//! CityEngine rule packages (`.rpk`) in the studio: each rule source of a package is a file of
//! the list, named as messages name it, `/folder/town.rpk!/rules/town.cga`, read from the
//! archive and derived with the package's imports and assets. The studio never writes into a
//! package: its rule files can be edited and derived, not saved. A package that cannot be used
//! (not an archive, only compiled rules) is listed by its own path, whose reading gives why.
//!
//! Packages are read whole into memory once and kept while the file stays as it was (same size
//! and modification time), so that deriving as one types does not unpack the archive each time.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::SystemTime;

use shapegram_load::{PackageError, RulePackage};

/// What separates a package's path from the path of a file inside it.
pub const SEPARATOR: &str = "!/";

/// A rule file of a package: the package as read, and the rule file's entry (`rules/a.cga`).
#[derive(Clone)]
pub struct PackagedRule {
    /// The package, read into memory.
    pub package: Arc<RulePackage>,
    /// The rule file's path in the package.
    pub entry: String,
}

impl PackagedRule {
    /// How the API names it: `/folder/town.rpk!/rules/town.cga`.
    pub fn path(&self) -> String {
        self.package.display(&self.entry)
    }
}

/// A path of the API split at a package: the package's path and the entry after it; `None`
/// for a path that names no file inside a package.
pub fn split(path: &str) -> Option<(&str, &str)> {
    let lower = path.to_ascii_lowercase();
    let at = lower.find(&format!(".rpk{SEPARATOR}"))? + ".rpk".len();
    Some((&path[..at], &path[at + SEPARATOR.len()..]))
}

/// The packages read so far, by canonical path, with the size and time of the file read.
#[derive(Default)]
pub struct Packages(Mutex<HashMap<PathBuf, Read>>);

/// A package as read from its file.
#[derive(Clone)]
struct Read {
    stamp: (u64, Option<SystemTime>),
    package: Result<Arc<RulePackage>, PackageError>,
}

impl Packages {
    /// The package at `path` (canonical), read again when its file changed.
    pub fn open(&self, path: &Path) -> Result<Arc<RulePackage>, PackageError> {
        let stamp = std::fs::metadata(path)
            .map(|m| (m.len(), m.modified().ok()))
            .unwrap_or((0, None));
        let mut known = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(read) = known.get(path)
            && read.stamp == stamp
        {
            return read.package.clone();
        }
        let package = RulePackage::open(path).map(Arc::new);
        known.insert(
            path.to_path_buf(),
            Read {
                stamp,
                package: package.clone(),
            },
        );
        package
    }

    /// The rule file `entry` of the package at `path` (canonical): one of its rule sources, or
    /// with `None` the one `shapegram derive` runs. An error says why there is none.
    pub fn rule(&self, path: &Path, entry: Option<&str>) -> Result<PackagedRule, String> {
        let package = self.open(path).map_err(message)?;
        let entry = match entry {
            None => package.rule_file(None).map_err(message)?,
            Some(entry) => {
                let sources = package.runnable_sources().map_err(message)?;
                sources
                    .iter()
                    .find(|s| **s == entry)
                    .map(|s| (*s).to_owned())
                    .ok_or_else(|| {
                        format!(
                            "{} has no rule file `{entry}`; its rule files are {}",
                            package.name(),
                            sources.join(", ")
                        )
                    })?
            }
        };
        Ok(PackagedRule { package, entry })
    }

    /// The rule files of the package at `path` to list, the one `shapegram derive` runs first;
    /// none when the package cannot be used.
    pub fn rules(&self, path: &Path) -> Vec<PackagedRule> {
        let Ok(package) = self.open(path) else {
            return Vec::new();
        };
        let main = package.rule_file(None).ok();
        let mut entries: Vec<String> = package
            .rule_sources()
            .into_iter()
            .map(str::to_owned)
            .collect();
        entries.sort_by_key(|e| Some(e) != main.as_ref());
        entries
            .into_iter()
            .map(|entry| PackagedRule {
                package: Arc::clone(&package),
                entry,
            })
            .collect()
    }
}

/// A package's error as the studio shows it: the message and its hint, which names the
/// command's option where the studio lists each rule file instead.
fn message(error: PackageError) -> String {
    match error.hint {
        Some(hint) if !hint.contains("--rule-file") => format!("{} ({hint})", error.message),
        _ => error.message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_split_at_the_package() {
        assert_eq!(
            split("/a/Town.RPK!/rules/t.cga"),
            Some(("/a/Town.RPK", "rules/t.cga"))
        );
        assert_eq!(
            split("/a/x.rpk!/rules/b.rpk!/c.cga"),
            Some(("/a/x.rpk", "rules/b.rpk!/c.cga"))
        );
        assert_eq!(split("/a/town.rpk"), None);
        assert_eq!(split("/a/house.cga"), None);
    }
}
