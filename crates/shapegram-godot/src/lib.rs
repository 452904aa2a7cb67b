//! Shapegram in Godot 4 (a GDExtension): the thesis's `GrammarState` resource, the
//! `GrammarMesh` that follows it and the `GrammarInstance3D` node that shows it, on the shared
//! runtime (`shapegram-runtime`). See docs/runtimes.md.

pub mod instance;
pub mod job;
pub mod mesh;
pub mod state;

use godot::prelude::*;

/// The extension's entry point (`shapegram_godot_init` in the `.gdextension` file).
struct Shapegram;

#[gdextension(entry_symbol = shapegram_godot_init)]
unsafe impl ExtensionLibrary for Shapegram {}
