//! Shapegram's Python module, `shapegram`: load a grammar of any kind the engine runs, derive it
//! with a seed, attributes, lots and generations (with the GIL released) and read the result as
//! mesh buffers (`array.array`s) that Blender and numpy take in one copy. Errors are
//! exceptions whose messages carry `file:line:column`. Built with maturin as one abi3 module
//! for CPython 3.11 and later (`docs/runtimes.md`). Tiled cities are derived and their shards
//! merged by module functions that a distributed scheduler maps over shards (`docs/tiles.md`).

mod errors;
mod grammar;
mod mesh;
mod tiles;

use pyo3::prelude::*;

/// The module: its classes and exceptions.
#[pymodule]
fn shapegram(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    module.add_class::<grammar::Grammar>()?;
    module.add_function(wrap_pyfunction!(tiles::derive_tiles, module)?)?;
    module.add_function(wrap_pyfunction!(tiles::merge_tiles, module)?)?;
    module.add_class::<grammar::Attr>()?;
    module.add_class::<mesh::Mesh>()?;
    module.add_class::<mesh::Part>()?;
    module.add_class::<mesh::Joint>()?;
    module.add_class::<mesh::Texture>()?;
    module.add("NO_JOINT", shapegram_export::NO_JOINT)?;
    module.add("Error", py.get_type::<errors::Error>())?;
    module.add("GrammarError", py.get_type::<errors::GrammarError>())?;
    module.add("DeriveError", py.get_type::<errors::DeriveError>())?;
    module.add(
        "UnknownAttributeError",
        py.get_type::<errors::UnknownAttributeError>(),
    )?;
    module.add("PackageError", py.get_type::<errors::PackageError>())?;
    module.add(
        "AttributeTypeError",
        py.get_type::<errors::AttributeTypeError>(),
    )?;
    Ok(())
}
