//! Writing a tileset: near tiles as they come, far tiles and tileset.json at the end.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::{Value as Json, json};
use shapegram_geom::{Aabb, Color, DAffine3, DQuat, DVec3, Mesh, Model, Part, primitives};

use super::shards::{Shard, ShardPart};
use super::{Cell, TileGrid};
use crate::{Error, ExportOptions};

/// The folder of the full models, one GLB per leaf cell.
const NEAR: &str = "near";
/// The folder of the masses, one GLB per parent cell.
const FAR: &str = "far";
/// The masses' colour: light grey.
const MASS_COLOR: Color = Color {
    r: 0.75,
    g: 0.75,
    b: 0.72,
    a: 1.0,
};

/// What was written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TilesetSummary {
    /// Leaf tiles (full models).
    pub near: usize,
    /// Parent tiles (masses).
    pub far: usize,
    /// Lots in tiles (those with geometry).
    pub lots: usize,
}

/// A leaf tile written: its content's bounds and its lots' masses, in the grammar's frame.
struct Near {
    bounds: Aabb,
    masses: Vec<Aabb>,
}

/// Writes a tileset into a folder: [`TilesetWriter::add`] each leaf tile's model, then
/// [`TilesetWriter::finish`]. The output depends only on what is added, not on the order.
pub struct TilesetWriter {
    dir: PathBuf,
    grid: TileGrid,
    transform: [f64; 16],
    near: BTreeMap<Cell, Near>,
}

impl TilesetWriter {
    /// A writer into `dir` (made when missing, with its `near/` and `far/` folders), for
    /// leaf cells of `grid`, whose root tile has the `transform` from the grammar's frame
    /// turned z-up (x east, y north, z up) to the tileset's coordinates (ECEF when
    /// georeferenced): column-major, as in tileset.json.
    pub fn new(dir: &Path, grid: TileGrid, transform: [f64; 16]) -> Result<Self, Error> {
        for sub in [NEAR, FAR] {
            let path = dir.join(sub);
            std::fs::create_dir_all(&path).map_err(|source| Error::Write { path, source })?;
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            grid,
            transform,
            near: BTreeMap::new(),
        })
    }

    /// Writes the leaf tile of `cell`: `lots` are the models of its lots, in the grammar's
    /// frame, each of which also becomes one box (its bounds) in the far tile above. Lots
    /// without geometry are left out; a cell with none gets no tile.
    pub fn add(&mut self, cell: Cell, lots: Vec<Model>) -> Result<(), Error> {
        let mut masses = Vec::new();
        let mut model = Model::default();
        for lot in lots {
            let Some(bounds) = lot.bounds() else {
                continue;
            };
            masses.push(bounds);
            model.parts.extend(lot.parts);
            model.lines.extend(lot.lines);
        }
        let Some(bounds) = union(&masses) else {
            return Ok(());
        };
        let path = self.dir.join(NEAR).join(format!("{}.glb", cell.name()));
        crate::save(&model, &path, &ExportOptions::default())?;
        self.near.insert(cell, Near { bounds, masses });
        Ok(())
    }

    /// Writes the far tiles and tileset.json.
    pub fn finish(self) -> Result<TilesetSummary, Error> {
        let far = self.write_far()?;
        write_tileset(&self.dir, self.grid.size, self.transform, &far)
    }

    /// Writes the far tiles and, instead of tileset.json, the part of it that `shard` holds
    /// (`tileset.shard-K-of-N.json`), for [`super::merge`] to join with the other shards'.
    pub fn finish_shard(self, shard: Shard) -> Result<TilesetSummary, Error> {
        let far = self.write_far()?;
        let part = ShardPart {
            shard,
            tile_size: self.grid.size,
            transform: self.transform,
            far,
        };
        part.write(&self.dir)?;
        Ok(summary(&part.far))
    }

    /// Writes a far tile (the masses) for each parent cell of the leaf tiles added.
    fn write_far(&self) -> Result<Vec<FarTile>, Error> {
        let mut parents: BTreeMap<Cell, Vec<(Cell, &Near)>> = BTreeMap::new();
        for (&cell, near) in &self.near {
            parents.entry(cell.parent()).or_default().push((cell, near));
        }
        let mut far = Vec::with_capacity(parents.len());
        for (parent, children) in parents {
            let masses: Vec<Aabb> = children
                .iter()
                .flat_map(|(_, near)| near.masses.iter().copied())
                .collect();
            crate::save(
                &masses_model(&masses),
                &self.dir.join(FarTile::uri_of(parent)),
                &ExportOptions::default(),
            )?;
            far.push(FarTile {
                cell: parent,
                bounds: union(&masses).expect("a parent tile has children with masses"),
                error: far_error(&masses),
                lots: masses.len(),
                near: children
                    .iter()
                    .map(|(cell, near)| (*cell, near.bounds))
                    .collect(),
            });
        }
        Ok(far)
    }
}

/// A far tile as written: its parent cell, the bounds and geometric error of its masses, how
/// many lots it holds, and its leaf tiles with the bounds of their content.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FarTile {
    pub cell: Cell,
    pub bounds: Aabb,
    pub error: f64,
    pub lots: usize,
    pub near: Vec<(Cell, Aabb)>,
}

impl FarTile {
    /// The file of a parent cell's masses, relative to the tileset.
    pub fn uri_of(cell: Cell) -> String {
        format!("{FAR}/{}.glb", cell.name())
    }

    /// The file of a leaf cell's full model, relative to the tileset.
    pub fn near_uri_of(cell: Cell) -> String {
        format!("{NEAR}/{}.glb", cell.name())
    }
}

/// What tiles were written.
fn summary(far: &[FarTile]) -> TilesetSummary {
    TilesetSummary {
        near: far.iter().map(|f| f.near.len()).sum(),
        far: far.len(),
        lots: far.iter().map(|f| f.lots).sum(),
    }
}

/// Writes tileset.json in `dir` over the far tiles (in the order of their cells) of a grid of
/// `tile_size` metres, with the root's `transform`.
pub(crate) fn write_tileset(
    dir: &Path,
    tile_size: f64,
    transform: [f64; 16],
    far: &[FarTile],
) -> Result<TilesetSummary, Error> {
    let far_tiles: Vec<Json> = far
        .iter()
        .map(|tile| {
            let leaves: Vec<Json> = tile
                .near
                .iter()
                .map(|(cell, bounds)| {
                    json!({
                        "boundingVolume": { "box": tile_box(bounds) },
                        "geometricError": 0.0,
                        "content": { "uri": FarTile::near_uri_of(*cell) },
                    })
                })
                .collect();
            json!({
                "boundingVolume": { "box": tile_box(&tile.bounds) },
                "geometricError": tile.error,
                "refine": "REPLACE",
                "content": { "uri": FarTile::uri_of(tile.cell) },
                "children": leaves,
            })
        })
        .collect();
    // The root has no content: it refines into the far tiles from afar, once the city is
    // larger on screen than its extent's error allows.
    let all: Vec<Aabb> = far.iter().map(|tile| tile.bounds).collect();
    let extent = union(&all).unwrap_or(Aabb {
        min: DVec3::ZERO,
        max: DVec3::ZERO,
    });
    let far_error = far.iter().map(|tile| tile.error).fold(0.0, f64::max);
    let root_error = (extent.max - extent.min)
        .length()
        .max(2.0 * far_error)
        .max(tile_size);
    let tileset = json!({
        "asset": {
            "version": "1.1",
            "generator": concat!("shapegram ", env!("CARGO_PKG_VERSION")),
        },
        "geometricError": root_error,
        "root": {
            "transform": transform,
            "boundingVolume": { "box": tile_box(&extent) },
            "geometricError": root_error,
            "refine": "REPLACE",
            "children": far_tiles,
        },
    });
    let path = dir.join("tileset.json");
    let mut text = serde_json::to_string_pretty(&tileset).expect("JSON values serialise");
    text.push('\n');
    std::fs::write(&path, text).map_err(|source| Error::Write { path, source })?;
    Ok(summary(far))
}

/// The smallest box holding all of `boxes`, `None` for none.
fn union(boxes: &[Aabb]) -> Option<Aabb> {
    boxes.iter().copied().reduce(|a, b| Aabb {
        min: a.min.min(b.min),
        max: a.max.max(b.max),
    })
}

/// The geometric error of showing lots as their boxes: the largest side of any box, the
/// farthest a box's face can be from the model inside it.
fn far_error(masses: &[Aabb]) -> f64 {
    masses
        .iter()
        .map(|b| (b.max - b.min).max_element())
        .fold(1.0, f64::max)
}

/// One box per lot.
fn masses_model(masses: &[Aabb]) -> Model {
    let mut mesh = Mesh::new();
    for b in masses {
        let map = DAffine3::from_scale_rotation_translation(b.max - b.min, DQuat::IDENTITY, b.min);
        mesh.append(&primitives::cuboid(DVec3::ONE).transformed(&map));
    }
    Model {
        parts: vec![Part::new("masses".to_owned(), MASS_COLOR, mesh, Vec::new())],
        ..Model::default()
    }
}

/// A 3D Tiles box (centre, then the three half-axes) around `b` given in the grammar's frame
/// (y up, z south), in the tileset's z-up frame, grown a little so that the f32 positions
/// of the content stay inside.
fn tile_box(b: &Aabb) -> [f64; 12] {
    let pad = |lo: f64, hi: f64| 0.01 + 1e-6 * lo.abs().max(hi.abs());
    let center = (b.min + b.max) / 2.0;
    let half = (b.max - b.min) / 2.0;
    let [hx, hy, hz] = [
        half.x + pad(b.min.x, b.max.x),
        half.y + pad(b.min.y, b.max.y),
        half.z + pad(b.min.z, b.max.z),
    ];
    // `+ 0.0` turns −0 into 0, which JSON would print as -0.0.
    [
        center.x + 0.0,
        -center.z + 0.0,
        center.y + 0.0,
        hx,
        0.0,
        0.0,
        0.0,
        hz,
        0.0,
        0.0,
        0.0,
        hy,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn aabb(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb {
            min: DVec3::from(min),
            max: DVec3::from(max),
        }
    }

    #[test]
    fn boxes_turn_z_up_and_grow_a_centimetre() {
        // x 0..20 east, y 0..12 up, z -30..0 (north of the origin).
        let b = tile_box(&aabb([0.0, 0.0, -30.0], [20.0, 12.0, 0.0]));
        let expected = [
            10.0, 15.0, 6.0, 10.01, 0.0, 0.0, 0.0, 15.01, 0.0, 0.0, 0.0, 6.01,
        ];
        for (got, want) in b.iter().zip(expected) {
            assert!((got - want).abs() < 1e-4, "{b:?}");
        }
    }

    #[test]
    fn masses_are_one_box_per_lot_and_their_error_the_largest_side() {
        let masses = [
            aabb([0.0, 0.0, 0.0], [20.0, 12.0, 30.0]),
            aabb([40.0, 0.0, 0.0], [45.0, 50.0, 5.0]),
        ];
        assert_eq!(far_error(&masses), 50.0);
        assert_eq!(far_error(&[aabb([0.0; 3], [0.5, 0.2, 0.1])]), 1.0);
        let model = masses_model(&masses);
        assert_eq!(model.parts.len(), 1);
        assert_eq!(model.parts[0].mesh.face_count(), 12);
        let bounds = model.bounds().unwrap();
        assert_eq!(
            (bounds.min, bounds.max),
            (masses[0].min, DVec3::new(45.0, 50.0, 30.0))
        );
        assert!(
            (model.parts[0].mesh.signed_volume() - (20.0 * 12.0 * 30.0 + 5.0 * 50.0 * 5.0)).abs()
                < 1e-9
        );
    }
}
