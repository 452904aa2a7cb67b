//! Shapegram for host programs (the C ABI, game engines, Python, the studio): a grammar of any
//! kind the engine runs, loaded from text (a goal grammar with its library) or from a CityEngine
//! rule package (`.rpk`), and derivations of it into mesh buffers, with the same engine calls as
//! the `shapegram` command's `derive`, `lsystem`, `cave` and `topo`.

mod error;
mod grammar;
mod library;
pub mod lots;
mod package;
pub mod tiles;
mod topo;

pub use error::{Error, ErrorKind, Place};
pub use grammar::{AttrDecl, AttrType, Derived, Grammar, Kind, Settings, default_lot, lot};
pub use library::{check_library_path, read_library};
pub use package::Package;
pub use shapegram_load::is_package;
pub use topo::{TopoGrammar, TopoMesh};
