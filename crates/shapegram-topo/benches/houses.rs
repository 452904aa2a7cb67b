//! Generating the demo house grammar (thesis 4.3) to triangle meshes, as a game would at run
//! time: 1,000 houses with seeds 0..1000, each derived for 8 generations and meshed. The
//! `houses` group counts one element per house, the `sub-shapes` group one per shape the
//! interpreter made (terminal and rewritten), so criterion prints houses/s and sub-shapes/s.
//! Run on one core: `cargo bench -p shapegram-topo` (the interpreter is single-threaded).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_topo::{Grammar, GrammarMesh, GrammarState, compile, demos};

const HOUSES: u64 = 1000;

/// Derives and meshes every house; returns the triangles and the shapes made.
fn build_houses(grammar: &Grammar) -> (usize, u64) {
    let mut triangles = 0;
    let mut shapes = 0;
    let mut state = GrammarState::new(grammar, "House")
        .expect("the demo grammar has House")
        .with_generations(8);
    for seed in 0..HOUSES {
        state = state.with_seed(seed);
        state.start();
        for _ in 0..state.generations {
            shapes += state.non_terminals().len() as u64;
            state.next_generation().expect("houses stay small");
        }
        shapes += state.terminals().len() as u64;
        triangles += GrammarMesh::new(&state).triangle_count();
    }
    (triangles, shapes)
}

fn bench(c: &mut Criterion) {
    let grammar = compile(&demos::house().expect("the demo builds")).expect("it compiles");
    let (_, shapes) = build_houses(&grammar);

    let mut group = c.benchmark_group("houses");
    group.throughput(Throughput::Elements(HOUSES));
    group.sample_size(20);
    group.bench_function("derive and mesh 1000 houses", |b| {
        b.iter(|| black_box(build_houses(black_box(&grammar))))
    });
    group.finish();

    let mut group = c.benchmark_group("sub-shapes");
    group.throughput(Throughput::Elements(shapes));
    group.sample_size(20);
    group.bench_function("derive and mesh 1000 houses", |b| {
        b.iter(|| black_box(build_houses(black_box(&grammar))))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
