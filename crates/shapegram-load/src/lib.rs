//! Shapegram's grammar files as the `shapegram` command and the C ABI read them: the text
//! (UTF-8, or Windows-1252 as CityEngine writes it), the files it imports, and the assets,
//! tables and file searches its rules ask for, found as CityEngine finds them.

mod assets;
mod grammar;
mod search;

pub use assets::{FileAssets, MissingAssets};
pub use grammar::{Compiled, Read, compile, import_path, read};
pub use search::search;
