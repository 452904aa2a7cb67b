//! Implicit solids in the engine: the aqueduct and outcrop examples derived and their CSG groups
//! meshed, once on one lot and for the outcrop on 100 lots (100 groups meshed in parallel).
//! Criterion prints triangles per second (`elem/s`); the counts are printed once up front.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_eval::{DeriveOptions, InitialShape, Program, derive};
use shapegram_geom::DVec2;
use shapegram_syntax::{SourceFile, parse};

fn example(name: &str) -> Program {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    let text = std::fs::read_to_string(&path).expect("the example exists");
    let parsed = parse(&SourceFile::new(name, &text));
    Program::compile(&parsed.grammar)
        .0
        .expect("the example compiles")
}

/// `count` lots of 20 × 30 m in rows of 10, 10 m apart.
fn lots(count: usize) -> Vec<InitialShape> {
    (0..count)
        .map(|i| {
            let (x, z) = ((i % 10) as f64 * 30.0, (i / 10) as f64 * 40.0);
            InitialShape::from_xz(&[
                DVec2::new(x, z),
                DVec2::new(x + 20.0, z),
                DVec2::new(x + 20.0, z + 30.0),
                DVec2::new(x, z + 30.0),
            ])
            .expect("a rectangle is a lot")
        })
        .collect()
}

fn triangles(program: &Program, lots: &[InitialShape]) -> usize {
    let d = derive(program, lots, &DeriveOptions::default()).expect("derives");
    d.solids.iter().map(|p| p.mesh.face_count()).sum()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("solids");
    group.sample_size(10);
    for (name, count) in [
        ("aqueduct.cga", 1),
        ("outcrop.cga", 1),
        ("outcrop.cga", 100),
    ] {
        let program = example(name);
        let lots = lots(count);
        let made = triangles(&program, &lots);
        println!("{name} on {count} lot(s): {made} triangles of implicit solids");
        group.throughput(Throughput::Elements(made as u64));
        group.bench_function(format!("{name} on {count} lot(s) (elem = triangle)"), |b| {
            b.iter(|| black_box(derive(&program, &lots, &DeriveOptions::default())))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
