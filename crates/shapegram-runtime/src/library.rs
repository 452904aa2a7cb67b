//! A goal grammar's library read from paths, as `shapegram derive --library` reads it.

use std::path::{Path, PathBuf};

use crate::error::Error;

/// The library of the goal grammar at `main`, read from `paths` as `shapegram derive
/// --library` reads them: files, and folders searched with their subfolders for goal grammars
/// (`*.goal`), all sorted by path, each once, `main` left out (so that a grammar's own folder
/// can be its library). Each comes as its path, which names it, and its text (UTF-8, else
/// Windows-1252), for [`crate::Grammar::load_with_library`]. A path that is neither a file nor
/// a folder, or a file or folder that cannot be read, is an error of kind
/// [`crate::ErrorKind::Io`].
pub fn read_library(paths: &[PathBuf], main: &Path) -> Result<Vec<(String, String)>, Error> {
    shapegram_load::library_files(paths, main)
        .map_err(Error::io)?
        .iter()
        .map(|path| {
            let read = shapegram_load::read(path).map_err(Error::io)?;
            Ok((read.source.name().to_owned(), read.source.text().to_owned()))
        })
        .collect()
}

/// Checks that `path` can be given to [`read_library`]: a file or a folder, else an error of
/// kind [`crate::ErrorKind::Io`] (what [`read_library`] would say of it), so that a host can
/// refuse it when it is given rather than when the grammar is loaded.
pub fn check_library_path(path: &Path) -> Result<(), Error> {
    shapegram_load::check_library_path(path).map_err(Error::io)
}
