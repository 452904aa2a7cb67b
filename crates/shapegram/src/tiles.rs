//! `derive --tiles`: the derived lots written as a 3D Tiles tileset (docs/tiles.md).

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

use shapegram_eval::{Derivation, InitialShape};
use shapegram_export::tiles::{Cell, TileGrid, TilesetSummary, TilesetWriter};
use shapegram_geom::{DVec2, Model};

use crate::Failure;
use crate::lots::Frame;

/// Writes the leaves of `derivation`, grown from `lots`, as a tileset in `dir`: each lot in
/// the grid cell of its footprint, each cell's lots one leaf tile. Implicit solids and
/// skeletons are left out (a warning says so unless `quiet`).
pub fn write(
    derivation: &Derivation,
    lots: &[InitialShape],
    frame: Frame,
    dir: &Path,
    grid: TileGrid,
    quiet: bool,
) -> Result<TilesetSummary, Failure> {
    if !quiet && (!derivation.solids.is_empty() || !derivation.skeletons.is_empty()) {
        eprintln!(
            "warning: --tiles writes the leaves' geometry: implicit solids and skeletons are \
             left out"
        );
    }
    let mut cells: BTreeMap<Cell, Vec<usize>> = BTreeMap::new();
    for (index, lot) in lots.iter().enumerate() {
        let corners = lot.footprint.iter().map(|p| DVec2::new(p.x, p.z));
        if let Some(cell) = grid.cell_of(corners) {
            cells.entry(cell).or_default().push(index);
        }
    }
    let leaves = leaves_by_lot(derivation, lots.len());
    let mut writer = TilesetWriter::new(dir, grid, frame.transform())?;
    for (cell, members) in cells {
        let models = members
            .iter()
            .map(|&lot| lot_model(derivation, leaves[lot].clone()))
            .collect();
        writer.add(cell, models)?;
    }
    let summary = writer.finish()?;
    if summary.near == 0 {
        return Err(Failure::new(format!(
            "nothing to tile in {}: no lot has geometry",
            dir.display()
        )));
    }
    Ok(summary)
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

/// One lot's leaves as a model, as [`Derivation::to_model`] makes it.
fn lot_model(derivation: &Derivation, leaves: Range<usize>) -> Model {
    let lot = Derivation {
        leaves: derivation.leaves[leaves].to_vec(),
        ..Derivation::default()
    };
    lot.to_model()
}
