//! The city benchmark: 1,000 lots of 20 × 30 m, extruded 5–20 floors, facades split into floors
//! and window tiles with stochastic window styles; and a box-only facade grammar that measures
//! the engine's raw rate. Run on one thread (`RAYON_NUM_THREADS=1`) to get per-core figures.
//! Criterion prints leaves per second (`elem/s`); the shape counts are printed once up front.
//! The occluded city puts the lots wall to wall and keeps windows off walls that a neighbour
//! touches: its summary line gives the occlusion queries per second and the time against the
//! plain city on the same lots. The hinged city opens every window on a hinge: its line gives
//! the time against the same rules without their kinematic operations, the cost of building
//! skeletons. The GLB lines give the city's file size and the cost of writing it in each
//! encoding (float, quantised, meshopt-compressed): wall time, CPU time and page faults of the
//! writer's threads, medians of five runs.

use std::hint::black_box;
use std::time::Instant;

mod city_lots;
#[path = "../../../bench/thread_usage.rs"]
mod thread_usage;

use city_lots::{lots, lots_apart};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_eval::{DeriveOptions, InitialShape, Program, derive};
use shapegram_export::{ExportOptions, GlbEncoding, write_glb};
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

/// The city with occlusion-guarded windows: a tile that touches a neighbour is wall.
fn occluded_city() -> String {
    CITY.replace(
        "Tile --> split(x)",
        "Tile --> case touches() : Wall\n        else : split(x)",
    )
}

/// The window's hinge: on its left edge, opened 30°.
const HINGE: &str = "joint(0, 0, 0) rotationLimits(y, 0, 90) rotateJoint(0, 30, 0) ";

/// The city with every window hinged: a skeleton per lot with a section per split part and
/// component (the cost of kinematics).
fn hinged_city() -> String {
    CITY.replace(
        "Window --> 40%",
        &format!("Window --> {HINGE}Casement\nCasement --> 40%"),
    )
}

/// The same city without kinematics: the hinged city's rules without their kinematic
/// operations, so that both derive the same shapes.
fn unhinged_city() -> String {
    hinged_city().replace(HINGE, "")
}

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

/// Derives `program` on `lots` `runs` times and returns the fastest time.
fn fastest(program: &Program, lots: &[InitialShape], runs: usize) -> f64 {
    (0..runs)
        .map(|_| {
            let started = Instant::now();
            black_box(derive(program, lots, &DeriveOptions::default()).expect("derives"));
            started.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The hinged city against the same rules without kinematics, in turns. Measured before the
/// other benchmarks, in a process that has not yet held a gigabyte of models: after them the
/// allocator hands out memory that is slower to touch, which costs the derivation that makes
/// more of it (the skeletons' sections) more than the other.
fn hinged(options: &DeriveOptions, lots: &[InitialShape]) {
    let hinged = program(&hinged_city());
    let unhinged = program(&unhinged_city());
    let (leaves, sections) = {
        let once = derive(&hinged, lots, options).expect("the hinged city derives");
        let sections: usize = once.skeletons.iter().map(|(_, s)| s.len()).sum();
        (once.stats.leaves, sections)
    };
    // Taken in turns, so that both see the machine alike.
    let (mut with, mut without) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..6 {
        with = with.min(fastest(&hinged, lots, 2));
        without = without.min(fastest(&unhinged, lots, 2));
    }
    println!(
        "hinged city: 1000 lots, {leaves} leaves, {sections} sections; derived in {:.1} ms \
         against {:.1} ms for the same city without kinematics ({:.2}×; the target is at most \
         1.3×)",
        with * 1e3,
        without * 1e3,
        with / without,
    );
}

/// Prints the size and the cost of writing (medians of five) of the city's GLB in each
/// encoding.
fn glb_encodings(model: &shapegram_geom::Model) {
    for encoding in [
        GlbEncoding::Float,
        GlbEncoding::Quantized,
        GlbEncoding::Compressed,
    ] {
        let options = ExportOptions {
            encoding,
            ..ExportOptions::default()
        };
        // The writer plans meshes on rayon's threads: CPU time and faults of all threads.
        let (wall, cpu, faults, bytes) =
            thread_usage::median_usage_by(5, thread_usage::process_usage, || {
                write_glb(model, &options).len()
            });
        println!(
            "city GLB ({encoding:?}): {:.1} MB written in {:.0} ms wall, {:.0} ms CPU, {} k \
             page faults ({} threads)",
            bytes as f64 / 1e6,
            wall * 1e3,
            cpu * 1e3,
            faults / 1000,
            rayon::current_num_threads(),
        );
    }
}

fn bench(c: &mut Criterion) {
    let options = DeriveOptions::default();
    let city = program(CITY);
    let city_lots = lots(1000);
    hinged(&options, &city_lots);
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
    glb_encodings(&once.to_model());
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

    let occluded = program(&occluded_city());
    let touching = lots_apart(1000, 0.0);
    let once = derive(&occluded, &touching, &options).expect("the occluded city derives");
    let queries = once
        .stats
        .rules
        .iter()
        .find(|(name, _)| name == "Tile")
        .map_or(0, |r| r.1);
    let with = fastest(&occluded, &touching, 5);
    let without = fastest(&city, &touching, 5);
    println!(
        "occluded city: 1000 touching lots, {queries} occlusion queries, {} leaves; derived in \
         {:.1} ms against {:.1} ms without occlusion ({:.2}×); {:.2} M queries/s counting all \
         the extra time as query time",
        once.stats.leaves,
        with * 1e3,
        without * 1e3,
        with / without,
        queries as f64 / (with - without).max(1e-9) / 1e6,
    );
    let mut group = c.benchmark_group("occluded city");
    group.sample_size(10);
    group.throughput(Throughput::Elements(queries as u64));
    group.bench_function("derive 1000 touching lots (elem = query)", |b| {
        b.iter(|| black_box(derive(&occluded, &touching, &options).expect("derives")))
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
