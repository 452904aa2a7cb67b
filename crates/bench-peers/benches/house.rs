//! Shapegram against symbios-shape on the same "hello house" grammar (see the crate docs and
//! README): many 20 × 30 m lots, 10 floors, facades → floors → 2.5 m tiles → wall | window | wall.
//! Both engines run on one thread (Shapegram inside a one-thread rayon pool); the grammars are
//! parsed and compiled outside the timed loop. Criterion reports terminals per second
//! (`elem/s`); a closing line gives the ratio from interleaved timings of the two engines.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput};
use shapegram_bench_peers::{ShapegramHouse, SymbiosHouse, terminals_per_lot};

const LOTS: usize = 100;
const FLOORS: u32 = 10;
/// Pairs of runs in turns for the ratio, at the least (and six seconds of them).
const PAIRS: usize = 41;

fn main() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let shapegram = ShapegramHouse::new(LOTS, FLOORS);
    let symbios = SymbiosHouse::new(LOTS, FLOORS);

    let sg_count = pool.install(|| shapegram.derive());
    let sy_count = symbios.derive();
    println!(
        "hello house: {LOTS} lots of 20 × 30 m, {FLOORS} floors; \
         shapegram {sg_count} leaves, symbios-shape {sy_count} terminals"
    );
    assert_eq!(
        sg_count, sy_count,
        "the two grammars must derive the same number of terminals"
    );
    assert_eq!(sg_count, LOTS * terminals_per_lot(FLOORS));
    let terminals = sg_count as u64;

    let mut c = Criterion::default().configure_from_args();
    {
        let mut group = c.benchmark_group("hello house");
        group.sample_size(20);
        group.throughput(Throughput::Elements(terminals));
        group.bench_function("shapegram (elem = terminal)", |b| {
            b.iter(|| pool.install(|| black_box(shapegram.derive())))
        });
        group.bench_function("symbios-shape (elem = terminal)", |b| {
            b.iter(|| black_box(symbios.derive()))
        });
        group.finish();
    }
    c.final_summary();

    // The summary: the engines run in turns, each pair close in time, so drift on a busy
    // machine hits both alike; the ratio is taken per pair and its median quoted, with the
    // quartiles to show how far single runs spread.
    let (mut sg, mut sy, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    let started = Instant::now();
    while sg.len() < PAIRS || started.elapsed() < Duration::from_secs(6) {
        let t = Instant::now();
        black_box(pool.install(|| shapegram.derive()));
        let sg_secs = t.elapsed().as_secs_f64();
        let t = Instant::now();
        black_box(symbios.derive());
        let sy_secs = t.elapsed().as_secs_f64();
        sg.push(sg_secs);
        sy.push(sy_secs);
        ratios.push(sy_secs / sg_secs);
    }
    let pairs = ratios.len();
    let (sg, sy) = (quantile(&mut sg, 0.5), quantile(&mut sy, 0.5));
    let rate = |secs: f64| terminals as f64 / secs / 1e6;
    println!(
        "shapegram:     {:7.2} ms per run, {:6.2} M terminals/s (median of {pairs})",
        sg * 1e3,
        rate(sg)
    );
    println!(
        "symbios-shape: {:7.2} ms per run, {:6.2} M terminals/s (median of {pairs})",
        sy * 1e3,
        rate(sy)
    );
    println!(
        "ratio: shapegram derives {:.2}× as many terminals per second as symbios-shape \
         (median of {pairs} pairs run in turns; quartiles {:.2}–{:.2})",
        quantile(&mut ratios, 0.5),
        quantile(&mut ratios, 0.25),
        quantile(&mut ratios, 0.75),
    );
}

/// The value below which a fraction `q` of `v` lies (nearest rank).
fn quantile(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}
