//! The city benchmark: 1,000 lots of 20 × 30 m, extruded 5–20 floors, facades split into floors
//! and window tiles with stochastic window styles; and a box-only facade grammar that measures
//! the engine's raw rate. Run on one thread (`RAYON_NUM_THREADS=1`) to get per-core figures.
//! Criterion prints leaves per second (`elem/s`); the shape counts are printed once up front.

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_eval::{DeriveOptions, InitialShape, Program, derive};
use shapegram_export::{ExportOptions, write_glb};
use shapegram_geom::DVec2;
use shapegram_syntax::{SourceFile, parse};

const CITY: &str = r##"
attr floors = floor(rand(5, 21))
const floorH = 3.2

@StartRule
Lot --> extrude(floors * floorH) Mass
Mass --> comp(f) { side : Facade | top : Roof | bottom : NIL }
Facade --> split(y) { 4 : Ground | { ~floorH : Floor }* }
Floor --> split(x) { 0.5 : Wall | { ~2.8 : Tile }* | 0.5 : Wall }
Tile --> split(x) { ~1 : Wall | 1.4 : Window | ~1 : Wall }
Window --> 40% : color("#5d7fa3") Glass.
           30% : color("#34495e") Glass.
           else : split(y) { 0.9 : Wall | ~1 : color("#8fb3d9") Glass. | 0.4 : Wall }
Ground --> split(x) { { ~5 : Shop }* }
Shop --> split(x) { 0.4 : Wall | ~1 : color("#a0c4e8") Glass. | 0.4 : Wall }
Roof --> color("#777777")
Wall --> color("#d9d4c7")
"##;

/// Facades of boxes only: every leaf is a rectangle made by arithmetic.
const FACADES: &str = r##"
Lot --> extrude(60) comp(f) { side : Facade }
Facade --> split(y) { ~3 : Floor }*
Floor --> split(x) { ~1 : Tile }*
Tile --> split(x) { 0.2 : Wall. | ~1 : Window. | 0.2 : Wall. }
"##;

fn program(text: &str) -> Program {
    let parsed = parse(&SourceFile::new("bench.cga", text));
    Program::compile(&parsed.grammar)
        .0
        .expect("the benchmark grammar compiles")
}

/// `count` lots of 20 × 30 m in rows, 5 m apart.
fn lots(count: usize) -> Vec<InitialShape> {
    (0..count)
        .map(|i| {
            let (x, z) = ((i % 40) as f64 * 25.0, (i / 40) as f64 * 35.0);
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

fn bench(c: &mut Criterion) {
    let options = DeriveOptions::default();
    let city = program(CITY);
    let city_lots = lots(1000);
    let started = Instant::now();
    let once = derive(&city, &city_lots, &options).expect("the city derives");
    let derived = started.elapsed();
    let glb = write_glb(&once.to_model(), &ExportOptions::default());
    let total = started.elapsed();
    println!(
        "city: 1000 lots, {} shapes, {} leaves; derived in {:.1} ms ({:.2} M shapes/s), \
         GLB of {:.1} MB after {:.1} ms",
        once.stats.shapes,
        once.stats.leaves,
        derived.as_secs_f64() * 1e3,
        once.stats.shapes as f64 / derived.as_secs_f64() / 1e6,
        glb.len() as f64 / 1e6,
        total.as_secs_f64() * 1e3,
    );
    let mut group = c.benchmark_group("city");
    group.sample_size(10);
    group.throughput(Throughput::Elements(once.stats.leaves as u64));
    group.bench_function("derive 1000 lots (elem = leaf)", |b| {
        b.iter(|| black_box(derive(&city, &city_lots, &options).expect("derives")))
    });
    group.bench_function("derive and write GLB (elem = leaf)", |b| {
        b.iter(|| {
            let d = derive(&city, &city_lots, &options).expect("derives");
            black_box(write_glb(&d.to_model(), &ExportOptions::default()))
        })
    });
    group.finish();

    let facades = program(FACADES);
    let facade_lots = lots(20);
    let once = derive(&facades, &facade_lots, &options).expect("the facades derive");
    println!(
        "box facades: {} shapes, {} leaves",
        once.stats.shapes, once.stats.leaves
    );
    let mut group = c.benchmark_group("box facades");
    group.sample_size(10);
    group.throughput(Throughput::Elements(once.stats.leaves as u64));
    group.bench_function("derive (elem = leaf)", |b| {
        b.iter(|| black_box(derive(&facades, &facade_lots, &options).expect("derives")))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
