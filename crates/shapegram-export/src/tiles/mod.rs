//! OGC 3D Tiles 1.1 tilesets of a city: lots assigned to a square grid, two levels of detail,
//! glTF (GLB) content, and georeferencing (`docs/tiles.md`).
//!
//! Tiling: the local frame's ground plane (x east, y north in the tileset; the grammar's x and
//! −z) is cut into square cells of [`TileGrid::size`] metres with a corner at the frame's
//! origin. A lot belongs to the cell that holds the mean of its footprint's corners, so the
//! assignment depends on that lot alone (a shard of the lots can be derived apart). Each
//! non-empty cell is a leaf tile whose content is the full model of its lots ("near"); the
//! cells are grouped [`PARENT_SPAN`] × [`PARENT_SPAN`] into parent tiles whose content is one
//! box per lot ("far", the masses). The root has no content and the tree refines by REPLACE.
//! Several machines can share the work by [`Shard`]: each writes whole parent tiles and its
//! part of tileset.json, and [`merge`] joins the parts.

mod crs;
mod shards;
mod tileset;

pub use crs::{Crs, EnuFrame, Geodetic};
pub use shards::{Shard, merge};
pub use tileset::{TileEncoding, TileLot, TilesetSummary, TilesetWriter};

use shapegram_geom::DVec2;

/// How many leaf cells along each side a parent tile holds.
pub const PARENT_SPAN: i64 = 4;

/// A cell of the grid: its column (east) and row (north), counted from the frame's origin.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Cell {
    /// Cells east of the origin, negative to the west.
    pub east: i64,
    /// Cells north of the origin, negative to the south.
    pub north: i64,
}

impl Cell {
    /// The parent tile's cell (on the grid of [`PARENT_SPAN`] times larger cells).
    pub fn parent(self) -> Cell {
        Cell {
            east: self.east.div_euclid(PARENT_SPAN),
            north: self.north.div_euclid(PARENT_SPAN),
        }
    }

    /// Its name in file names: `east_north`.
    pub fn name(self) -> String {
        format!("{}_{}", self.east, self.north)
    }
}

/// The square grid that assigns lots to leaf tiles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileGrid {
    /// The side of a leaf cell in metres.
    pub size: f64,
}

impl TileGrid {
    /// The cell of a lot whose footprint has these corners, in the grammar's ground plane
    /// (x east, z south); `None` for no corners or a non-finite mean.
    pub fn cell_of(&self, corners: impl ExactSizeIterator<Item = DVec2>) -> Option<Cell> {
        let n = corners.len();
        let sum = corners.fold(DVec2::ZERO, |sum, p| sum + p);
        let mean = sum / n as f64;
        if n == 0 || !mean.is_finite() {
            return None;
        }
        // Cells are whole numbers of cells from the origin: an f64 floor stays exact far
        // beyond any city.
        let index = |v: f64| (v / self.size).floor() as i64;
        Some(Cell {
            east: index(mean.x),
            north: index(-mean.y),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lots_belong_to_the_cell_of_their_corners_mean() {
        let grid = TileGrid { size: 100.0 };
        let corners =
            |c: &[(f64, f64)]| c.iter().map(|&(x, z)| DVec2::new(x, z)).collect::<Vec<_>>();
        // Mean (50, -150): 50 m east, 150 m north.
        let lot = corners(&[
            (0.0, -100.0),
            (100.0, -100.0),
            (100.0, -200.0),
            (0.0, -200.0),
        ]);
        assert_eq!(
            grid.cell_of(lot.into_iter()),
            Some(Cell { east: 0, north: 1 })
        );
        let west = corners(&[(-0.5, 0.5), (-0.1, 0.5), (-0.3, 0.1)]);
        assert_eq!(
            grid.cell_of(west.into_iter()),
            Some(Cell {
                east: -1,
                north: -1
            })
        );
        assert_eq!(grid.cell_of(Vec::new().into_iter()), None);
        assert_eq!(
            Cell { east: -1, north: 7 }.parent(),
            Cell { east: -1, north: 1 }
        );
        assert_eq!(
            Cell { east: 4, north: 3 }.parent(),
            Cell { east: 1, north: 0 }
        );
        assert_eq!(
            Cell {
                east: -3,
                north: 12
            }
            .name(),
            "-3_12"
        );
    }
}
