//! The files the studio may touch: grammar files (by extension) directly inside the folders of
//! the files it was given, and the rule files inside the rule packages there (see
//! [`super::packages`]). A path is refused when it has a `..`, is not in one of those folders
//! once links are resolved (a link leading out), or has another extension. Files are read as
//! `shapegram derive` reads them (UTF-8, a byte-order mark dropped, else Windows-1252) and saved
//! back the same way (encoding, byte-order mark, line endings), atomically: a temporary file in
//! the same folder, synced, then renamed over the old one.

use std::collections::HashMap;
use std::io::Write;
use std::path::{Component, Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use serde::{Deserialize, Serialize};

use super::StudioState;
use super::packages::{PackagedRule, Packages};
use crate::error::ApiError;
use crate::extract::{ApiQuery, JsonBody};

/// Extensions of the grammar files the studio lists, reads and writes.
pub const GRAMMAR_EXTENSIONS: [&str; 7] = ["cga", "mul", "sgl", "goal", "lsys", "cave", "grammar"];

/// The folders the studio works in and the files it was given (all canonical paths).
pub struct Folders {
    given: Vec<PathBuf>,
    folders: Vec<PathBuf>,
    /// The rule packages read.
    packages: Packages,
}

/// A file the API names: a grammar file, or a rule file inside a rule package.
pub enum Source {
    /// A grammar file's canonical path.
    File(PathBuf),
    /// A rule file of a package.
    Packaged(PackagedRule),
}

impl Folders {
    /// The folders of `files` (none: the current folder). Each file must be a grammar file or a
    /// rule package (`.rpk`) that exists.
    pub fn new(files: &[PathBuf]) -> Result<Folders, String> {
        let mut given = Vec::new();
        let mut folders = Vec::new();
        for file in files {
            let path = std::fs::canonicalize(file)
                .map_err(|e| format!("cannot open {}: {e}", file.display()))?;
            if !path.is_file() || !is_listed(&path) {
                return Err(format!(
                    "{} is not a grammar file (.{}), a rule package (.rpk) or a topological grammar project (.sgproj.json)",
                    file.display(),
                    GRAMMAR_EXTENSIONS.join(", .")
                ));
            }
            let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
            if !folders.contains(&folder) {
                folders.push(folder);
            }
            given.push(path);
        }
        if files.is_empty() {
            let here = std::env::current_dir()
                .and_then(std::fs::canonicalize)
                .map_err(|e| format!("cannot find the current folder: {e}"))?;
            folders.push(here);
        }
        Ok(Folders {
            given,
            folders,
            packages: Packages::default(),
        })
    }

    /// The canonical path of the existing grammar file `path` names, if the studio may touch it.
    pub fn resolve(&self, path: &str) -> Result<PathBuf, ApiError> {
        self.check(path, has_grammar_extension)
    }

    /// The canonical path of the existing topological grammar project (`.sgproj.json`) `path`
    /// names, if the studio may touch it.
    pub fn resolve_project(&self, path: &str) -> Result<PathBuf, ApiError> {
        self.check(path, is_project)
    }

    /// The grammar file or packaged rule file `path` names, if the studio may touch it: a
    /// grammar file as [`Folders::resolve`] finds it, or `/folder/town.rpk!/rules/a.cga` (a rule
    /// source of a package the studio may touch); a package's own path names the rule file
    /// `shapegram derive` runs. A package that cannot be used, or has no such rule file, is
    /// refused with the reason (422).
    pub fn resolve_source(&self, path: &str) -> Result<Source, ApiError> {
        let (archive, entry) = match super::packages::split(path) {
            Some((archive, entry)) => (archive, Some(entry)),
            None if shapegram_load::is_package(Path::new(path)) => (path, None),
            None => return self.resolve(path).map(Source::File),
        };
        if let Some(entry) = entry
            && entry.split(['/', '\\']).any(|part| part == "..")
        {
            return Err(ApiError::forbidden(format!("`{path}` goes up with `..`")));
        }
        let real = self.check(archive, shapegram_load::is_package)?;
        self.packages
            .rule(&real, entry)
            .map(Source::Packaged)
            .map_err(|e| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, e))
    }

    /// The canonical path of the existing file `path` names, if it is of a kind `allowed` (by
    /// its extension) and in the folders the studio may touch.
    fn check(&self, path: &str, allowed: fn(&Path) -> bool) -> Result<PathBuf, ApiError> {
        let named = Path::new(path);
        if !named.is_absolute() {
            return Err(ApiError::bad_request(format!(
                "`{path}` is not an absolute path (GET /api/files lists the files)"
            )));
        }
        if named.components().any(|c| c == Component::ParentDir) {
            return Err(ApiError::forbidden(format!("`{path}` goes up with `..`")));
        }
        if !allowed(named) {
            return Err(ApiError::forbidden(format!(
                "`{path}` is not a grammar file (.{}) or a rule file of a rule package (.rpk!/rules/…)",
                GRAMMAR_EXTENSIONS.join(", .")
            )));
        }
        let real = std::fs::canonicalize(named).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                ApiError::new(StatusCode::NOT_FOUND, format!("no file `{path}`"))
            } else {
                ApiError::bad_request(format!("cannot open `{path}`: {e}"))
            }
        })?;
        let inside = |p: &Path| {
            p.parent()
                .is_some_and(|f| self.folders.iter().any(|x| x == f))
        };
        if !inside(named) || !inside(&real) || !allowed(&real) {
            return Err(ApiError::forbidden(format!(
                "`{path}` is outside the folders of the files the studio was given"
            )));
        }
        if !real.is_file() {
            return Err(ApiError::bad_request(format!("`{path}` is not a file")));
        }
        Ok(real)
    }

    /// The files to list: the grammar files and rule packages given first, then the others in
    /// their folders, by path; each package as its rule files, or as itself when it has none to
    /// run (reading it says why). With each, whether it was given and whether it is inside a
    /// package.
    fn listing(&self) -> Vec<(String, bool, bool)> {
        self.files()
            .into_iter()
            .flat_map(|(path, given)| {
                let rules = if shapegram_load::is_package(&path) {
                    self.packages.rules(&path)
                } else {
                    Vec::new()
                };
                let plain = rules
                    .is_empty()
                    .then(|| (path.display().to_string(), given, false));
                rules
                    .into_iter()
                    .map(move |rule| (rule.path(), given, true))
                    .chain(plain)
            })
            .collect()
    }

    /// The grammar files and packages: those given first, then the others in their folders, by
    /// path.
    fn files(&self) -> Vec<(PathBuf, bool)> {
        let mut others = Vec::new();
        for folder in &self.folders {
            let Ok(entries) = std::fs::read_dir(folder) else {
                continue;
            };
            for entry in entries.flatten() {
                let path = entry.path();
                if is_listed(&path)
                    && entry.file_type().is_ok_and(|t| t.is_file())
                    && !self.given.contains(&path)
                {
                    others.push(path);
                }
            }
        }
        others.sort();
        self.given
            .iter()
            .map(|p| (p.clone(), true))
            .chain(others.into_iter().map(|p| (p, false)))
            .collect()
    }
}

fn has_grammar_extension(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| GRAMMAR_EXTENSIONS.contains(&e))
}

/// Whether `path` names a topological grammar project.
fn is_project(path: &Path) -> bool {
    path.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
        n.len() > super::topo::PROJECT_SUFFIX.len() && n.ends_with(super::topo::PROJECT_SUFFIX)
    })
}

/// Whether the file list shows `path`: a grammar file, a rule package or a topological grammar
/// project.
fn is_listed(path: &Path) -> bool {
    has_grammar_extension(path) || shapegram_load::is_package(path) || is_project(path)
}

/// A file's encoding, as it was read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Encoding {
    #[serde(rename = "utf-8")]
    Utf8,
    /// UTF-8 that started with a byte-order mark.
    #[serde(rename = "utf-8-bom")]
    Utf8Bom,
    /// Not UTF-8: read as Windows-1252, as CityEngine writes rule files on Windows.
    #[serde(rename = "windows-1252")]
    Windows1252,
}

/// How a file was written: its encoding and whether its lines end in CR LF.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Format {
    pub encoding: Encoding,
    pub crlf: bool,
}

/// How each file was read last.
#[derive(Default)]
pub struct Formats(Mutex<HashMap<PathBuf, Format>>);

/// Decodes a grammar file as `shapegram derive` does: UTF-8 (a byte-order mark dropped), else
/// Windows-1252. Line endings stay as they are.
pub fn decode(bytes: Vec<u8>) -> (String, Encoding) {
    match String::from_utf8(bytes) {
        Ok(mut text) => {
            if text.starts_with('\u{feff}') {
                text.drain(..'\u{feff}'.len_utf8());
                (text, Encoding::Utf8Bom)
            } else {
                (text, Encoding::Utf8)
            }
        }
        Err(e) => {
            let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(e.as_bytes());
            (text.into_owned(), Encoding::Windows1252)
        }
    }
}

/// The bytes of `text` (lines ending in `\n` as an editor gives them) written in `format`; an
/// error names the first character Windows-1252 cannot hold.
pub fn encode(text: &str, format: Format) -> Result<Vec<u8>, String> {
    let normalized = text.replace("\r\n", "\n");
    let text = if format.crlf {
        normalized.replace('\n', "\r\n")
    } else {
        normalized
    };
    match format.encoding {
        Encoding::Utf8 => Ok(text.into_bytes()),
        Encoding::Utf8Bom => Ok(["\u{feff}", &text].concat().into_bytes()),
        Encoding::Windows1252 => {
            let (bytes, _, unmappable) = encoding_rs::WINDOWS_1252.encode(&text);
            if unmappable {
                let (line, c) = text
                    .lines()
                    .enumerate()
                    .find_map(|(i, l)| l.chars().find(|&c| !in_windows_1252(c)).map(|c| (i, c)))
                    .unwrap_or((0, '?'));
                return Err(format!(
                    "line {}: `{c}` (U+{:04X}) cannot be written in Windows-1252, the file's encoding",
                    line + 1,
                    c as u32
                ));
            }
            Ok(bytes.into_owned())
        }
    }
}

fn in_windows_1252(c: char) -> bool {
    let mut buffer = [0u8; 4];
    !encoding_rs::WINDOWS_1252
        .encode(c.encode_utf8(&mut buffer))
        .2
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, synced, renamed over it,
/// keeping the old file's permissions.
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let folder = path.parent().unwrap_or(Path::new("."));
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let mut suffix = [0u8; 6];
    getrandom::fill(&mut suffix).map_err(|e| std::io::Error::other(e.to_string()))?;
    let suffix: String = suffix.iter().map(|b| format!("{b:02x}")).collect();
    let temporary = folder.join(format!(".{name}.{suffix}.studio-tmp"));
    let written = (|| {
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)?;
        file.write_all(bytes)?;
        if let Ok(metadata) = std::fs::metadata(path) {
            file.set_permissions(metadata.permissions())?;
        }
        file.sync_all()?;
        std::fs::rename(&temporary, path)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

/// One grammar file in the list.
#[derive(Serialize)]
pub struct FileEntry {
    /// The absolute path: how the API names the file (`/folder/town.rpk!/rules/a.cga` inside a
    /// rule package).
    pub path: String,
    /// The file name (`town.rpk!/rules/a.cga` inside a package).
    pub name: String,
    /// Whether it was named on the command line (for a packaged rule file: its package).
    pub given: bool,
    /// Whether it is a rule file inside a package, which the studio derives but does not save.
    pub read_only: bool,
}

/// The answer of `GET /api/files`.
#[derive(Serialize)]
pub struct FileList {
    pub files: Vec<FileEntry>,
    pub folders: Vec<String>,
}

/// `GET /api/files`: the files given, then the other grammar files in their folders.
pub async fn list(State(state): State<StudioState>) -> Json<FileList> {
    let files = state
        .folders
        .listing()
        .into_iter()
        .map(|(path, given, read_only)| {
            let archive = super::packages::split(&path).map_or(path.as_str(), |(a, _)| a);
            let folder = Path::new(archive).parent().unwrap_or(Path::new(""));
            let name = Path::new(&path)
                .strip_prefix(folder)
                .map_or_else(|_| path.clone(), |n| n.to_string_lossy().into_owned());
            FileEntry {
                name,
                path,
                given,
                read_only,
            }
        })
        .collect();
    let folders = state
        .folders
        .folders
        .iter()
        .map(|f| f.display().to_string())
        .collect();
    Json(FileList { files, folders })
}

/// The query naming a file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileQuery {
    pub path: String,
}

/// The answer of `GET /api/file`.
#[derive(Serialize)]
pub struct FileText {
    /// The file's path; for a package's own path, its rule file's.
    pub path: String,
    pub text: String,
    pub encoding: Encoding,
    /// `lf` or `crlf`: how lines end in the file (the text keeps them).
    pub line_endings: &'static str,
    /// Whether it is a rule file inside a package, which the studio does not save.
    pub read_only: bool,
}

/// `GET /api/file?path=…`: the text of a file, decoded.
pub async fn read(
    State(state): State<StudioState>,
    ApiQuery(query): ApiQuery<FileQuery>,
) -> Result<Json<FileText>, ApiError> {
    // A packaged rule file has no path of its own on disk, and is never saved.
    let (shown, bytes, real) = match state.folders.resolve_source(&query.path)? {
        Source::File(real) => {
            let bytes = std::fs::read(&real)
                .map_err(|e| ApiError::bad_request(format!("cannot read `{}`: {e}", query.path)))?;
            (query.path, bytes, Some(real))
        }
        Source::Packaged(rule) => {
            let bytes = rule.package.file(&rule.entry).map(|b| b.to_vec());
            (rule.path(), bytes.unwrap_or_default(), None)
        }
    };
    let (text, encoding) = decode(bytes);
    let crlf = text.contains("\r\n");
    if let Some(real) = &real {
        state
            .formats
            .0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert(real.clone(), Format { encoding, crlf });
    }
    Ok(Json(FileText {
        path: shown,
        text,
        encoding,
        line_endings: if crlf { "crlf" } else { "lf" },
        read_only: real.is_none(),
    }))
}

/// The body of `PUT /api/file`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SaveRequest {
    pub path: String,
    pub text: String,
}

/// The answer of `PUT /api/file`.
#[derive(Serialize)]
pub struct Saved {
    pub path: String,
    pub bytes: usize,
    pub encoding: Encoding,
    pub line_endings: &'static str,
}

/// `PUT /api/file`: writes the text back in the encoding and line endings the file was read in
/// (a file not read yet: as it is on disk now).
pub async fn save(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<SaveRequest>,
) -> Result<Json<Saved>, ApiError> {
    let real = match state.folders.resolve_source(&request.path)? {
        Source::File(real) => real,
        Source::Packaged(rule) => {
            return Err(ApiError::forbidden(format!(
                "`{}` is inside the rule package {}, which the studio does not write: edits derive, but are not saved",
                rule.path(),
                rule.package.name()
            )));
        }
    };
    let known = state
        .formats
        .0
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .get(&real)
        .copied();
    let format = match known {
        Some(format) => format,
        None => {
            let bytes = std::fs::read(&real).map_err(|e| {
                ApiError::bad_request(format!("cannot read `{}`: {e}", request.path))
            })?;
            let (text, encoding) = decode(bytes);
            Format {
                encoding,
                crlf: text.contains("\r\n"),
            }
        }
    };
    let bytes = encode(&request.text, format)
        .map_err(|e| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, e))?;
    write_atomically(&real, &bytes).map_err(|e| {
        ApiError::new(
            StatusCode::CONFLICT,
            format!("cannot write `{}`: {e}", request.path),
        )
    })?;
    Ok(Json(Saved {
        path: request.path,
        bytes: bytes.len(),
        encoding: format.encoding,
        line_endings: if format.crlf { "crlf" } else { "lf" },
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decoding_and_encoding_round_trip_each_encoding() {
        let latin = b"// caf\xe9 \x80\r\nLot --> X.\r\n".to_vec();
        let (text, encoding) = decode(latin.clone());
        assert_eq!(encoding, Encoding::Windows1252);
        assert_eq!(text, "// café €\r\nLot --> X.\r\n");
        let format = Format {
            encoding,
            crlf: true,
        };
        assert_eq!(encode(&text.replace("\r\n", "\n"), format).unwrap(), latin);
        let (text, encoding) = decode("\u{feff}a\n".as_bytes().to_vec());
        assert_eq!((text.as_str(), encoding), ("a\n", Encoding::Utf8Bom));
        let bom = Format {
            encoding,
            crlf: false,
        };
        assert_eq!(encode("a\n", bom).unwrap(), "\u{feff}a\n".as_bytes());
    }

    #[test]
    fn a_character_windows_1252_lacks_is_refused_with_its_line() {
        let format = Format {
            encoding: Encoding::Windows1252,
            crlf: false,
        };
        assert_eq!(
            encode("a\n// \u{4e2d}\n", format).unwrap_err(),
            "line 2: `\u{4e2d}` (U+4E2D) cannot be written in Windows-1252, the file's encoding"
        );
    }
}
