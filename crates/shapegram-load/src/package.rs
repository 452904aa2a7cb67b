//! CityEngine rule packages (`.rpk`): 7-Zip archives holding a project's rule sources
//! (`rules/*.cga`), their compiled form (`bin/*.cgb`), the assets the rules insert (`assets/`),
//! workspace files they use from other projects (`.ws/`) and a resolve map (`.resolvemap.xml`)
//! from the names the rules use to the files of the archive. A package is read whole into
//! memory once, so derivations read it as they read folders, without extracting it anywhere.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt;
use std::path::Path;
use std::sync::Arc;

/// How many bytes a package may unpack to: far more than real packages hold (a few megabytes),
/// few enough that a hostile archive cannot claim all memory.
pub const MAX_UNPACKED: u64 = 1 << 30;

/// A rule package read into memory.
pub struct RulePackage {
    /// The archive's path as given, for messages.
    name: String,
    /// File entries by path (`/`-separated, relative to the archive's root).
    files: BTreeMap<String, Arc<[u8]>>,
    /// Every folder that holds a file, at any depth (`assets`, `assets/facade`, …).
    folders: BTreeSet<String>,
    /// The resolve map: names used by the rules (`/Project/assets/a.obj`) to entries.
    resolve_map: HashMap<String, String>,
    /// The name of the CityEngine project the package was made from.
    project: String,
}

/// Why a package cannot be read or run, and what to do about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PackageError {
    /// What is wrong, naming the archive.
    pub message: String,
    /// How to fix it, when there is a way.
    pub hint: Option<String>,
}

impl PackageError {
    fn new(message: String) -> Self {
        Self {
            message,
            hint: None,
        }
    }

    fn with_hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }
}

impl fmt::Display for PackageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for PackageError {}

/// Whether `path` names a rule package, by its extension (`.rpk`, any letter case).
pub fn is_package(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("rpk"))
}

impl RulePackage {
    /// Reads the package at `path`.
    pub fn open(path: &Path) -> Result<Self, PackageError> {
        let name = path.display().to_string();
        let bytes = std::fs::read(path)
            .map_err(|e| PackageError::new(format!("cannot read the rule package {name}: {e}")))?;
        Self::from_bytes(name, bytes)
    }

    /// Reads a package from its bytes; `name` names it in messages.
    pub fn from_bytes(name: String, bytes: Vec<u8>) -> Result<Self, PackageError> {
        Self::read(name, bytes, MAX_UNPACKED)
    }

    /// [`RulePackage::from_bytes`] for packages that unpack to at most `limit` bytes.
    fn read(name: String, bytes: Vec<u8>, limit: u64) -> Result<Self, PackageError> {
        let broken = |why: String| {
            PackageError::new(format!(
                "{name} is not a readable rule package (a 7-Zip archive): {why}"
            ))
        };
        let mut reader = sevenz_rust2::ArchiveReader::new(
            std::io::Cursor::new(bytes),
            sevenz_rust2::Password::empty(),
        )
        .map_err(|e| broken(e.to_string()))?;
        reader.set_thread_count(1);
        // What the files claim, and what the compressed blocks holding them unpack to (the
        // reader decodes a block whole, also what no file claims).
        let archive = reader.archive();
        let files_size = archive.files.iter().map(|f| f.size);
        let blocks_size = archive
            .blocks
            .iter()
            .map(sevenz_rust2::Block::get_unpack_size);
        let unpacked = files_size
            .fold(0, u64::saturating_add)
            .max(blocks_size.fold(0, u64::saturating_add));
        if unpacked > limit {
            return Err(broken(format!(
                "it claims to unpack to {unpacked} bytes, more than the {limit} a package may hold"
            )));
        }
        let mut files = BTreeMap::new();
        reader
            .for_each_entries(|entry, data| {
                if entry.is_directory || entry.is_anti_item {
                    return Ok(true);
                }
                let mut bytes = Vec::with_capacity(entry.size.min(limit) as usize);
                // Never more than the entry claims, which the total above bounds.
                std::io::Read::read_to_end(&mut std::io::Read::take(data, entry.size), &mut bytes)?;
                if let Some(path) = entry_path(&entry.name) {
                    files.insert(path, Arc::from(bytes));
                }
                Ok(true)
            })
            .map_err(|e| broken(e.to_string()))?;
        let folders = files
            .keys()
            .flat_map(|path| {
                path.match_indices('/')
                    .map(move |(at, _)| path[..at].to_owned())
            })
            .collect();
        let resolve_map = files
            .get(".resolvemap.xml")
            .map(|xml| resolve_map(&String::from_utf8_lossy(xml)))
            .unwrap_or_default();
        let project = project_name(&resolve_map).unwrap_or_else(|| {
            Path::new(&name)
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
        });
        Ok(Self {
            name,
            files,
            folders,
            resolve_map,
            project,
        })
    }

    /// The archive's path as given.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The name of the CityEngine project the package was made from (as its resolve map names
    /// it, else the archive's file stem): what workspace paths (`/Project/assets/a.obj`) and
    /// `fileSearch` results start with.
    pub fn project(&self) -> &str {
        &self.project
    }

    /// How messages name an entry: `package.rpk!/assets/a.obj`.
    pub fn display(&self, entry: &str) -> String {
        format!("{}!/{entry}", self.name)
    }

    /// The bytes of a file entry.
    pub fn file(&self, entry: &str) -> Option<&Arc<[u8]>> {
        self.files.get(entry)
    }

    /// Whether `entry` is a folder holding files (`""` is the root).
    pub fn is_folder(&self, entry: &str) -> bool {
        entry.is_empty() || self.folders.contains(entry)
    }

    /// Every file entry, sorted.
    pub fn files(&self) -> impl Iterator<Item = &str> {
        self.files.keys().map(String::as_str)
    }

    /// The entry the resolve map gives for a name the rules use, if that entry is a file of
    /// the package.
    pub fn resolve(&self, key: &str) -> Option<&str> {
        self.resolve_map
            .get(key)
            .map(String::as_str)
            .filter(|entry| self.files.contains_key(*entry))
    }

    /// The CGA sources of the project's rules (`rules/**/*.cga`), sorted.
    pub fn rule_sources(&self) -> Vec<&str> {
        self.files()
            .filter(|f| f.starts_with("rules/") && has_extension(f, "cga"))
            .collect()
    }

    /// [`RulePackage::rule_sources`], or why the package has none to run: it holds only
    /// compiled rules, or no rules at all.
    pub fn runnable_sources(&self) -> Result<Vec<&str>, PackageError> {
        let sources = self.rule_sources();
        if !sources.is_empty() {
            return Ok(sources);
        }
        let compiled = self.compiled_rules();
        if compiled.is_empty() {
            Err(PackageError::new(format!(
                "{} holds no rule file (rules/*.cga)",
                self.name
            )))
        } else {
            Err(self.compiled_only(&compiled))
        }
    }

    /// The compiled rule files PRT can start from (`bin/**/*.cgb`): the rule files themselves,
    /// not the compiled imports beside them (`rule$import.cgb`), sorted.
    pub fn compiled_rules(&self) -> Vec<&str> {
        self.files()
            .filter(|f| f.starts_with("bin/") && has_extension(f, "cgb"))
            .filter(|f| !file_name(f).contains('$'))
            .collect()
    }

    /// The rule file to derive, as an entry of the package. `requested` picks one by its path
    /// in the package (`rules/a.cga`, `bin/a.cgb` for its source) or by its file name; without
    /// it, the rule file PRT runs: the source of the package's one compiled rule file (or of its
    /// one rule source when nothing is compiled).
    pub fn rule_file(&self, requested: Option<&str>) -> Result<String, PackageError> {
        let sources = self.rule_sources();
        if let Some(requested) = requested {
            return self.requested_rule_file(requested, &sources);
        }
        let compiled = self.compiled_rules();
        let choose = || {
            PackageError::new(format!(
                "{} holds {} rule files: {}",
                self.name,
                sources.len(),
                sources.join(", ")
            ))
            .with_hint("choose one with --rule-file")
        };
        match compiled.as_slice() {
            [] => match sources.as_slice() {
                [] => Err(PackageError::new(format!(
                    "{} holds no rule file (rules/*.cga)",
                    self.name
                ))),
                [only] => Ok((*only).to_owned()),
                _ => Err(choose()),
            },
            [main] => {
                let source = source_of(main);
                if self.files.contains_key(&source) {
                    Ok(source)
                } else if sources.is_empty() {
                    Err(self.compiled_only(&compiled))
                } else {
                    Err(PackageError::new(format!(
                        "{} has no CGA source for its rule file {main} (no {source})",
                        self.name
                    ))
                    .with_hint(format!(
                        "choose one of its rule sources with --rule-file: {}",
                        sources.join(", ")
                    )))
                }
            }
            _ if sources.is_empty() => Err(self.compiled_only(&compiled)),
            _ => Err(choose()),
        }
    }

    /// [`RulePackage::rule_file`] for a file asked for by name.
    fn requested_rule_file(
        &self,
        requested: &str,
        sources: &[&str],
    ) -> Result<String, PackageError> {
        let wanted = entry_path(requested).unwrap_or_default();
        let wanted = if has_extension(&wanted, "cgb") {
            source_of(&wanted)
        } else {
            wanted
        };
        let by_path = [wanted.clone(), format!("rules/{wanted}")]
            .into_iter()
            .find(|p| self.files.contains_key(p));
        if let Some(found) = by_path {
            return Ok(found);
        }
        let by_name: Vec<&&str> = sources
            .iter()
            .filter(|s| file_name(s) == file_name(&wanted))
            .collect();
        match by_name.as_slice() {
            [only] => Ok((**only).to_owned()),
            _ if sources.is_empty() => Err(self.compiled_only(&self.compiled_rules())),
            _ => Err(PackageError::new(format!(
                "{} has no rule file `{requested}`; its rule files are {}",
                self.name,
                sources.join(", ")
            ))),
        }
    }

    /// The error for a package of compiled rules without their sources.
    fn compiled_only(&self, compiled: &[&str]) -> PackageError {
        PackageError::new(format!(
            "{} holds only compiled rules ({}) and no CGA source: Shapegram runs CGA source, not CityEngine's compiled .cgb files",
            self.name,
            compiled.join(", ")
        ))
        .with_hint("use a package that includes its rules/*.cga files, or derive the .cga files of the CityEngine project")
    }
}

/// An entry's path as the package keys it: `/`-separated, without a leading `/` or `./`, `..`
/// folded; `None` for a path that leaves the archive.
pub(crate) fn entry_path(name: &str) -> Option<String> {
    let mut parts: Vec<&str> = Vec::new();
    for part in name.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop()?;
            }
            part => parts.push(part),
        }
    }
    Some(parts.join("/"))
}

/// The CGA source of a compiled rule file: `bin/a/b.cgb` is compiled from `rules/a/b.cga`.
fn source_of(compiled: &str) -> String {
    let inner = compiled.strip_prefix("bin/").unwrap_or(compiled);
    let stem = inner.strip_suffix(".cgb").unwrap_or(inner);
    format!("rules/{stem}.cga")
}

fn file_name(path: &str) -> &str {
    path.rsplit('/').next().unwrap_or(path)
}

fn has_extension(path: &str, extension: &str) -> bool {
    Path::new(path)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(extension))
}

/// The entries of a resolve map (`<entry key="…" value="…" />`), keys to values.
fn resolve_map(xml: &str) -> HashMap<String, String> {
    xml.split("<entry")
        .skip(1)
        .filter_map(|element| {
            let element = element.split('>').next()?;
            Some((attribute(element, "key")?, attribute(element, "value")?))
        })
        .collect()
}

/// The value of attribute `name` in an XML element's text, entities replaced.
fn attribute(element: &str, name: &str) -> Option<String> {
    let at = element.match_indices(name).find_map(|(at, _)| {
        let before = element[..at].chars().next_back();
        let after = element[at + name.len()..].trim_start();
        (before.is_some_and(char::is_whitespace) && after.starts_with('='))
            .then(|| after[1..].trim_start())
    })?;
    let quote = at.chars().next().filter(|q| *q == '"' || *q == '\'')?;
    let value = &at[1..at[1..].find(quote)? + 1];
    Some(
        value
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&amp;", "&"),
    )
}

/// The project a resolve map's workspace keys name for the package's own files:
/// `/Project/rules/a.cga` → `rules/a.cga` says `Project`.
fn project_name(map: &HashMap<String, String>) -> Option<String> {
    let mut names: Vec<&str> = map
        .iter()
        .filter_map(|(key, value)| {
            let rest = key.strip_prefix('/')?;
            let (project, inner) = rest.split_once('/')?;
            (inner == value).then_some(project)
        })
        .collect();
    names.sort_unstable();
    names.first().map(|n| (*n).to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entry_paths_are_folded_and_stay_inside() {
        assert_eq!(entry_path("./rules/a.cga").as_deref(), Some("rules/a.cga"));
        assert_eq!(
            entry_path("rules\\typology/../facade.cga").as_deref(),
            Some("rules/facade.cga")
        );
        assert_eq!(
            entry_path("/assets//a.obj").as_deref(),
            Some("assets/a.obj")
        );
        assert_eq!(entry_path("../a.obj"), None);
    }

    #[test]
    fn packages_that_unpack_to_more_than_the_limit_are_refused() {
        let mut writer =
            sevenz_rust2::ArchiveWriter::new(std::io::Cursor::new(Vec::new())).unwrap();
        let big = vec![b'a'; 5000];
        writer
            .push_archive_entry(
                sevenz_rust2::ArchiveEntry::new_file("rules/a.cga"),
                Some(big.as_slice()),
            )
            .unwrap();
        let bytes = writer.finish().unwrap().into_inner();
        assert!(RulePackage::read("a.rpk".into(), bytes.clone(), 5000).is_ok());
        let error = RulePackage::read("a.rpk".into(), bytes, 4999)
            .err()
            .unwrap();
        assert_eq!(
            error.message,
            "a.rpk is not a readable rule package (a 7-Zip archive): it claims to unpack to 5000 bytes, more than the 4999 a package may hold"
        );
    }

    #[test]
    fn resolve_maps_are_read_with_their_entities() {
        let map = resolve_map(
            "<?xml version=\"1.0\"?>\n<resolvemap>\n  <entry key=\"/My Town/assets/a&amp;b.obj\" value=\"assets/a&amp;b.obj\" />\n  <entry value='rules/r.cga' key='/My Town/rules/r.cga'/>\n</resolvemap>",
        );
        assert_eq!(map.len(), 2);
        assert_eq!(map["/My Town/assets/a&b.obj"], "assets/a&b.obj");
        assert_eq!(map["/My Town/rules/r.cga"], "rules/r.cga");
        assert_eq!(project_name(&map).as_deref(), Some("My Town"));
        assert_eq!(source_of("bin/typology/e.cgb"), "rules/typology/e.cga");
    }
}
