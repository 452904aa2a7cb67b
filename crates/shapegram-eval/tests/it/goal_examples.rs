//! The goal-grammar examples of `examples/`: the office building of Ilčík and Wimmer's Figures
//! 4–7 (`examples/office/`), derived with its library at the paper's scale.

use crate::common;

use std::path::{Path, PathBuf};

use shapegram_eval::{Derivation, DeriveOptions, Leaf, Program};
use shapegram_geom::DVec3;
use shapegram_syntax::{Dialect, SourceFile, parse_as};

/// The `.goal` files of a folder, the main grammar first and the rest sorted by path (as
/// `shapegram derive main.goal --library folder` reads them).
fn goal_files(folder: &Path, main: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "goal"))
        .collect();
    files.sort();
    let at = files
        .iter()
        .position(|p| p.file_name().is_some_and(|n| n == main))
        .expect("the main grammar is in the folder");
    let main = files.remove(at);
    files.insert(0, main);
    files
}

/// Compiles the files as one library, asserting that there is not a single diagnostic.
fn compile_library(files: &[PathBuf]) -> Program {
    let sources: Vec<SourceFile> = files
        .iter()
        .map(|path| {
            let text = std::fs::read_to_string(path).unwrap();
            SourceFile::new(path.file_name().unwrap().to_string_lossy(), text)
        })
        .collect();
    let parsed: Vec<_> = sources.iter().map(|s| parse_as(s, Dialect::Goal)).collect();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    let grammars: Vec<(&str, &shapegram_syntax::ast::Grammar)> = names
        .iter()
        .zip(&parsed)
        .map(|(n, p)| (n.as_str(), &p.grammar))
        .collect();
    let (program, diagnostics) = Program::compile_library(&grammars);
    let rendered: Vec<String> = parsed
        .iter()
        .zip(&sources)
        .flat_map(|(p, s)| p.diagnostics.iter().map(|d| s.render(d)))
        .chain(diagnostics.iter().map(|(k, d)| sources[*k].render(d)))
        .collect();
    assert!(rendered.is_empty(), "{}", rendered.join("\n"));
    program.expect("no errors")
}

fn has_tag(leaf: &Leaf, tag: &str) -> bool {
    leaf.semantics()
        .is_some_and(|s| s.tags.iter().any(|t| &**t == tag))
}

fn count_tagged(d: &Derivation, tag: &str) -> usize {
    d.leaves.iter().filter(|l| has_tag(l, tag)).count()
}

/// Leaves of one part of a kind: the desktops of desks, the seats of office chairs.
fn count_parts(d: &Derivation, name: &str, tag: &str) -> usize {
    d.leaves
        .iter()
        .filter(|l| d.name(l.name) == name && has_tag(l, tag))
        .count()
}

/// The box around the leaves with a tag.
fn bounds_of(d: &Derivation, tag: &str) -> (DVec3, DVec3) {
    let mut min = DVec3::splat(f64::INFINITY);
    let mut max = DVec3::splat(f64::NEG_INFINITY);
    for leaf in d.leaves.iter().filter(|l| has_tag(l, tag)) {
        if let Some(b) = leaf.world_mesh().and_then(|m| m.bounds()) {
            min = min.min(b.min);
            max = max.max(b.max);
        }
    }
    (min, max)
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() < 1e-9
}

#[test]
fn the_office_building_is_derived_at_the_scale_of_the_paper() {
    let files = goal_files(&common::examples().join("office"), "office.goal");
    // "47,284 derivation steps controlled by 329 rules which were combined from 27 grammars"
    assert!(files.len() >= 27, "{} grammars", files.len());
    assert_eq!(files.len(), 42);
    let program = compile_library(&files);
    let options = DeriveOptions {
        seed: 0,
        ..DeriveOptions::default()
    };
    let d = common::derive_on_threads(&program, &[], &options, 1);
    let stats = &d.stats;
    assert!(stats.rules.len() >= 329, "{} rules", stats.rules.len());
    assert_eq!(stats.rules.len(), 535);
    assert!(stats.steps >= 47_284, "{} steps", stats.steps);
    assert_eq!(stats.grammars.len(), files.len());
    let idle: Vec<&str> = stats
        .grammars
        .iter()
        .filter(|(_, steps)| *steps == 0)
        .map(|(name, _)| name.as_str())
        .collect();
    assert!(idle.is_empty(), "grammars that took no step: {idle:?}");

    // About 240 desks and as many office chairs (one more: the receptionist's), each of many
    // parts.
    assert_eq!(count_parts(&d, "desktop", "desk"), 225);
    assert_eq!(count_parts(&d, "seat_pan", "office_chair"), 226);
    assert_eq!(count_tagged(&d, "desk"), 4464);
    assert_eq!(count_tagged(&d, "office_chair"), 6511);
    // (Two repeats in one split take their shares in turn, as CityEngine counts them.)
    assert_eq!(d.leaves.len(), 28_366);

    // Three storeys of 36 × 24 m on the site, fins and the canopy standing out of the facades,
    // the stair's roof exit on top.
    let (min, max) = bounds_of(&d, "building");
    assert!(
        close(min, DVec3::new(4.8, 0.0, 3.8)) && close(max, DVec3::new(41.2, 14.2, 29.8)),
        "{min} {max}"
    );
    let (min, max) = bounds_of(&d, "floor_slab");
    assert!(
        close(min, DVec3::new(5.0, 0.0, 4.0)) && close(max, DVec3::new(41.0, 7.5, 28.0)),
        "{min} {max}"
    );
    // Every chair stands on its five casters, every desk on its feet, legs or panels, on one of
    // the three floors (slabs of 0.3 m every 3.6 m).
    let on_floor = |y: f64| [0.3, 3.9, 7.5].iter().any(|f| (y - f).abs() < 1e-9);
    let mut standing = 0;
    for leaf in &d.leaves {
        let chair_foot = has_tag(leaf, "office_chair") && d.name(leaf.name) == "castor_wheel";
        let desk_foot =
            has_tag(leaf, "desk") && ["leg", "foot", "panel_end"].contains(&d.name(leaf.name));
        if chair_foot || desk_foot {
            let b = leaf.world_mesh().and_then(|m| m.bounds()).unwrap();
            assert!(on_floor(b.min.y), "{} at {}", d.name(leaf.name), b.min);
            standing += 1;
        }
    }
    assert_eq!(standing, 226 * 5 + 492);

    // The same seed gives the same building on any number of threads.
    let four = common::derive_on_threads(&program, &[], &options, 4);
    assert_eq!(d.leaves, four.leaves);
}
