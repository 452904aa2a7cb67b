//! The chairs of `examples/chairs/` (seed 003, Figures 2 and 3): the basic chair as printed,
//! the metallic override as printed, and about a hundred chairs from four incomplete designs.

use crate::common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use shapegram_eval::{Derivation, DeriveOptions, Leaf, Program, derive};
use shapegram_geom::{Color, DVec3};

fn chairs() -> PathBuf {
    common::examples().join("chairs")
}

/// The `.goal` files of a folder, or the file itself, sorted.
fn goal_files(path: &Path) -> Vec<PathBuf> {
    if path.is_file() {
        return vec![path.to_owned()];
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(path)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "goal"))
        .collect();
    files.sort();
    files
}

/// `main` with the library `paths`, compiled without any diagnostic.
fn library(main: &str, paths: &[&str]) -> Program {
    let mut files = vec![chairs().join(main)];
    for path in paths {
        files.extend(goal_files(&chairs().join(path)));
    }
    let texts: Vec<(String, String)> = files
        .iter()
        .map(|f| {
            let stem = f.file_stem().unwrap().to_string_lossy().into_owned();
            (stem, std::fs::read_to_string(f).unwrap())
        })
        .collect();
    let pairs: Vec<(&str, &str)> = texts
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    common::goal_library(&pairs, true).unwrap_or_else(|e| panic!("{e}"))
}

fn run(program: &Program, seed: u64) -> Derivation {
    let options = DeriveOptions {
        seed,
        ..DeriveOptions::default()
    };
    derive(program, &[], &options).unwrap()
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() < 1e-9
}

const BROWN: &str = "#8b5a2b";
const STEEL: &str = "#9aa4ad";

#[test]
fn the_basic_chair_as_printed_stands_on_four_legs_and_is_brown() {
    let program = library("chair.goal", &["materials"]);
    let d = run(&program, 0);
    let names: Vec<&str> = d.leaves.iter().map(|l| d.name(l.name)).collect();
    assert_eq!(names, ["leg", "leg", "leg", "leg", "seat", "lean"]);
    let brown = Color::from_hex(BROWN).unwrap();
    assert!(d.leaves.iter().all(|l| d.color(l) == brown));
    let leg = d.leaves[0].scope.size;
    assert!((0.03..0.05).contains(&leg.x) && leg.x == leg.z, "{leg:?}");
    assert!((leg.y - 0.32).abs() < 1e-12);
    assert!(close(d.leaves[5].scope.size, DVec3::new(0.4, 0.44, 0.04)));
    assert_eq!(d.stats.steps, 11);
}

#[test]
fn the_metallic_override_as_printed_puts_the_chair_on_a_steel_pedestal() {
    let program = library("metallic_chair.goal", &["chair.goal", "materials"]);
    let d = run(&program, 0);
    let names: Vec<&str> = d.leaves.iter().map(|l| d.name(l.name)).collect();
    assert_eq!(names, ["stand", "seat", "lean"]);
    let stand = &d.leaves[0];
    assert!(
        close(stand.scope.size, DVec3::new(0.1, 0.32, 0.1)),
        "{:?}",
        stand.scope
    );
    assert!(
        close(stand.scope.origin, DVec3::new(0.15, 0.0, 0.15)),
        "{:?}",
        stand.scope
    );
    assert_eq!(d.color(stand), Color::from_hex(STEEL).unwrap());
    let brown = Color::from_hex(BROWN).unwrap();
    assert_eq!(
        (d.color(&d.leaves[1]), d.color(&d.leaves[2])),
        (brown, brown)
    );
    let tags = &stand.semantics().unwrap().tags;
    assert!(tags.iter().any(|t| &**t == "metallic"), "{tags:?}");
}

/// Each place of the showroom (a 1.3 × 1.1 m cell) and the leaves of the chair in it, relative
/// to the cell's corner.
fn chairs_by_place(d: &Derivation) -> Vec<Vec<&Leaf>> {
    let mut places: Vec<Vec<&Leaf>> = vec![Vec::new(); 100];
    for leaf in &d.leaves {
        let centre = leaf.scope.to_world(leaf.scope.size * 0.5);
        let (i, j) = ((centre.x / 1.3) as usize, (centre.z / 1.1) as usize);
        places[i * 10 + j].push(leaf);
    }
    places
}

/// A chair's geometry, to the centimetre: each leaf's name, shape, size and place in its cell.
fn geometry(d: &Derivation, place: usize, leaves: &[&Leaf]) -> Vec<String> {
    let corner = DVec3::new((place / 10) as f64 * 1.3, 0.0, (place % 10) as f64 * 1.1);
    let cm = |v: DVec3| (v * 100.0).round().to_array().map(|x| x as i64);
    let mut parts: Vec<String> = leaves
        .iter()
        .map(|l| {
            let kind = match &l.geometry {
                shapegram_eval::Geometry::Box => "box".to_owned(),
                shapegram_eval::Geometry::Mesh(m, _) => format!("mesh{}", m.face_count()),
                other => format!("{other:?}"),
            };
            format!(
                "{} {kind} {:?} {:?}",
                d.name(l.name),
                cm(l.scope.size),
                cm(l.scope.origin - corner)
            )
        })
        .collect();
    parts.sort();
    parts
}

#[test]
fn four_incomplete_designs_give_about_a_hundred_different_chairs() {
    let program = library("showroom.goal", &["designs", "materials"]);
    let d = run(&program, 0);
    let places = chairs_by_place(&d);
    assert!(places.iter().all(|p| !p.is_empty()));
    let designs: BTreeSet<Vec<String>> = places
        .iter()
        .enumerate()
        .map(|(i, leaves)| geometry(&d, i, leaves))
        .collect();
    // Counted by geometry alone: colours and materials aside.
    assert!(designs.len() >= 90, "{} different chairs", designs.len());
    // Told apart by their parts alone, sizes aside: the combinations of the designs.
    let kinds: BTreeSet<Vec<String>> = places
        .iter()
        .map(|leaves| {
            let mut parts: Vec<String> = leaves
                .iter()
                .map(|l| {
                    format!(
                        "{} {}",
                        d.name(l.name),
                        matches!(l.geometry, shapegram_eval::Geometry::Box)
                    )
                })
                .collect();
            parts.sort();
            parts
        })
        .collect();
    assert_eq!((designs.len(), kinds.len()), (95, 41));
    // Each design contributes, and the materials too.
    let used: Vec<(&str, usize)> = d
        .stats
        .grammars
        .iter()
        .map(|(n, s)| (n.as_str(), *s))
        .collect();
    assert!(used.iter().all(|(_, s)| *s > 0), "{used:?}");
    assert_eq!(used.len(), 8);
    // No chair stands in the air or leaves its place.
    for (i, leaves) in places.iter().enumerate() {
        let low = leaves
            .iter()
            .map(|l| l.scope.origin.y)
            .fold(f64::INFINITY, f64::min);
        assert!(low.abs() < 1e-9, "chair {i} starts at {low}");
        let corner = DVec3::new((i / 10) as f64 * 1.3, 0.0, (i % 10) as f64 * 1.1);
        for l in leaves {
            let far = l.scope.to_world(l.scope.size) - corner;
            assert!(
                far.x <= 1.3 + 1e-9 && far.z <= 1.1 + 1e-9,
                "chair {i}: {:?}",
                l.scope
            );
        }
    }
}

#[test]
fn the_showroom_is_the_same_on_any_number_of_threads() {
    let program = library("showroom.goal", &["designs", "materials"]);
    let options = DeriveOptions {
        seed: 3,
        ..DeriveOptions::default()
    };
    let one = common::derive_on_threads(&program, &[], &options, 1);
    let four = common::derive_on_threads(&program, &[], &options, 4);
    assert_eq!(one.leaves, four.leaves);
}
