//! The GLB writer plans meshes, and the Z-order and the pieces of a mesh's vertex pool, on
//! rayon's threads: the file must be the same bytes on one thread as on four.

use crate::common;

use std::sync::Arc;

use common::*;
use shapegram_export::{ExportOptions, FlatNormals, GlbEncoding, write_glb};
use shapegram_geom::{Color, DVec3, Mesh, Metadata, Model, Part};

/// The colour of tile (column, row): four, no two neighbours alike, so that no tiles merge.
fn color(column: usize, row: usize) -> Color {
    [RED, BLUE, GREEN, GREY][(column + 2 * row) % 4]
}

/// A facade of `side` × `side` unit tiles, a part each, every tenth row's first tile with
/// metadata of its own (a mesh of its own), and the sample model's solids beside it.
fn facade(side: usize) -> Model {
    let mut parts: Vec<Part> = (0..side * side)
        .map(|i| {
            let (column, row) = (i % side, i / side);
            let (x, y) = (column as f64, row as f64);
            Part {
                name: "Tile".to_owned(),
                color: color(column, row),
                mesh: Mesh::from_polygon(&[
                    DVec3::new(x, y, 0.0),
                    DVec3::new(x + 1.0, y, 0.0),
                    DVec3::new(x + 1.0, y + 1.0, 0.0),
                    DVec3::new(x, y + 1.0, 0.0),
                ]),
                metadata: (column == 0 && row % 10 == 0).then(|| {
                    Arc::new(Metadata {
                        tags: vec![format!("row {row}")],
                        ..Metadata::default()
                    })
                }),
                ..Part::default()
            }
        })
        .collect();
    parts.extend(sample_model().parts);
    Model {
        parts,
        ..Model::default()
    }
}

/// The GLB written on a pool of `threads` threads.
fn written(model: &Model, options: &ExportOptions, threads: usize) -> Vec<u8> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| write_glb(model, options))
}

#[test]
fn one_thread_and_four_write_the_same_bytes() {
    // 260 × 260 tiles: more corners than one piece of the vertex pool holds (65,534).
    let model = facade(260);
    let encodings = [
        GlbEncoding::Float,
        GlbEncoding::Quantized,
        GlbEncoding::Compressed,
    ];
    for encoding in encodings {
        for flat_normals in [FlatNormals::Computed, FlatNormals::Written] {
            let options = ExportOptions {
                encoding,
                flat_normals,
                ..ExportOptions::default()
            };
            let one = written(&model, &options, 1);
            let (json, _) = split_glb(&one);
            if flat_normals == FlatNormals::Computed {
                // The tiles' mesh: a primitive per colour in each of several pool pieces.
                let meshes = json["meshes"].as_array().unwrap();
                let tiles = meshes.iter().find(|m| m["name"] == "model").unwrap();
                let primitives = tiles["primitives"].as_array().unwrap().len();
                assert!(primitives > 4, "{encoding:?}: {primitives}");
            }
            // 26 parts with metadata, each a mesh of its own.
            let meshes = json["meshes"].as_array().unwrap().len();
            assert!(meshes > 26, "{meshes}");
            let four = written(&model, &options, 4);
            assert!(
                one == four,
                "{encoding:?}, {flat_normals:?}: the bytes differ"
            );
        }
    }
}
