//! Marching cubes throughput on a CSG of twelve primitives with differences and a morph (see
//! `scene.rs`), at 128 and 256 cells along the longest side. Criterion reports grid voxels per
//! second (`elem/s`); a summary line per size adds triangles per second.

mod scene;

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_implicit::{MeshOptions, mesh};

fn bench(c: &mut Criterion) {
    let solid = scene::scene();
    let mut group = c.benchmark_group("mesh");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(5));
    for cells in [128, 256] {
        let options = MeshOptions::cells_along_longest(&solid, cells);
        let first = mesh(&solid, &options).unwrap();
        let voxels = first.grid.cell_count();
        let triangles = first.mesh.face_count();
        group.throughput(Throughput::Elements(voxels));
        group.bench_function(format!("{cells}^3"), |b| {
            b.iter(|| black_box(mesh(black_box(&solid), &options).unwrap()))
        });
        let runs = 5;
        let started = Instant::now();
        for _ in 0..runs {
            black_box(mesh(&solid, &options).unwrap());
        }
        let seconds = started.elapsed().as_secs_f64() / f64::from(runs);
        let [x, y, z] = first.grid.cells;
        println!(
            "mesh {cells}^3: grid {x} x {y} x {z}, {triangles} triangles, {:.1} ms, {:.1} M voxels/s, \
             {:.2} M triangles/s, {:.1} % of samples evaluated",
            seconds * 1e3,
            voxels as f64 / seconds / 1e6,
            triangles as f64 / seconds / 1e6,
            100.0 * first.evaluated_samples as f64 / voxels as f64,
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
