//! Shapegram's C ABI: a handle (`sg_state`) that holds a grammar of any kind the engine runs,
//! the settings of a derivation (seed, attributes, lots, generations) and the mesh buffers of
//! the last derivation, after the thesis's GrammarState. `include/shapegram.h` is generated
//! from this crate by cbindgen (`cargo test -p shapegram-ffi` fails when it is stale);
//! `docs/runtimes.md` tells how to build, link and use it.
//!
//! Every entry point catches panics and returns a status; a handle admits one call at a time
//! (an atomic flag: a second, concurrent call gets `SG_BUSY`), except `sg_state_cancel` and
//! `sg_state_progress`, which may be called from any thread while a derivation runs.

#![allow(unsafe_code)]

mod abi;
mod status;

pub use abi::*;
pub use status::{Error, sg_status};
