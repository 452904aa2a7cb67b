//! Writing a tileset: near tiles as they come, far tiles and tileset.json at the end.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde_json::{Value as Json, json};
use shapegram_geom::{
    Aabb, Color, DAffine3, DQuat, DVec3, Mesh, Metadata, Model, Part, primitives,
};

use super::shards::{Shard, ShardPart};
use super::{Cell, PARENT_SPAN, TileGrid};
use crate::{Error, ExportOptions, Features, FlatNormals, GlbEncoding};

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

/// How the tiles' GLBs store their vertices: the choices of [`ExportOptions`] that `derive
/// --quantize`, `--meshopt` and `--normals` make for `-o x.glb`, which apply to every near and
/// far tile alike. The default writes floats, as tiles were written before they had a choice.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TileEncoding {
    /// Floats, KHR_mesh_quantization, or that compressed with EXT_meshopt_compression.
    pub encoding: GlbEncoding,
    /// Whether flat-shaded primitives carry normals.
    pub flat_normals: FlatNormals,
}

impl TileEncoding {
    /// The encoding the flags `--quantize`, `--meshopt` and `--normals` ask for: `--meshopt`
    /// quantises too, so it wins over `--quantize`.
    pub fn from_flags(quantize: bool, meshopt: bool, normals: bool) -> Self {
        Self {
            encoding: match (meshopt, quantize) {
                (true, _) => GlbEncoding::Compressed,
                (false, true) => GlbEncoding::Quantized,
                (false, false) => GlbEncoding::Float,
            },
            flat_normals: if normals {
                FlatNormals::Written
            } else {
                FlatNormals::Computed
            },
        }
    }

    /// The options a tile's GLB is written with.
    fn options(self) -> ExportOptions {
        ExportOptions {
            encoding: self.encoding,
            flat_normals: self.flat_normals,
            ..ExportOptions::default()
        }
    }

    /// `b`, the bounds of a tile's content, grown by as much as quantised positions may lie
    /// outside it: each mesh's grid spans that mesh, within `b`, in ±32,767 steps, so a step
    /// is at most `b`'s largest side / 65,534, and a position moves by half a step when it is
    /// rounded to the grid; a whole step leaves room for the f32 arithmetic of the grid's
    /// centre and scale. Floats stay where they are: `b` unchanged.
    fn content_bounds(self, b: Aabb) -> Aabb {
        if self.encoding == GlbEncoding::Float {
            return b;
        }
        let step = (b.max - b.min).max_element() / 65_534.0;
        Aabb {
            min: b.min - step,
            max: b.max + step,
        }
    }
}

/// A lot of a leaf tile: its index among the city's lots, its model in the grammar's frame
/// and, for a tileset with metadata, its metadata (a GLB's lot node's: rule, path,
/// attributes, leaf count, report summaries), which makes it a feature of the tiles.
#[derive(Clone, Debug, Default)]
pub struct TileLot {
    /// The lot's index among the city's lots: features are in this order.
    pub index: usize,
    /// Its leaves' model.
    pub model: Model,
    /// Its metadata, for its row in the tiles' property tables.
    pub metadata: Option<Arc<Metadata>>,
}

/// A leaf tile written: its content's bounds and its lots' masses, in the grammar's frame,
/// with their lots' indices and metadata when they have some.
struct Near {
    bounds: Aabb,
    masses: Vec<Aabb>,
    features: Vec<(usize, Arc<Metadata>)>,
}

/// Writes a tileset into a folder: [`TilesetWriter::add`] each leaf tile's model, then
/// [`TilesetWriter::finish`]. The output depends only on what is added, not on the order.
pub struct TilesetWriter {
    dir: PathBuf,
    grid: TileGrid,
    transform: [f64; 16],
    encoding: TileEncoding,
    /// The leaf tiles whose far tile is not written yet.
    near: BTreeMap<Cell, Near>,
    /// The far tiles written already (see [`TilesetWriter::write_far_before`]).
    far: Vec<FarTile>,
}

impl TilesetWriter {
    /// A writer into `dir` (made when missing, with its `near/` and `far/` folders), for
    /// leaf cells of `grid`, whose root tile has the `transform` from the grammar's frame
    /// turned z-up (x east, y north, z up) to the tileset's coordinates (ECEF when
    /// georeferenced): column-major, as in tileset.json. Every tile's GLB is written with
    /// `encoding`.
    pub fn new(
        dir: &Path,
        grid: TileGrid,
        transform: [f64; 16],
        encoding: TileEncoding,
    ) -> Result<Self, Error> {
        for sub in [NEAR, FAR] {
            let path = dir.join(sub);
            std::fs::create_dir_all(&path).map_err(|source| Error::Write { path, source })?;
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            grid,
            transform,
            encoding,
            near: BTreeMap::new(),
            far: Vec::new(),
        })
    }

    /// Writes the leaf tile of `cell`: `lots` are the models of its lots, in the grammar's
    /// frame, each of which also becomes one box (its bounds) in the far tile above. Lots
    /// without geometry are left out; a cell with none gets no tile.
    pub fn add(&mut self, cell: Cell, lots: Vec<Model>) -> Result<(), Error> {
        let lots = lots.into_iter().enumerate().map(|(index, model)| TileLot {
            index,
            model,
            metadata: None,
        });
        self.add_lots(cell, lots.collect())
    }

    /// [`TilesetWriter::add`] of lots that may carry metadata: when some do, every lot with
    /// geometry becomes a feature of this tile and of the far tile above (rows in order of
    /// `lots`, which must be that of their indices; a lot without metadata gets an empty row).
    pub fn add_lots(&mut self, cell: Cell, lots: Vec<TileLot>) -> Result<(), Error> {
        let described = lots.iter().any(|lot| lot.metadata.is_some());
        let mut masses = Vec::new();
        let mut model = Model::default();
        let mut features = Vec::new();
        let mut ids = Features::default();
        for lot in lots {
            let Some(bounds) = lot.model.bounds() else {
                continue;
            };
            masses.push(bounds);
            if described {
                let id = features.len() as u32;
                ids.parts.extend(lot.model.parts.iter().map(|_| id));
                ids.lines.extend(lot.model.lines.iter().map(|_| id));
                features.push((lot.index, lot.metadata.unwrap_or_default()));
            }
            model.parts.extend(lot.model.parts);
            model.lines.extend(lot.model.lines);
        }
        let Some(bounds) = union(&masses) else {
            return Ok(());
        };
        let path = self.dir.join(NEAR).join(format!("{}.glb", cell.name()));
        ids.rows = features.iter().map(|(_, m)| &**m).collect();
        save(&model, described.then_some(&ids), &path, self.encoding)?;
        drop(ids);
        self.near.insert(
            cell,
            Near {
                bounds: self.encoding.content_bounds(bounds),
                masses,
                features,
            },
        );
        Ok(())
    }

    /// Writes the far tiles all of whose leaf cells come before `next` in cell order (east,
    /// then north), and lets go of their lots' masses and metadata: for a caller that adds
    /// cells in order, so that a city's metadata is never held whole. The files are the same
    /// as when every far tile is written by [`TilesetWriter::finish`].
    pub fn write_far_before(&mut self, next: Cell) -> Result<(), Error> {
        let last = PARENT_SPAN - 1;
        let complete = |parent: Cell| {
            let last_child = Cell {
                east: parent.east * PARENT_SPAN + last,
                north: parent.north * PARENT_SPAN + last,
            };
            last_child < next
        };
        let done: BTreeMap<Cell, Near> = self
            .near
            .extract_if(.., |cell, _| complete(cell.parent()))
            .collect();
        let far = self.write_far(done)?;
        self.far.extend(far);
        Ok(())
    }

    /// Writes the far tiles and tileset.json.
    pub fn finish(mut self) -> Result<TilesetSummary, Error> {
        let far = self.write_rest()?;
        write_tileset(&self.dir, self.grid.size, self.transform, &far)
    }

    /// Writes the far tiles and, instead of tileset.json, the part of it that `shard` holds
    /// (`tileset.shard-K-of-N.json`), for [`super::merge`] to join with the other shards'.
    pub fn finish_shard(mut self, shard: Shard) -> Result<TilesetSummary, Error> {
        let far = self.write_rest()?;
        let part = ShardPart {
            shard,
            tile_size: self.grid.size,
            transform: self.transform,
            encoding: self.encoding,
            far,
        };
        part.write(&self.dir)?;
        Ok(summary(&part.far))
    }

    /// Writes the far tiles not written yet; returns every far tile, in order of their cells.
    fn write_rest(&mut self) -> Result<Vec<FarTile>, Error> {
        let rest = std::mem::take(&mut self.near);
        let mut far = std::mem::take(&mut self.far);
        far.extend(self.write_far(rest)?);
        far.sort_by_key(|tile| tile.cell);
        Ok(far)
    }

    /// Writes a far tile (the masses) for each parent cell of the leaf tiles `near`.
    fn write_far(&self, near: BTreeMap<Cell, Near>) -> Result<Vec<FarTile>, Error> {
        let mut parents: BTreeMap<Cell, Vec<(Cell, &Near)>> = BTreeMap::new();
        for (&cell, near) in &near {
            parents.entry(cell.parent()).or_default().push((cell, near));
        }
        let mut far = Vec::with_capacity(parents.len());
        for (parent, children) in parents {
            let masses: Vec<Aabb> = children
                .iter()
                .flat_map(|(_, near)| near.masses.iter().copied())
                .collect();
            let path = self.dir.join(FarTile::uri_of(parent));
            if children.iter().any(|(_, near)| !near.features.is_empty()) {
                write_far_features(&children, &path, self.encoding)?;
            } else {
                save(&masses_model(&masses), None, &path, self.encoding)?;
            }
            let bounds = union(&masses).expect("a parent tile has children with masses");
            far.push(FarTile {
                cell: parent,
                bounds: self.encoding.content_bounds(bounds),
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

/// Writes a tile's GLB in `encoding`, with `features` when given.
fn save(
    model: &Model,
    features: Option<&Features<'_>>,
    path: &Path,
    encoding: TileEncoding,
) -> Result<(), Error> {
    let options = encoding.options();
    match features {
        None => crate::save(model, path, &options),
        Some(features) => crate::stream(path, |out| {
            crate::write_glb_with_features_to(model, &options, features, out)
        })
        .map_err(|source| Error::Write {
            path: path.to_path_buf(),
            source,
        }),
    }
}

/// Writes the far tile of `children` with features: a box per lot, each a feature, in order
/// of the lots' indices.
fn write_far_features(
    children: &[(Cell, &Near)],
    path: &Path,
    encoding: TileEncoding,
) -> Result<(), Error> {
    let mut lots: Vec<(usize, Aabb, &Metadata)> = children
        .iter()
        .flat_map(|(_, near)| {
            let features = near.features.iter();
            near.masses
                .iter()
                .zip(features)
                .map(|(mass, (index, metadata))| (*index, *mass, &**metadata))
        })
        .collect();
    lots.sort_by_key(|(index, _, _)| *index);
    let model = Model {
        parts: lots
            .iter()
            .map(|(_, mass, _)| masses_model(std::slice::from_ref(mass)).parts.remove(0))
            .collect(),
        ..Model::default()
    };
    let features = Features {
        rows: lots.iter().map(|(_, _, metadata)| *metadata).collect(),
        parts: (0..lots.len() as u32).collect(),
        lines: Vec::new(),
    };
    save(&model, Some(&features), path, encoding)
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
