//! The one error type of the crate: every message is a single line that names the file.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use crate::Format;

/// Why reading or writing a model failed.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The path has no extension we know (`.glb`, `.obj`, `.stl`).
    UnknownFormat(PathBuf),
    /// The file could not be read.
    Read {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: io::Error,
    },
    /// The file could not be written.
    Write {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: io::Error,
    },
    /// The contents are not a valid file of the format.
    Broken {
        /// The format the contents were read as.
        format: Format,
        /// The file, when the contents came from one.
        path: Option<PathBuf>,
        /// What is wrong, in one line.
        message: String,
    },
    /// Shards of a tileset that do not make one tileset (`tiles merge`).
    Shards {
        /// The folder or file at fault.
        path: PathBuf,
        /// What is wrong, in one line.
        message: String,
    },
}

impl Error {
    pub(crate) fn broken(format: Format, message: impl Into<String>) -> Self {
        Self::Broken {
            format,
            path: None,
            // Library messages sometimes span lines; ours promise one.
            message: message.into().replace('\n', " "),
        }
    }

    /// Readers of byte slices know no path; `load` adds it afterwards.
    pub(crate) fn at(self, file: &Path) -> Self {
        match self {
            Self::Broken {
                format,
                path: None,
                message,
            } => Self::Broken {
                format,
                path: Some(file.to_path_buf()),
                message,
            },
            other => other,
        }
    }
}

/// `io::Error` prints "No such file or directory (os error 2)"; the code is noise for users.
fn os_message(error: &io::Error) -> String {
    let text = error.to_string();
    match error.raw_os_error() {
        Some(code) => text
            .strip_suffix(&format!(" (os error {code})"))
            .map_or_else(|| text.clone(), str::to_owned),
        None => text,
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownFormat(path) => write!(
                f,
                "unknown file format '{}': use .glb, .obj or .stl",
                path.display()
            ),
            Self::Read { path, source } => {
                write!(f, "cannot read {}: {}", path.display(), os_message(source))
            }
            Self::Write { path, source } => {
                write!(f, "cannot write {}: {}", path.display(), os_message(source))
            }
            Self::Broken {
                format,
                path,
                message,
            } => {
                write!(f, "broken {} file", format.name())?;
                if let Some(path) = path {
                    write!(f, " {}", path.display())?;
                }
                write!(f, ": {message}")
            }
            Self::Shards { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Read { source, .. } | Self::Write { source, .. } => Some(source),
            Self::UnknownFormat(_) | Self::Broken { .. } | Self::Shards { .. } => None,
        }
    }
}
