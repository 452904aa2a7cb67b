//! Goal grammars in the Michelangelo notation derive as their native equivalents: the paper's
//! basic chair (seed 003, its listings as printed, wrapped in `using` as the paper advises) and
//! the native chair of `goals.rs` give the same leaves, seed for seed.

use crate::common;

use shapegram_eval::{Derivation, DeriveOptions, Program, derive};
use shapegram_syntax::{Dialect, SourceFile, parse};

const MICHELANGELO: &str = r#"new Axiom("chair", "wooden").Size  
  ↪ (0.4, 0.8, 0.4);

new Rules.Split(Axis.Y,  
  Relative(0.4).Goal("support").  
  ↪ Attribute("Leg.Size", Rnd  
  ↪ (0.03, 0.05)),  
  Relative(0.05).Goal("seat"),  
  Relative(0.55).Goal("lean"))  
.Fulfills("chair");

using (Predicates.IfIs("chair")) {
new Rules.Split(Axis.X,

Absolute(@Double("Leg.Size")).
  ↪ goal("split-legs"),
Relative(1).Void(),
Absolute(@Double("Leg.Size")).
  ↪ goal("split-legs"))
.Fulfills("support");

new Rules.Split(Axis.Z,
  Absolute(@Double("Leg.Size")).
    ↪ Goal("leg"),
  Relative(1).Void(),
  Absolute(@Double("Leg.Size")).
    ↪ Goal("leg"))
.Fulfills("split-legs");

new Rules.Size(Axis.Z, 0.04)
.Fulfills("lean");
}
"#;

/// Compiles the files as one library, the first the main one, asserting that there are no
/// diagnostics.
fn library(files: &[(&str, &str)]) -> Program {
    common::goal_library(files, true).unwrap_or_else(|e| panic!("{e}"))
}

/// Every leaf: name, scope, colour and semantics.
fn leaves(d: &Derivation) -> Vec<String> {
    d.leaves
        .iter()
        .map(|l| {
            format!(
                "{} {:?} {:?} {:?} {:?}",
                d.name(l.name),
                l.scope.origin,
                l.scope.size,
                d.color(l),
                l.semantics()
            )
        })
        .collect()
}

#[test]
fn the_papers_chair_derives_as_the_native_one() {
    let michelangelo = library(&[("chair", MICHELANGELO), ("wood", common::WOOD)]);
    let native = library(&[("chair", common::NATIVE_CHAIR), ("wood", common::WOOD)]);
    assert_eq!(
        parse(&SourceFile::new("chair", MICHELANGELO))
            .grammar
            .dialect,
        Dialect::Michelangelo
    );
    for seed in 0..5 {
        let options = DeriveOptions {
            seed,
            ..DeriveOptions::default()
        };
        let a = derive(&michelangelo, &[], &options).expect("derives");
        let b = derive(&native, &[], &options).expect("derives");
        let names: Vec<&str> = a.leaves.iter().map(|l| a.name(l.name)).collect();
        assert_eq!(names, ["leg", "leg", "leg", "leg", "seat", "lean"]);
        assert_eq!(leaves(&a), leaves(&b), "seed {seed}");
    }
}
