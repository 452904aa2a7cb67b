//! A tileset written by several machines: which tiles a shard writes, the part of tileset.json
//! each shard leaves beside its tiles, and the merge that joins the parts (`docs/tiles.md`).
//!
//! A shard owns whole parent tiles, so that each far tile (the masses of up to 4 × 4 leaf
//! cells) is written by exactly one shard. The parts record every number of tileset.json as
//! the bits of its f64, so the merged tileset is byte for byte the one a single run writes.

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde_json::{Value as Json, json};
use shapegram_geom::{Aabb, DVec3};

use super::Cell;
use super::tileset::{FarTile, TileEncoding, write_tileset};
use crate::tiles::TilesetSummary;
use crate::{Error, FlatNormals, GlbEncoding};

/// Shard `index` of `count` (counted from 0): `--shard 1/3` is the second of three.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Shard {
    /// Which shard, from 0 to `count - 1`.
    pub index: u32,
    /// How many shards share the tileset.
    pub count: u32,
}

impl Shard {
    /// The shard of `k/n`: `k` from 0 to `n - 1`, `n` at least 1.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let usage =
            || format!("'{text}' is no shard: expected k/n with k from 0 to n - 1, like 0/4");
        let (k, n) = text.split_once('/').ok_or_else(usage)?;
        let (Ok(index), Ok(count)) = (k.trim().parse::<u32>(), n.trim().parse::<u32>()) else {
            return Err(usage());
        };
        if count == 0 {
            return Err(format!("'{text}': a tileset needs at least 1 shard"));
        }
        if index >= count {
            return Err(format!(
                "'{text}': shards of {count} are numbered 0 to {}",
                count - 1
            ));
        }
        Ok(Shard { index, count })
    }

    /// The shard's share of `parents` parent tiles listed in order: a contiguous range, the
    /// first `parents * k / n` going to the shards before it. Neighbouring tiles stay
    /// together, so few lots are derived twice as context; shards differ by at most one tile.
    pub fn parents(self, parents: usize) -> Range<usize> {
        let at = |k: u32| (parents as u128 * u128::from(k) / u128::from(self.count)) as usize;
        at(self.index)..at(self.index + 1)
    }

    /// The name of the shard's part of tileset.json: `tileset.shard-K-of-N.json`.
    pub fn file_name(self) -> String {
        format!("tileset.shard-{}-of-{}.json", self.index, self.count)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// The part of tileset.json one shard wrote.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ShardPart {
    pub shard: Shard,
    pub tile_size: f64,
    pub transform: [f64; 16],
    pub encoding: TileEncoding,
    pub far: Vec<FarTile>,
}

/// The names of the encodings in a part (floats have none: a part without `encoding` is of
/// floats, as parts were before tiles had a choice).
const ENCODINGS: [(GlbEncoding, &str); 2] = [
    (GlbEncoding::Quantized, "quantized"),
    (GlbEncoding::Compressed, "meshopt"),
];

impl ShardPart {
    /// Writes the part into `dir`, beside the shard's tiles.
    pub fn write(&self, dir: &Path) -> Result<(), Error> {
        let far: Vec<Json> = self
            .far
            .iter()
            .map(|tile| {
                json!({
                    "cell": [tile.cell.east, tile.cell.north],
                    "bounds": aabb_bits(&tile.bounds),
                    "error": bits(tile.error),
                    "lots": tile.lots,
                    "near": tile.near.iter().map(|(cell, bounds)| json!({
                        "cell": [cell.east, cell.north],
                        "bounds": aabb_bits(bounds),
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        let mut part = json!({
            "shard": self.shard.index,
            "shards": self.shard.count,
            "tileSize": bits(self.tile_size),
            "transform": self.transform.map(bits),
        });
        // Only what differs from floats is written, so that the parts of float tiles stay
        // what they were.
        if let Some((_, name)) = ENCODINGS
            .iter()
            .find(|(encoding, _)| *encoding == self.encoding.encoding)
        {
            part["encoding"] = json!(name);
        }
        if self.encoding.flat_normals == FlatNormals::Written {
            part["normals"] = json!("written");
        }
        part["far"] = json!(far);
        let path = dir.join(self.shard.file_name());
        let mut text = serde_json::to_string_pretty(&part).expect("JSON values serialise");
        text.push('\n');
        std::fs::write(&path, text).map_err(|source| Error::Write { path, source })
    }

    /// Reads a part written by [`ShardPart::write`].
    fn read(path: &Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let broken = |what: &str| Error::Shards {
            path: path.to_path_buf(),
            message: format!("not a shard of a tileset written by shapegram ({what})"),
        };
        let json: Json = serde_json::from_str(&text).map_err(|e| broken(&e.to_string()))?;
        let number = |v: &Json, what: &str| v.as_u64().ok_or_else(|| broken(what));
        let float = |v: &Json, what: &str| {
            v.as_str()
                .and_then(|s| u64::from_str_radix(s, 16).ok())
                .map(f64::from_bits)
                .ok_or_else(|| broken(what))
        };
        let cell = |v: &Json| -> Result<Cell, Error> {
            match v.as_array().map(Vec::as_slice) {
                Some([east, north]) => Ok(Cell {
                    east: east.as_i64().ok_or_else(|| broken("cell"))?,
                    north: north.as_i64().ok_or_else(|| broken("cell"))?,
                }),
                _ => Err(broken("cell")),
            }
        };
        let aabb = |v: &Json| -> Result<Aabb, Error> {
            let values = v.as_array().ok_or_else(|| broken("bounds"))?;
            let values: Vec<f64> = values
                .iter()
                .map(|v| float(v, "bounds"))
                .collect::<Result<_, _>>()?;
            match values.as_slice() {
                [a, b, c, d, e, f] => Ok(Aabb {
                    min: DVec3::new(*a, *b, *c),
                    max: DVec3::new(*d, *e, *f),
                }),
                _ => Err(broken("bounds")),
            }
        };
        let list = |v: &Json, what: &str| v.as_array().cloned().ok_or_else(|| broken(what));
        let index = u32::try_from(number(&json["shard"], "shard")?).map_err(|_| broken("shard"))?;
        let count =
            u32::try_from(number(&json["shards"], "shards")?).map_err(|_| broken("shards"))?;
        if index >= count {
            return Err(broken("shard"));
        }
        let transform: Vec<f64> = list(&json["transform"], "transform")?
            .iter()
            .map(|v| float(v, "transform"))
            .collect::<Result<_, _>>()?;
        let transform: [f64; 16] = transform.try_into().map_err(|_| broken("transform"))?;
        let mut far = Vec::new();
        for tile in list(&json["far"], "far")? {
            let mut near = Vec::new();
            for leaf in list(&tile["near"], "near")? {
                near.push((cell(&leaf["cell"])?, aabb(&leaf["bounds"])?));
            }
            far.push(FarTile {
                cell: cell(&tile["cell"])?,
                bounds: aabb(&tile["bounds"])?,
                error: float(&tile["error"], "error")?,
                lots: number(&tile["lots"], "lots")? as usize,
                near,
            });
        }
        let encoding = match json.get("encoding") {
            None => GlbEncoding::Float,
            Some(name) => ENCODINGS
                .iter()
                .find(|(_, known)| name == known)
                .map(|(encoding, _)| *encoding)
                .ok_or_else(|| broken("encoding"))?,
        };
        let flat_normals = match json.get("normals") {
            None => FlatNormals::Computed,
            Some(name) if name == "written" => FlatNormals::Written,
            Some(_) => return Err(broken("normals")),
        };
        Ok(ShardPart {
            shard: Shard { index, count },
            tile_size: float(&json["tileSize"], "tileSize")?,
            transform,
            encoding: TileEncoding {
                encoding,
                flat_normals,
            },
            far,
        })
    }
}

/// An f64 as the hexadecimal digits of its bits: read back exactly.
fn bits(v: f64) -> String {
    format!("{:016x}", v.to_bits())
}

fn aabb_bits(b: &Aabb) -> [String; 6] {
    [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z].map(bits)
}

/// Joins the shards written into the folders `inputs` (each holding the tiles of one or more
/// shards and their `tileset.shard-K-of-N.json`) into one tileset in `out`: the tiles are
/// copied there (unless they are there already) and tileset.json written over all of them.
/// Every shard of the run must be found exactly once, all of one grid and frame.
pub fn merge(inputs: &[PathBuf], out: &Path) -> Result<TilesetSummary, Error> {
    let mut parts: BTreeMap<Shard, (PathBuf, ShardPart)> = BTreeMap::new();
    for dir in inputs {
        let entries = std::fs::read_dir(dir).map_err(|source| Error::Read {
            path: dir.clone(),
            source,
        })?;
        let mut found = false;
        let mut names: Vec<PathBuf> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("tileset.shard-") && n.ends_with(".json"))
            })
            .collect();
        names.sort();
        for path in names {
            found = true;
            let part = ShardPart::read(&path)?;
            if let Some((other, _)) = parts.get(&part.shard) {
                return Err(Error::Shards {
                    path,
                    message: format!(
                        "shard {} is also in {}: give each shard once",
                        part.shard,
                        other.display()
                    ),
                });
            }
            parts.insert(part.shard, (dir.clone(), part));
        }
        if !found {
            return Err(Error::Shards {
                path: dir.clone(),
                message: "no shard of a tileset here (tileset.shard-K-of-N.json, written by \
                          derive --tiles … --shard K/N)"
                    .to_owned(),
            });
        }
    }
    let Some((first_dir, first)) = parts.values().next() else {
        return Err(Error::Shards {
            path: out.to_path_buf(),
            message: "no shards to merge".to_owned(),
        });
    };
    let count = first.shard.count;
    for (dir, part) in parts.values() {
        let agrees = part.shard.count == count
            && part.tile_size.to_bits() == first.tile_size.to_bits()
            && part.transform.map(f64::to_bits) == first.transform.map(f64::to_bits)
            && part.encoding == first.encoding;
        if !agrees {
            return Err(Error::Shards {
                path: dir.join(part.shard.file_name()),
                message: format!(
                    "shard {} is not of the run of {} (another shard count, tile size, frame \
                     or encoding: --quantize, --meshopt, --normals)",
                    part.shard,
                    first_dir.join(first.shard.file_name()).display()
                ),
            });
        }
    }
    let missing: Vec<String> = (0..count)
        .map(|index| Shard { index, count })
        .filter(|s| !parts.contains_key(s))
        .map(|s| s.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(Error::Shards {
            path: out.to_path_buf(),
            message: format!("missing shard {} of {count}", missing.join(", ")),
        });
    }
    let (tile_size, transform) = (first.tile_size, first.transform);
    for sub in ["near", "far"] {
        let path = out.join(sub);
        std::fs::create_dir_all(&path).map_err(|source| Error::Write { path, source })?;
    }
    let mut far: Vec<FarTile> = Vec::new();
    for (dir, part) in parts.into_values() {
        let same = same_folder(&dir, out);
        for tile in &part.far {
            let uris = std::iter::once(FarTile::uri_of(tile.cell)).chain(
                tile.near
                    .iter()
                    .map(|(cell, _)| FarTile::near_uri_of(*cell)),
            );
            for uri in uris.filter(|_| !same) {
                let from = dir.join(&uri);
                std::fs::copy(&from, out.join(&uri))
                    .map_err(|source| Error::Read { path: from, source })?;
            }
        }
        far.extend(part.far);
    }
    far.sort_by_key(|tile| tile.cell);
    if let Some(pair) = far.windows(2).find(|pair| pair[0].cell == pair[1].cell) {
        return Err(Error::Shards {
            path: out.to_path_buf(),
            message: format!(
                "two shards wrote the far tile {}: they are not of one run",
                FarTile::uri_of(pair[0].cell)
            ),
        });
    }
    write_tileset(out, tile_size, transform, &far)
}

/// Whether two paths name one folder.
fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_k_of_n_and_refuse_the_rest() {
        assert_eq!(Shard::parse("1/3"), Ok(Shard { index: 1, count: 3 }));
        assert_eq!(Shard::parse("0/1"), Ok(Shard { index: 0, count: 1 }));
        assert_eq!(
            Shard::parse("3/3").unwrap_err(),
            "'3/3': shards of 3 are numbered 0 to 2"
        );
        assert_eq!(
            Shard::parse("0/0").unwrap_err(),
            "'0/0': a tileset needs at least 1 shard"
        );
        for bad in ["1", "a/3", "-1/3", "1/3/4", ""] {
            assert!(
                Shard::parse(bad).unwrap_err().contains("is no shard"),
                "{bad}"
            );
        }
    }

    #[test]
    fn shards_take_contiguous_ranges_that_cover_every_parent_once() {
        for parents in [0, 1, 2, 5, 16] {
            for count in 1..=6 {
                let ranges: Vec<Range<usize>> = (0..count)
                    .map(|index| Shard { index, count }.parents(parents))
                    .collect();
                assert_eq!(ranges[0].start, 0);
                assert_eq!(ranges.last().unwrap().end, parents);
                for pair in ranges.windows(2) {
                    assert_eq!(pair[0].end, pair[1].start);
                }
                let sizes: Vec<usize> = ranges.iter().map(|r| r.len()).collect();
                let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(max - min <= 1, "{parents} of {count}: {sizes:?}");
            }
        }
        // Two parents among three shards: the first shard has none.
        assert_eq!(Shard { index: 0, count: 3 }.parents(2), 0..0);
    }

    #[test]
    fn parts_read_back_bit_for_bit() {
        let dir = std::env::temp_dir().join(format!("shapegram-shard-part-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let tricky = 0.1 + 0.2;
        let b = Aabb {
            min: DVec3::new(-tricky, 1e-300, -0.0),
            max: DVec3::new(1.0 / 3.0, 5e6 + tricky, 7.0),
        };
        let part = ShardPart {
            shard: Shard { index: 2, count: 5 },
            tile_size: 200.0,
            transform: std::array::from_fn(|i| i as f64 / 7.0),
            encoding: TileEncoding::default(),
            far: vec![FarTile {
                cell: Cell { east: -3, north: 9 },
                bounds: b,
                error: 30.000000000000004,
                lots: 17,
                near: vec![(
                    Cell {
                        east: -9,
                        north: 36,
                    },
                    b,
                )],
            }],
        };
        let path = dir.join("tileset.shard-2-of-5.json");
        part.write(&dir).unwrap();
        let back = ShardPart::read(&path).unwrap();
        assert_eq!(back, part);
        assert_eq!(back.far[0].bounds.min.z.to_bits(), (-0.0f64).to_bits());
        // Floats name no encoding; the others read back as written.
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            !text.contains("encoding") && !text.contains("normals"),
            "{text}"
        );
        let encoded = ShardPart {
            encoding: TileEncoding {
                encoding: GlbEncoding::Compressed,
                flat_normals: FlatNormals::Written,
            },
            ..part
        };
        encoded.write(&dir).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("\"encoding\": \"meshopt\""), "{text}");
        assert!(text.contains("\"normals\": \"written\""), "{text}");
        assert_eq!(ShardPart::read(&path).unwrap(), encoded);
        std::fs::write(dir.join("bad.json"), "{\"shard\": 1}").unwrap();
        let error = ShardPart::read(&dir.join("bad.json"))
            .unwrap_err()
            .to_string();
        assert!(error.contains("not a shard of a tileset"), "{error}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
