//! Goal grammars at library scale: a street of 300 houses (some 40,000 derivation steps) derived
//! with a library of 100 rules and with one of 10,000, where the extra rules fulfil the same
//! goals as the street's own (other panes, windows, bays), so that every step chooses among
//! them. Prints the time per derivation step of both and their ratio (the target: the bigger
//! library costs less than twice as much per step). Run on one thread (`RAYON_NUM_THREADS=1`)
//! for per-core figures.

use std::hint::black_box;
use std::time::Instant;

use shapegram_eval::{DeriveOptions, Program, derive};
use shapegram_syntax::{Dialect, SourceFile, ast::Grammar, parse_as};

const STREET: &str = r#"
axiom street size(1800, 12, 8)
fulfills(street) --> split(x) { { ~6 : +house }* }
"#;

/// The rules that build a house, in the library grammar `houses`.
const HOUSE: &str = r##"
fulfills(house) --> split(y) { { ~3 : +floor }* }
fulfills(floor) --> split(x) { { ~1.5 : +bay }* }
fulfills(bay) --> split(y) { ~0.3 : +sill | ~2 : +window | ~0.7 : +lintel }
fulfills(window) --> split(x) { ~1 : +pane | ~1 : +pane }
fulfills(pane) --> color("#88aacc")
fulfills(sill) --> color("#d8d0c0")
fulfills(lintel) --> color("#b0a890")
"##;

/// `count` further rules for the goals of a house, each a little different.
fn variants(count: usize) -> String {
    let mut text = String::new();
    for i in 0..count {
        let shade = |k: usize| format!("{:02x}", (i * 37 + k * 71) % 256);
        let color = format!("#{}{}{}", shade(0), shade(1), shade(2));
        let ratio = 1.0 + (i % 7) as f64 / 10.0;
        let rule = match i % 5 {
            0 => format!("fulfills(pane) --> color(\"{color}\")\n"),
            1 => format!("fulfills(sill) --> color(\"{color}\") s('1, '0.9, '1)\n"),
            2 => format!("fulfills(lintel) --> color(\"{color}\")\n"),
            3 => format!("fulfills(window) --> split(x) {{ ~1 : +pane | ~{ratio} : +pane }}\n"),
            _ => format!(
                "fulfills(bay) --> split(y) {{ ~0.3 : +sill | ~{ratio} : +window | ~0.7 : +lintel }}\n"
            ),
        };
        text.push_str(&rule);
    }
    text
}

fn parse(name: &str, text: &str) -> Grammar {
    let parsed = parse_as(&SourceFile::new(name, text), Dialect::Goal);
    assert!(!parsed.has_errors(), "{name}: {:?}", parsed.diagnostics);
    parsed.grammar
}

/// The street with a library of `rules` rules in all.
fn program(rules: usize) -> Program {
    let street = parse("street", STREET);
    let houses = parse("houses", &format!("{HOUSE}{}", variants(rules - 8)));
    let (program, diagnostics) =
        Program::compile_library(&[("street", &street), ("houses", &houses)]);
    program.unwrap_or_else(|| panic!("{diagnostics:?}"))
}

/// The fastest of `runs` derivations: seconds per step, and the steps.
fn per_step(program: &Program, runs: usize) -> (f64, usize) {
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for seed in 0..runs as u64 {
        let options = DeriveOptions {
            seed,
            ..DeriveOptions::default()
        };
        let started = Instant::now();
        let d = black_box(derive(program, &[], &options).expect("the street derives"));
        let seconds = started.elapsed().as_secs_f64();
        steps = d.stats.steps;
        best = best.min(seconds / steps as f64);
    }
    (best, steps)
}

fn main() {
    let small = program(100);
    let large = program(10_000);
    let runs = 7;
    // Interleaved, so that a slow moment of the machine hits both.
    let mut small_best = (f64::INFINITY, 0);
    let mut large_best = (f64::INFINITY, 0);
    for _ in 0..3 {
        let s = per_step(&small, runs);
        let l = per_step(&large, runs);
        if s.0 < small_best.0 {
            small_best = s;
        }
        if l.0 < large_best.0 {
            large_best = l;
        }
    }
    println!(
        "library of    100 rules: {:.3} µs per step ({} steps)",
        small_best.0 * 1e6,
        small_best.1
    );
    println!(
        "library of 10,000 rules: {:.3} µs per step ({} steps)",
        large_best.0 * 1e6,
        large_best.1
    );
    println!(
        "ratio: {:.2}× per step (target: under 2×)",
        large_best.0 / small_best.0
    );
}
