//! Shapegram's grammar files as the `shapegram` command and the C ABI read them: the text
//! (UTF-8, or Windows-1252 as CityEngine writes it), the files it imports, a goal grammar's
//! library, and the assets, tables and file searches its rules ask for, found as CityEngine
//! finds them, on disk or in a CityEngine rule package (`.rpk`).

mod assets;
mod files;
mod grammar;
mod library;
mod package;
mod search;

pub use assets::{FileAssets, MissingAssets};
pub use files::Files;
pub use grammar::{
    Compiled, Read, compile, compile_in, compile_in_style, import_path, read, read_in,
};
pub use library::{
    CompiledLibrary, NameClash, check_library_names, check_library_path, compile_library,
    goal_dialect, library_files,
};
pub use package::{MAX_UNPACKED, PackageError, RulePackage, is_package};
pub use search::search;
