//! Meshes the benchmark scene once at the given number of cells along its longest side and prints
//! the time and counts as one JSON line; `bench/compare.py` runs it next to NumPy pipelines.
//!
//! `cargo run --release -p shapegram-implicit --example bench_scene -- 256`

#[path = "../benches/scene.rs"]
mod scene;

use std::time::Instant;

use shapegram_implicit::{MeshOptions, mesh};

fn main() {
    let cells: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(256);
    let solid = scene::scene();
    let options = MeshOptions::cells_along_longest(&solid, cells);
    // One warm-up run (thread pool start, page faults), then the best of three.
    let mut best = f64::INFINITY;
    let mut result = mesh(&solid, &options).expect("the scene meshes");
    for _ in 0..3 {
        let started = Instant::now();
        result = mesh(&solid, &options).expect("the scene meshes");
        best = best.min(started.elapsed().as_secs_f64());
    }
    let g = result.grid;
    println!(
        "{{\"cells\": {cells}, \"origin\": [{}, {}, {}], \"cell_size\": {}, \"grid\": [{}, {}, {}], \
         \"triangles\": {}, \"vertices\": {}, \"area\": {}, \"seconds\": {best}}}",
        g.origin.x,
        g.origin.y,
        g.origin.z,
        g.cell_size,
        g.cells[0],
        g.cells[1],
        g.cells[2],
        result.mesh.face_count(),
        result.mesh.vertex_count(),
        result.mesh.area(),
    );
}
