//! `shapegram.derive_tiles` and `shapegram.merge_tiles`: a city of footprints derived into a 3D
//! Tiles tileset, whole or one shard of it, and the shards joined; what a distributed scheduler
//! (Dask, Ray) maps over shards, one call per task (docs/tiles.md, "Many machines").

use std::ffi::CString;
use std::path::PathBuf;
use std::sync::Arc;

use pyo3::exceptions::{PyTypeError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use shapegram_eval::DeriveControl;
use shapegram_export::tiles::{Crs, Shard, TileEncoding, TileGrid};
use shapegram_runtime::lots::{Collected, Placing};
use shapegram_runtime::tiles::{Tiling, stream};
use shapegram_runtime::{Error as EngineError, Settings};

use crate::errors::{guard, to_py};
use crate::grammar::{Grammar, attr_value};

/// Derives the lots of the footprint files `lots` (GeoJSON or OBJ; a path or a list of paths)
/// with the grammar file `grammar` into a tileset in `out_dir`, cell by cell, as `shapegram
/// derive GRAMMAR --lots … --tiles OUT_DIR` does: `shard=(k, n)` writes only shard k of n
/// (its parent tiles and `tileset.shard-k-of-n.json`, for `merge_tiles`), `None` the whole
/// tileset. `tile_size` is the grid cell's side in metres, `crs` the GeoJSON positions'
/// coordinate system (`"local"`, `"wgs84"`, `"EPSG:32633"`), `halo` the context around a cell
/// for grammars with context rules. `metadata=True` makes each lot a feature of its tiles with
/// a row of its rule, path, attributes and reports in each tile's property table
/// (EXT_mesh_features, EXT_structural_metadata; `--metadata`). `quantize=True` stores the
/// tiles' vertices as small integers (KHR_mesh_quantization; `--quantize`), `meshopt=True`
/// quantises and compresses them (EXT_meshopt_compression, whose decoder viewers need;
/// `--meshopt`, which wins over `quantize`), and `normals=True` writes flat faces' normals
/// (`--normals`). Returns counts: near, far and lots (of the tiles written), derived (lots
/// derived, context included), shapes and leaves. Parts of the files that are skipped (holes,
/// points, polygons without area) are each a `UserWarning`. Releases the GIL.
#[pyfunction]
#[pyo3(signature = (grammar, lots, out_dir, *, shard=None, tile_size=200.0, crs="local",
                    halo=20.0, seed=0, attrs=None, metadata=false, quantize=false,
                    meshopt=false, normals=false))]
#[allow(clippy::too_many_arguments)]
pub fn derive_tiles<'py>(
    py: Python<'py>,
    grammar: PathBuf,
    lots: &Bound<'py, PyAny>,
    out_dir: PathBuf,
    shard: Option<(u32, u32)>,
    tile_size: f64,
    crs: &str,
    halo: f64,
    seed: u64,
    attrs: Option<&Bound<'py, PyDict>>,
    metadata: bool,
    quantize: bool,
    meshopt: bool,
    normals: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let files = footprint_files(lots)?;
    let shard = shard.map(shard_of).transpose()?;
    if !(1.0..=1e6).contains(&tile_size) {
        return Err(PyValueError::new_err(format!(
            "tile_size is {tile_size}: expected a tile size in metres from 1 to 1,000,000"
        )));
    }
    if !(0.0..=1e6).contains(&halo) {
        return Err(PyValueError::new_err(format!(
            "halo is {halo}: expected a halo in metres from 0 to 1,000,000"
        )));
    }
    let crs = Crs::parse(crs).map_err(PyValueError::new_err)?;
    let loaded = Grammar::load(py, grammar, None, None, None)?;
    let engine = loaded.engine();
    if engine.is_goal() {
        return Err(PyValueError::new_err(
            "goal grammars start from their axioms, not from lots: they are not tiled",
        ));
    }
    let mut values = Vec::new();
    for (name, value) in attrs.into_iter().flat_map(|d| d.iter()) {
        let name: String = name
            .extract()
            .map_err(|_| PyTypeError::new_err("attribute names are strings"))?;
        let value = attr_value(&name, &value)?;
        engine.check_attr(&name, &value).map_err(to_py)?;
        values.push((name, value));
    }
    let encoding = TileEncoding::from_flags(quantize, meshopt, normals);
    let settings = Settings {
        seed,
        attrs: values,
        lots: Vec::new(),
        generations: None,
        control: Arc::new(DeriveControl::new()),
    };
    let (tiled, warnings) = py.detach(|| {
        guard(|| {
            let placing = Placing {
                crs,
                recentre: true,
            };
            let Collected {
                lots,
                frame,
                warnings,
            } = shapegram_runtime::lots::collect(Vec::new(), &files, placing).map_err(to_py)?;
            let tiling = Tiling {
                grid: TileGrid { size: tile_size },
                halo: engine.has_context_rules().then_some(halo),
                shard,
                metadata: metadata.then(|| engine.attr_names()),
                encoding,
            };
            let derive = |cell: &[_], _own: &[bool]| {
                if metadata {
                    engine.derivation_with_tree(cell, &settings)
                } else {
                    engine.derivation(cell, &settings)
                }
            };
            let tiled = stream::<EngineError>(&lots, frame, &out_dir, tiling, derive, true)
                .map_err(to_py)?;
            Ok((tiled, warnings))
        })
    })?;
    // What the command prints as `warning:` lines: parts of the files that were skipped.
    let category = py.get_type::<PyUserWarning>();
    for warning in warnings {
        let message = CString::new(warning.replace('\0', " ")).expect("NUL bytes are replaced");
        PyErr::warn(py, &category, &message, 1)?;
    }
    let counts = PyDict::new(py);
    counts.set_item("near", tiled.summary.near)?;
    counts.set_item("far", tiled.summary.far)?;
    counts.set_item("lots", tiled.summary.lots)?;
    counts.set_item("derived", tiled.derived)?;
    counts.set_item("shapes", tiled.shapes)?;
    counts.set_item("leaves", tiled.leaves)?;
    Ok(counts)
}

/// Joins the shards that `derive_tiles(…, shard=(k, n))` wrote into the folders `dirs` into
/// one tileset in `out_dir` (the tiles copied there unless they are there already), as
/// `shapegram tiles merge DIRS… --out OUT_DIR` does: the same bytes as the whole run. Every
/// shard must be there once. Returns the counts near, far and lots. Releases the GIL.
#[pyfunction]
pub fn merge_tiles<'py>(
    py: Python<'py>,
    dirs: Vec<PathBuf>,
    out_dir: PathBuf,
) -> PyResult<Bound<'py, PyDict>> {
    let summary = py.detach(|| {
        guard(|| {
            shapegram_export::tiles::merge(&dirs, &out_dir)
                .map_err(|e| to_py(EngineError::io(e.to_string())))
        })
    })?;
    let counts = PyDict::new(py);
    counts.set_item("near", summary.near)?;
    counts.set_item("far", summary.far)?;
    counts.set_item("lots", summary.lots)?;
    Ok(counts)
}

/// The footprint files: one path, or a list of them.
fn footprint_files(lots: &Bound<'_, PyAny>) -> PyResult<Vec<PathBuf>> {
    let files: Vec<PathBuf> = if lots.is_instance_of::<PyString>() {
        vec![lots.extract()?]
    } else if let Ok(one) = lots.extract::<PathBuf>() {
        vec![one]
    } else {
        lots.extract().map_err(|_| {
            PyTypeError::new_err("lots is a footprint file's path or a list of them")
        })?
    };
    if files.is_empty() {
        return Err(PyValueError::new_err("lots names no footprint file"));
    }
    Ok(files)
}

/// Shard `k` of `n`, checked.
fn shard_of((index, count): (u32, u32)) -> PyResult<Shard> {
    if count == 0 {
        return Err(PyValueError::new_err(
            "shard=(k, 0): a tileset needs at least 1 shard",
        ));
    }
    if index >= count {
        return Err(PyValueError::new_err(format!(
            "shard=({index}, {count}): shards of {count} are numbered 0 to {}",
            count - 1
        )));
    }
    Ok(Shard { index, count })
}
