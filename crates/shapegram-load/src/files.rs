//! Where a grammar's files are read from: the file system, or a rule package read into memory.
//! Paths inside a package are relative to its root (`rules/a.cga`, `assets/b.obj`), so the
//! searches of imports and assets run over both the same way.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::package::{RulePackage, entry_path};

/// The files a grammar, its imports and its assets come from.
#[derive(Clone, Default)]
pub enum Files {
    /// The file system.
    #[default]
    Disk,
    /// A rule package: paths are entries of the archive.
    Package(Arc<RulePackage>),
}

impl Files {
    /// Whether `path` is a file.
    pub fn is_file(&self, path: &Path) -> bool {
        match self {
            Self::Disk => path.is_file(),
            Self::Package(package) => entry(path).is_some_and(|e| package.file(&e).is_some()),
        }
    }

    /// Whether `path` is a folder.
    pub fn is_dir(&self, path: &Path) -> bool {
        match self {
            Self::Disk => path.is_dir(),
            Self::Package(package) => entry(path).is_some_and(|e| package.is_folder(&e)),
        }
    }

    /// The bytes of the file at `path`, or why they cannot be had (naming the file).
    pub fn read(&self, path: &Path) -> Result<Vec<u8>, String> {
        self.read_io(path)
            .map_err(|e| format!("cannot read {}: {e}", self.display(path)))
    }

    /// [`Files::read`] with the operating system's error.
    pub fn read_io(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        match self {
            Self::Disk => std::fs::read(path),
            Self::Package(package) => entry(path)
                .and_then(|e| package.file(&e))
                .map(|bytes| bytes.to_vec())
                .ok_or_else(|| {
                    std::io::Error::new(std::io::ErrorKind::NotFound, "not in the rule package")
                }),
        }
    }

    /// How messages name the file at `path`: as given on disk, `package.rpk!/entry` in a
    /// package.
    pub fn display(&self, path: &Path) -> String {
        match self {
            Self::Disk => path.display().to_string(),
            Self::Package(package) => {
                package.display(&entry(path).unwrap_or_else(|| path.display().to_string()))
            }
        }
    }

    /// The path that [`Files::display`] shows as `shown`.
    pub fn undisplay(&self, shown: &Path) -> PathBuf {
        match self {
            Self::Disk => shown.to_path_buf(),
            Self::Package(package) => {
                let shown = shown.to_string_lossy();
                let prefix = format!("{}!/", package.name());
                PathBuf::from(shown.strip_prefix(&prefix).unwrap_or(&shown))
            }
        }
    }

    /// One name per file, whatever path leads to it: what a file read once is keyed by.
    pub fn canonical(&self, path: &Path) -> PathBuf {
        match self {
            Self::Disk => std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
            Self::Package(_) => entry(path).map_or_else(|| path.to_path_buf(), PathBuf::from),
        }
    }

    /// Where an import's file is: next to the importing file `from`, else in the nearest folder
    /// above it that has it. A path starting with `/` names a file of the workspace
    /// (`/ESRI.lib/rules/a.cga`): it is looked for in each folder above, and in its `.ws`
    /// folder, where rule packages keep the workspace files they bring.
    pub fn import_path(&self, from: &Path, path: &str) -> Option<PathBuf> {
        if let Self::Package(package) = self
            && path.starts_with('/')
            && let Some(entry) = package.resolve(path)
        {
            return Some(PathBuf::from(entry));
        }
        let relative = path.trim_start_matches('/');
        let workspace = path.starts_with('/');
        from.parent()?
            .ancestors()
            .flat_map(|folder| {
                let packaged = workspace.then(|| folder.join(".ws").join(relative));
                std::iter::once(folder.join(relative)).chain(packaged)
            })
            .find(|candidate| self.is_file(candidate))
    }

    /// The files under `root`, outside hidden folders, as paths relative to `root` split into
    /// their parts.
    pub(crate) fn listing(&self, root: &Path) -> Vec<Vec<String>> {
        match self {
            Self::Disk => disk_listing(root),
            Self::Package(package) => {
                let prefix = entry(root).unwrap_or_default();
                package
                    .files()
                    .filter_map(|f| match prefix.as_str() {
                        "" => Some(f),
                        p => f.strip_prefix(p)?.strip_prefix('/'),
                    })
                    .map(|f| f.split('/').map(str::to_owned).collect::<Vec<_>>())
                    .filter(|parts| !parts[..parts.len() - 1].iter().any(|p| p.starts_with('.')))
                    .collect()
            }
        }
    }
}

/// A path inside a package as an entry name.
fn entry(path: &Path) -> Option<String> {
    entry_path(&path.to_string_lossy())
}

/// [`Files::listing`] on disk.
fn disk_listing(root: &Path) -> Vec<Vec<String>> {
    let mut found = Vec::new();
    let mut pending = vec![root.to_path_buf()];
    while let Some(folder) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let hidden = entry.file_name().to_string_lossy().starts_with('.');
            match entry.file_type() {
                Ok(t) if t.is_dir() && !hidden => pending.push(path),
                Ok(t) if t.is_file() => {
                    let Ok(relative) = path.strip_prefix(root) else {
                        continue;
                    };
                    found.push(
                        relative
                            .components()
                            .map(|c| c.as_os_str().to_string_lossy().into_owned())
                            .collect(),
                    );
                }
                _ => {}
            }
        }
    }
    found
}

/// The folder `to` relative to the folder `from` (both named from the same place),
/// `/`-separated: `lib`, `../lib`, or `""` for the same folder.
pub(crate) fn relative(from: &Path, to: &Path) -> String {
    use std::path::Component;
    let parts = |p: &Path| {
        let mut parts: Vec<String> = Vec::new();
        for c in p.components() {
            match c {
                Component::CurDir => {}
                Component::ParentDir if parts.last().is_some_and(|l| l != "..") => {
                    parts.pop();
                }
                c => parts.push(c.as_os_str().to_string_lossy().into_owned()),
            }
        }
        parts
    };
    let (from, to) = (parts(from), parts(to));
    let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    let up = std::iter::repeat_n("..".to_owned(), from.len() - common);
    up.chain(to[common..].iter().cloned())
        .collect::<Vec<_>>()
        .join("/")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_relative_to_another_go_up_then_down() {
        let r = |a: &str, b: &str| relative(Path::new(a), Path::new(b));
        assert_eq!(r("rules", "rules/lib"), "lib");
        assert_eq!(r("", "lib/deep"), "lib/deep");
        assert_eq!(r("rules/main", "rules/shared"), "../shared");
        assert_eq!(r("/p/rules", "/p/assets"), "../assets");
        assert_eq!(r("./rules/a/..", "rules"), "");
        assert_eq!(r("rules", "rules/../.ws/Lib/rules"), "../.ws/Lib/rules");
    }
}
