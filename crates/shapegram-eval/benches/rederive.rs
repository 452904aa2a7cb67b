//! Deriving again after an edit (`derive_again`): the robot of `examples/robot.cga`, its limbs
//! clad in rings of scales (some 3,000 parts, a section each), has the rule of its hands edited.
//! Prints the time of deriving the edited robot afresh against deriving it again from the
//! previous derivation (the target is at least 10× faster), and what keeping a trace costs.
//! Run on one thread (`RAYON_NUM_THREADS=1`) for per-core figures.

use std::hint::black_box;
use std::time::Instant;

use shapegram_eval::{
    Derivation, DeriveOptions, InitialShape, Program, Rederivation, derive, derive_again,
};
use shapegram_geom::DVec2;
use shapegram_syntax::{SourceFile, parse};

const ROBOT: &str = include_str!("../../../examples/robot.cga");

/// The robot with every limb clad in rings of 16 scales, a part and a section each.
fn clad_robot() -> String {
    let limb =
        "Limb(thick) --> s(thick, '1, thick) center(xz) primitiveCylinder(16) color(bodyColor)";
    assert!(ROBOT.contains(limb), "the robot's Limb rule changed");
    ROBOT.replace(
        limb,
        "Limb(thick) --> s(thick, '1, thick) center(xz) split(y) { ~0.025 : Ring }*
Ring --> primitiveCylinder(16) color(bodyColor) comp(f) { side : Scale. }",
    )
}

/// The edit: the hands' palms wider and in another colour.
fn edited(robot: &str) -> String {
    let palm = "s(0.9 * limbT, '1, 0.6 * limbT) center(xz) primitiveCube() color(jointColor) Palm.";
    assert!(robot.contains(palm), "the robot's Hand rule changed");
    robot.replace(
        palm,
        "s(1.1 * limbT, '1, 0.7 * limbT) center(xz) primitiveCube() color(trimColor) Palm.",
    )
}

fn program(text: &str) -> Program {
    let parsed = parse(&SourceFile::new("robot.cga", text));
    Program::compile(&parsed.grammar)
        .0
        .expect("the robot compiles")
}

/// The fastest of `runs` runs of `f`, in seconds, and its last result.
fn fastest<T>(runs: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..runs {
        let started = Instant::now();
        let result = black_box(f());
        best = best.min(started.elapsed().as_secs_f64());
        last = Some(result);
    }
    (best, last.expect("at least one run"))
}

fn main() {
    let before = program(&clad_robot());
    let after = program(&edited(&clad_robot()));
    let lots = [InitialShape::from_xz(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(6.0, 0.0),
        DVec2::new(6.0, 6.0),
        DVec2::new(0.0, 6.0),
    ])
    .expect("a square is a lot")];
    let plain = DeriveOptions::default();
    let traced = DeriveOptions {
        trace: true,
        ..DeriveOptions::default()
    };
    let previous: Derivation = derive(&before, &lots, &traced).expect("the robot derives");
    // Taken in turns, so that all three see the machine alike.
    let (mut afresh, mut with_trace, mut again) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let (mut full, mut result) = (None, None);
    for _ in 0..10 {
        let (t, d) = fastest(5, || derive(&after, &lots, &plain).expect("derives"));
        afresh = afresh.min(t);
        full = Some(d);
        with_trace =
            with_trace.min(fastest(5, || derive(&after, &lots, &traced).expect("derives")).0);
        let (t, r): (f64, Rederivation) = fastest(5, || {
            derive_again(&previous, &after, &lots, &traced).expect("derives again")
        });
        again = again.min(t);
        result = Some(r);
    }
    let (full, result) = (full.expect("ran"), result.expect("ran"));
    assert_eq!(result.derivation.leaves, full.leaves);
    assert_eq!(result.fallback, None);
    let sections: usize = full.skeletons.iter().map(|(_, s)| s.len()).sum();
    println!(
        "clad robot: {} parts, {sections} sections, {} rule applications",
        full.stats.leaves,
        result.reused + result.applied,
    );
    println!(
        "edit of the hands' rule: derived afresh in {:.2} ms, again in {:.3} ms ({:.1}× faster; \
         the target is at least 10×), {} rule applications reused, {} applied",
        afresh * 1e3,
        again * 1e3,
        afresh / again,
        result.reused,
        result.applied,
    );
    println!(
        "keeping a trace: {:.2} ms against {:.2} ms without ({:.2}×)",
        with_trace * 1e3,
        afresh * 1e3,
        with_trace / afresh,
    );
}
