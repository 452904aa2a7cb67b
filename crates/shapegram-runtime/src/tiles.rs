//! Tiled cities: lots derived cell by cell (or from a whole derivation) and written as a 3D
//! Tiles tileset, by one machine or in shards that `shapegram_export::tiles::merge` joins; what
//! `shapegram derive --tiles` and the Python module's tiled runs share (docs/tiles.md).

use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use shapegram_eval::{Derivation, InitialShape};
use shapegram_export::tiles::{
    Cell, Shard, TileEncoding, TileGrid, TileLot, TilesetSummary, TilesetWriter,
};
use shapegram_geom::{DVec2, Metadata, Model};

use crate::Error;
use crate::lots::Frame;

/// How a tiled run cuts the city: the grid, the context around each cell, the shard, whether
/// tiles carry the lots' metadata, and how their GLBs store vertices.
#[derive(Clone, Debug)]
pub struct Tiling {
    /// The grid of leaf cells.
    pub grid: TileGrid,
    /// For grammars with context rules: how far around a cell lots are derived as context,
    /// in metres. `None`: lots derive on their own.
    pub halo: Option<f64>,
    /// The shard to write, `None` for the whole tileset.
    pub shard: Option<Shard>,
    /// For tiles with each lot's metadata as a feature (`--metadata`): the grammar's
    /// attribute names (`Program::attr_names`), with which the derivations kept their trees.
    /// `None`: tiles without metadata.
    pub metadata: Option<Vec<String>>,
    /// How every tile's GLB stores its vertices (`--quantize`, `--meshopt`, `--normals`).
    pub encoding: TileEncoding,
}

/// What a tiled run wrote and derived.
#[derive(Debug, Default)]
pub struct Tiled {
    /// The tiles written.
    pub summary: TilesetSummary,
    /// Lots derived, the context around cells included.
    pub derived: usize,
    /// Shapes made, in every cell's derivation.
    pub shapes: usize,
    /// Leaves of the lots of the tiles.
    pub leaves: usize,
}

/// Derives the lots cell by cell and writes each cell's tile as soon as it is derived, so
/// that only one cell's derivation is held at a time. `derive` derives a list of lots (each
/// numbered by its place in `lots`, so that it derives as it would among all of them); a
/// cell's list is its lots and, with a halo, the lots within the halo around it as context,
/// in the order of `lots`, and `derive` is told which are the cell's own (`true`) and which
/// are context (`false`). With a shard, only the cells of its parent tiles are derived.
/// Errors are `derive`'s, or [`Error`]s of writing the tiles.
pub fn stream<E: From<Error>>(
    lots: &[InitialShape],
    frame: Frame,
    dir: &Path,
    tiling: Tiling,
    mut derive: impl FnMut(&[InitialShape], &[bool]) -> Result<Derivation, E>,
    quiet: bool,
) -> Result<Tiled, E> {
    let cells = cells_of(lots, tiling.grid);
    let cells = match tiling.shard {
        Some(shard) => in_shard(cells, shard),
        None => cells,
    };
    let halo = tiling.halo.map(|halo| Halo::new(lots, tiling.grid, halo));
    let mut writer = TilesetWriter::new(dir, tiling.grid, frame.transform(), tiling.encoding)
        .map_err(written)?;
    let mut tiled = Tiled::default();
    let mut warned = quiet;
    for (cell, members) in cells {
        let derived: Vec<usize> = match &halo {
            Some(halo) => {
                let mut all: BTreeSet<usize> = members.iter().copied().collect();
                all.extend(halo.around(cell));
                all.into_iter().collect()
            }
            None => members.clone(),
        };
        let numbered: Vec<InitialShape> = derived
            .iter()
            .map(|&i| InitialShape {
                index: Some(i as u64),
                ..lots[i].clone()
            })
            .collect();
        let own: Vec<bool> = derived
            .iter()
            .map(|i| members.binary_search(i).is_ok())
            .collect();
        let derivation = derive(&numbered, &own)?;
        if !warned {
            warned = warn_unwritten(&derivation);
        }
        let leaves = leaves_by_lot(&derivation, numbered.len());
        // Paths name each lot by its number in the city, not in the cell.
        let numbers: Vec<u32> = derived.iter().map(|&i| i as u32).collect();
        let metadata = lots_metadata(&derivation, tiling.metadata.as_deref(), &numbers);
        let models = members
            .iter()
            .map(|&lot| {
                let at = derived.binary_search(&lot).expect("members are derived");
                tiled.leaves += leaves[at].len();
                TileLot {
                    index: lot,
                    model: lot_model(&derivation, leaves[at].clone()),
                    metadata: metadata.get(at).cloned().flatten(),
                }
            })
            .collect();
        tiled.derived += numbered.len();
        tiled.shapes += derivation.stats.shapes;
        drop(derivation);
        // Cells come in order: the far tiles before this cell are complete.
        writer.write_far_before(cell).map_err(written)?;
        writer.add_lots(cell, models).map_err(written)?;
    }
    tiled.summary = match tiling.shard {
        Some(shard) => writer.finish_shard(shard),
        None => writer.finish(),
    }
    .map_err(written)?;
    if tiling.shard.is_none() {
        nothing_to_tile(dir, &tiled.summary)?;
    }
    Ok(tiled)
}

/// Writes the leaves of `derivation`, grown from `lots`, as a tileset in `dir`: each lot in
/// the grid cell of its footprint, each cell's lots one leaf tile, with each lot's metadata
/// as a feature when `metadata` gives the grammar's attribute names (see
/// [`Tiling::metadata`]), every GLB in `encoding`. Implicit solids and skeletons are left out
/// (a warning says so unless `quiet`).
#[allow(clippy::too_many_arguments)]
pub fn write(
    derivation: &Derivation,
    lots: &[InitialShape],
    frame: Frame,
    dir: &Path,
    grid: TileGrid,
    metadata: Option<&[String]>,
    encoding: TileEncoding,
    quiet: bool,
) -> Result<TilesetSummary, Error> {
    if !quiet {
        warn_unwritten(derivation);
    }
    let leaves = leaves_by_lot(derivation, lots.len());
    let described = lots_metadata(derivation, metadata, &[]);
    let mut writer = TilesetWriter::new(dir, grid, frame.transform(), encoding).map_err(written)?;
    for (cell, members) in cells_of(lots, grid) {
        let models = members
            .iter()
            .map(|&lot| TileLot {
                index: lot,
                model: lot_model(derivation, leaves[lot].clone()),
                metadata: described.get(lot).cloned().flatten(),
            })
            .collect();
        writer.write_far_before(cell).map_err(written)?;
        writer.add_lots(cell, models).map_err(written)?;
    }
    let summary = writer.finish().map_err(written)?;
    nothing_to_tile(dir, &summary)?;
    Ok(summary)
}

/// Says that implicit solids and skeletons are not written, when the derivation has some;
/// returns whether it said so.
fn warn_unwritten(derivation: &Derivation) -> bool {
    let unwritten = !derivation.solids.is_empty() || !derivation.skeletons.is_empty();
    if unwritten {
        eprintln!(
            "warning: --tiles writes the leaves' geometry: implicit solids and skeletons are \
             left out"
        );
    }
    unwritten
}

/// An error of writing the tileset's files.
fn written(error: shapegram_export::Error) -> Error {
    Error::io(error.to_string())
}

/// A tileset without geometry is an error.
fn nothing_to_tile(dir: &Path, summary: &TilesetSummary) -> Result<(), Error> {
    if summary.near == 0 {
        return Err(Error::invalid(format!(
            "nothing to tile in {}: no lot has geometry",
            dir.display()
        )));
    }
    Ok(())
}

/// The lots of each cell, by the mean of their footprint's corners; cells in order.
fn cells_of(lots: &[InitialShape], grid: TileGrid) -> Vec<(Cell, Vec<usize>)> {
    let mut cells: BTreeMap<Cell, Vec<usize>> = BTreeMap::new();
    for (index, lot) in lots.iter().enumerate() {
        let corners = lot.footprint.iter().map(|p| DVec2::new(p.x, p.z));
        if let Some(cell) = grid.cell_of(corners) {
            cells.entry(cell).or_default().push(index);
        }
    }
    cells.into_iter().collect()
}

/// The cells of a shard's parent tiles, in order.
fn in_shard(cells: Vec<(Cell, Vec<usize>)>, shard: Shard) -> Vec<(Cell, Vec<usize>)> {
    let parents: Vec<Cell> = cells
        .iter()
        .map(|(cell, _)| cell.parent())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let mine: BTreeSet<Cell> = parents[shard.parents(parents.len())]
        .iter()
        .copied()
        .collect();
    cells
        .into_iter()
        .filter(|(cell, _)| mine.contains(&cell.parent()))
        .collect()
}

/// Which lots lie within the halo of a cell: those whose footprint's bounds (on the ground),
/// grown by the halo, meet the cell's square. Lots are found through the cells their grown
/// bounds cover; a lot that covers very many cells is tested against every cell instead.
struct Halo {
    grid: TileGrid,
    halo: f64,
    /// Each lot's bounds on the ground: x east, y north.
    bounds: Vec<(DVec2, DVec2)>,
    near: BTreeMap<Cell, Vec<usize>>,
    wide: Vec<usize>,
}

/// More cells than this under one lot's grown bounds and the lot is tested for every cell.
const MOST_CELLS_PER_LOT: i64 = 1024;

impl Halo {
    fn new(lots: &[InitialShape], grid: TileGrid, halo: f64) -> Self {
        let bounds: Vec<(DVec2, DVec2)> = lots
            .iter()
            .map(|lot| {
                let ground = lot.footprint.iter().map(|p| DVec2::new(p.x, -p.z));
                let min = ground.clone().fold(DVec2::INFINITY, DVec2::min);
                let max = ground.fold(DVec2::NEG_INFINITY, DVec2::max);
                (min, max)
            })
            .collect();
        let mut near: BTreeMap<Cell, Vec<usize>> = BTreeMap::new();
        let mut wide = Vec::new();
        for (i, (min, max)) in bounds.iter().enumerate() {
            // One cell more on each side: the exact test in `around` decides.
            let range = |lo: f64, hi: f64| {
                let index = |v: f64| (v / grid.size).floor() as i64;
                (index(lo - halo) - 1)..(index(hi + halo) + 2)
            };
            let (east, north) = (range(min.x, max.x), range(min.y, max.y));
            let many = (east.end - east.start).saturating_mul(north.end - north.start);
            if !(min.is_finite() && max.is_finite()) || many > MOST_CELLS_PER_LOT {
                wide.push(i);
                continue;
            }
            for e in east {
                for n in north.clone() {
                    near.entry(Cell { east: e, north: n }).or_default().push(i);
                }
            }
        }
        Self {
            grid,
            halo,
            bounds,
            near,
            wide,
        }
    }

    /// The lots within the halo of `cell`.
    fn around(&self, cell: Cell) -> impl Iterator<Item = usize> + '_ {
        let size = self.grid.size;
        let lo = DVec2::new(cell.east as f64 * size, cell.north as f64 * size) - self.halo;
        let hi = lo + size + 2.0 * self.halo;
        let meets = move |&i: &usize| {
            let (min, max) = self.bounds[i];
            min.x <= hi.x && max.x >= lo.x && min.y <= hi.y && max.y >= lo.y
        };
        self.near
            .get(&cell)
            .into_iter()
            .flatten()
            .chain(&self.wide)
            .copied()
            .filter(meets)
    }
}

/// The range of [`Derivation::leaves`] of each lot: they come lot by lot.
fn leaves_by_lot(derivation: &Derivation, lots: usize) -> Vec<Range<usize>> {
    let mut ranges = vec![0..0; lots];
    let mut start = 0;
    let leaves = &derivation.leaves;
    while start < leaves.len() {
        let lot = leaves[start].lot;
        let end = start + leaves[start..].partition_point(|l| l.lot == lot);
        if let Some(range) = ranges.get_mut(lot as usize) {
            *range = start..end;
        }
        start = end;
    }
    ranges
}

/// Each lot's metadata by its index in `derivation` (see [`Derivation::lot_metadata`]), when
/// `attr_names` asks for it; none otherwise.
fn lots_metadata(
    derivation: &Derivation,
    attr_names: Option<&[String]>,
    numbers: &[u32],
) -> Vec<Option<Arc<Metadata>>> {
    match attr_names {
        Some(names) => derivation.lot_metadata(names, numbers),
        None => Vec::new(),
    }
}

/// One lot's leaves as a model, as [`Derivation::to_model`] makes it.
fn lot_model(derivation: &Derivation, leaves: Range<usize>) -> Model {
    let lot = Derivation {
        leaves: derivation.leaves[leaves].to_vec(),
        names: derivation.names.clone(),
        paints: derivation.paints.clone(),
        ..Derivation::default()
    };
    lot.to_model()
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_export::tiles::PARENT_SPAN;

    fn square(x: f64, north: f64, side: f64) -> InitialShape {
        let corners = [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)]
            .map(|(dx, dn)| DVec2::new(x + dx, -(north + dn)));
        InitialShape::from_xz(&corners).unwrap()
    }

    #[test]
    fn the_halo_of_a_cell_holds_the_lots_whose_bounds_come_that_close() {
        let grid = TileGrid { size: 100.0 };
        let lots = [
            square(10.0, 10.0, 20.0),   // in cell (0, 0)
            square(105.0, 50.0, 10.0),  // 5 m east of it
            square(125.0, 50.0, 10.0),  // 25 m east
            square(-40.0, -40.0, 30.0), // touching its south-west corner at 10 m
            square(50.0, 300.0, 10.0),  // far north
            square(-5e4, -5e4, 1e5),    // a lot over many cells: holds every cell
        ];
        let halo = Halo::new(&lots, grid, 10.0);
        let around: BTreeSet<usize> = halo.around(Cell { east: 0, north: 0 }).collect();
        assert_eq!(around, BTreeSet::from([0, 1, 3, 5]));
        let wider = Halo::new(&lots, grid, 25.0);
        let around: BTreeSet<usize> = wider.around(Cell { east: 0, north: 0 }).collect();
        assert_eq!(around, BTreeSet::from([0, 1, 2, 3, 5]));
        assert_eq!(halo.wide, [5]);
    }

    #[test]
    fn shards_take_whole_parent_tiles() {
        let span = PARENT_SPAN;
        let cells: Vec<(Cell, Vec<usize>)> = [(0, 0), (1, 3), (span, 0), (0, span), (-1, 0)]
            .iter()
            .enumerate()
            .map(|(i, &(east, north))| (Cell { east, north }, vec![i]))
            .collect::<BTreeMap<_, _>>()
            .into_iter()
            .collect();
        // Parents in order: (-1, 0), (0, 0) with two cells, (0, 1), (1, 0).
        let lots_of = |shard: Shard| -> Vec<usize> {
            in_shard(cells.clone(), shard)
                .into_iter()
                .flat_map(|(_, lots)| lots)
                .collect()
        };
        assert_eq!(lots_of(Shard { index: 0, count: 2 }), [4, 0, 1]);
        assert_eq!(lots_of(Shard { index: 1, count: 2 }), [3, 2]);
        assert_eq!(lots_of(Shard { index: 0, count: 1 }).len(), 5);
        assert!(lots_of(Shard { index: 0, count: 9 }).is_empty());
    }
}
