//! Plane-splitting throughput: boxes and 40-gon prisms cut by oblique planes, one cut at a time
//! and as one pass of nine parallel planes. Throughput is reported in cuts per second
//! (criterion's `elem/s`, one element = one plane cut).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_geom::{
    DVec3, Mesh, Plane,
    primitives::{cuboid, cylinder},
    split::{split, split_slabs},
};

/// Deterministic oblique planes crossing the box `[0, 4]³`: a fixed rotation of directions and
/// offsets through the middle half, so every plane really cuts.
fn planes(count: usize) -> Vec<Plane> {
    (0..count)
        .map(|i| {
            let a = i as f64 * 2.399_963; // golden angle: well spread directions
            let normal = DVec3::new(a.cos(), 0.7 + 0.3 * (3.0 * a).sin(), a.sin()).normalize();
            let through = DVec3::splat(2.0) + DVec3::splat(((i % 7) as f64 - 3.0) * 0.15);
            Plane::from_point_normal(through, normal)
        })
        .collect()
}

fn bench_single_cuts(c: &mut Criterion, name: &str, mesh: &Mesh) {
    let planes = planes(64);
    let mut group = c.benchmark_group(name);
    group.throughput(Throughput::Elements(planes.len() as u64));
    group.bench_function("one plane", |b| {
        b.iter(|| {
            for plane in &planes {
                black_box(split(black_box(mesh), plane));
            }
        })
    });
    let offsets: Vec<f64> = (1..10).map(|k| f64::from(k) * 0.4).collect();
    group.throughput(Throughput::Elements(offsets.len() as u64));
    group.bench_function("nine parallel planes in one pass", |b| {
        b.iter(|| {
            black_box(split_slabs(
                black_box(mesh),
                DVec3::new(0.3, 1.0, 0.2),
                &offsets,
            ))
        })
    });
    group.finish();
}

fn bench(c: &mut Criterion) {
    bench_single_cuts(c, "split box", &cuboid(DVec3::splat(4.0)));
    bench_single_cuts(c, "split 40-gon prism", &cylinder(DVec3::splat(4.0), 40));
}

criterion_group!(benches, bench);
criterion_main!(benches);
