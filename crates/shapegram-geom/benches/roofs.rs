//! Roof and offset throughput on footprints of growing size: a 40-gon (convex), a comb of 12 teeth
//! (rectilinear, with many simultaneous skeleton events) and an L. One element = one roof or one
//! inside/border split.

// The kernel tests' shapes (the L footprint among them).
#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_geom::{
    DVec2, DVec3,
    offset::inset_border,
    primitives::{cylinder, footprint},
    roof::{roof_gable, roof_hip},
};

/// The bottom face of a 40-sided cylinder, turned to face up: a convex 40-gon of radius 5.
fn forty_gon() -> Vec<DVec3> {
    let mut bottom: Vec<DVec3> = cylinder(DVec3::new(10.0, 1.0, 10.0), 40)
        .face_points(0)
        .collect();
    bottom.reverse();
    bottom
}

/// A comb: a 2-deep spine along x with `teeth` teeth 1 wide, 3 long and 1 apart.
fn comb(teeth: u32) -> Vec<DVec3> {
    let mut outline = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(f64::from(2 * teeth - 1), 0.0),
    ];
    for t in (0..teeth).rev() {
        let x = f64::from(2 * t);
        outline.extend([
            DVec2::new(x + 1.0, 2.0),
            DVec2::new(x + 1.0, 5.0),
            DVec2::new(x, 5.0),
            DVec2::new(x, 2.0),
        ]);
    }
    footprint(&outline)
        .expect("a comb is a valid footprint")
        .face_points(0)
        .collect()
}

fn bench(c: &mut Criterion) {
    let shapes = [
        ("40-gon", forty_gon()),
        ("comb", comb(12)),
        ("L", common::l_footprint()),
    ];
    let mut group = c.benchmark_group("roofs");
    group.throughput(Throughput::Elements(1));
    for (name, points) in &shapes {
        group.bench_function(format!("hip {name}"), |b| {
            b.iter(|| black_box(roof_hip(black_box(points), 30.0, 0.0)))
        });
        group.bench_function(format!("gable {name}"), |b| {
            b.iter(|| black_box(roof_gable(black_box(points), 30.0, 0.0)))
        });
        group.bench_function(format!("inside/border {name}"), |b| {
            b.iter(|| black_box(inset_border(black_box(points), -0.3)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
