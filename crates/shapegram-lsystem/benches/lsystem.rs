//! L-system throughput: a D0L curve, a bracketed stochastic plant and a parametric tree derived
//! to 10⁷ modules and more (criterion's `elem/s` = modules of the final word per second), and a
//! word of about 10⁶ segments drawn by the turtle, built into a tube model or a line model and
//! written as GLB bytes (`elem/s` = segments per second).
//!
//! Before criterion's rows, one line each gives the tube GLB's cost as the median of five runs:
//! wall time, CPU time and page faults of the whole step from word to bytes and of `write_glb`
//! alone (CPU time and page faults vary less than wall time on a shared machine).
//!
//! Run with `cargo bench -p shapegram-lsystem`; on one core for comparable numbers.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shapegram_export::{ExportOptions, GlbEncoding, write_glb};
use shapegram_lsystem::{
    DeriveOptions, LSystem, Word, drawing_to_lines, drawing_to_model, interpret,
};

/// The quadratic Koch island, 7 steps: 8.4 million F and 15.7 million modules.
const KOCH: &str = "n: 7\nangle: 90\naxiom: F-F-F-F\nF -> F-F+F+FF-F-F+F\n";

/// The paper's stochastic plant (Figure 4), 13 steps: about 7.5 × 10⁷ modules.
const STOCHASTIC: &str = "n: 13\nangle: 30\nseed: 1\naxiom: F\n\
    F (0.33) -> F[+F]F[-F]F\nF (0.33) -> F[+F]F\nF (0.34) -> F[-F]F\n";

/// Honda's tree (ABOP Figure 2.6) with two parameters per module, 21 steps: 1.5 × 10⁷ modules.
const PARAMETRIC: &str = "n: 21\n\
    define: r1 = 0.9\ndefine: r2 = 0.6\ndefine: a0 = 45\ndefine: a2 = 45\n\
    define: d = 137.5\ndefine: wr = 0.707\n\
    axiom: A(1,10)\n\
    A(l,w) -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)\n\
    B(l,w) -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)\n\
    C(l,w) -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)\n";

#[path = "../../../bench/thread_usage.rs"]
mod thread_usage;
use thread_usage::median_usage;

/// A bracketed plant with 4¹⁰ = 1,048,576 segments.
const MILLION_SEGMENTS: &str = "n: 10\nangle: 25.7\nsides: 5\naxiom: F\nF -> F[+F][-F]F\n";

fn bench_derive(c: &mut Criterion, name: &str, text: &str) {
    let system = LSystem::parse(text).unwrap();
    let options = DeriveOptions {
        max_modules: 200_000_000,
        ..DeriveOptions::default()
    };
    let modules = system.derive(&options).unwrap().len();
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(8));
    group.throughput(Throughput::Elements(modules as u64));
    group.bench_function(format!("derive to {modules} modules"), |b| {
        b.iter(|| black_box(system.derive(&options).unwrap()))
    });
    group.finish();
}

fn bench_turtle(c: &mut Criterion) {
    let system = LSystem::parse(MILLION_SEGMENTS).unwrap();
    let word = system.derive(&DeriveOptions::default()).unwrap();
    let segments = interpret(&system, &word).segment_count();
    tube_glb_costs(&system, &word);
    let mut group = c.benchmark_group("turtle");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.throughput(Throughput::Elements(segments as u64));
    group.bench_function(format!("{segments} segments: turtle"), |b| {
        b.iter(|| black_box(interpret(&system, black_box(&word))))
    });
    let drawing = interpret(&system, &word);
    group.bench_function(format!("{segments} segments: tube model"), |b| {
        b.iter(|| black_box(drawing_to_model(black_box(&drawing), &system.settings)))
    });
    group.bench_function(format!("{segments} segments: line model"), |b| {
        b.iter(|| black_box(drawing_to_lines(black_box(&drawing), &system.settings)))
    });
    group.bench_function(format!("{segments} segments: word to GLB bytes"), |b| {
        b.iter(|| {
            let drawing = interpret(&system, black_box(&word));
            let model = drawing_to_model(&drawing, &system.settings);
            black_box(write_glb(&model, &ExportOptions::default()))
        })
    });
    group.bench_function(
        format!("{segments} segments: word to GLB bytes as lines"),
        |b| {
            b.iter(|| {
                let drawing = interpret(&system, black_box(&word));
                let model = drawing_to_lines(&drawing, &system.settings);
                black_box(write_glb(&model, &ExportOptions::default()))
            })
        },
    );
    group.finish();
}

/// Prints the median wall time, CPU time and page faults of the tube GLB, from the word and
/// from the model, in float and quantised encodings.
fn tube_glb_costs(system: &LSystem, word: &Word) {
    let print = |what: &str, (wall, cpu, faults, bytes): (f64, f64, u64, usize)| {
        println!(
            "{what}: {:.1} MB in {:.0} ms wall, {:.0} ms CPU, {} k page faults (median of 5)",
            bytes as f64 / 1e6,
            wall * 1e3,
            cpu * 1e3,
            faults / 1000,
        );
    };
    print(
        "tubes: word to GLB bytes",
        median_usage(5, || {
            let drawing = interpret(system, word);
            let model = drawing_to_model(&drawing, &system.settings);
            write_glb(&model, &ExportOptions::default()).len()
        }),
    );
    let model = drawing_to_model(&interpret(system, word), &system.settings);
    for encoding in [GlbEncoding::Float, GlbEncoding::Quantized] {
        let options = ExportOptions {
            encoding,
            ..ExportOptions::default()
        };
        print(
            &format!("tubes: write_glb ({encoding:?})"),
            median_usage(5, || write_glb(&model, &options).len()),
        );
    }
}

fn bench(c: &mut Criterion) {
    bench_derive(c, "D0L Koch island", KOCH);
    bench_derive(c, "stochastic bracketed plant", STOCHASTIC);
    bench_derive(c, "parametric Honda tree", PARAMETRIC);
    bench_turtle(c);
}

criterion_group!(benches, bench);
criterion_main!(benches);
