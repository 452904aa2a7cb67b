//! Derives the "hello house" with Shapegram alone, `N` times in a row on one thread (the first
//! argument, 1 by default): what `valgrind --tool=cachegrind` or `callgrind` counts. A run of
//! 6 minus a run of 1 is five derives with the setup cancelled out (see the README).

use std::hint::black_box;

use shapegram_bench_peers::ShapegramHouse;

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .map_or(1, |n| n.parse().expect("a number of runs"));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let house = ShapegramHouse::new(100, 10);
    let mut leaves = 0;
    for _ in 0..runs {
        leaves = pool.install(|| black_box(house.derive()));
    }
    println!("{runs} runs, {leaves} leaves each");
}
