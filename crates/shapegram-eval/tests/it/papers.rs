//! The grammars printed in the papers (`examples/`, in the Müller 2006 and SGL notations) derive
//! the models the papers describe.

use crate::common;

use std::sync::Arc;

use common::examples;
use shapegram_eval::{AssetLoader, Derivation, DeriveOptions, Program, Value, derive};
use shapegram_geom::{DVec3, Mesh};
use shapegram_syntax::Dialect;

/// Assets from the examples folder (`roof.obj`).
struct ExampleAssets;

impl AssetLoader for ExampleAssets {
    fn load(&self, path: &str) -> Result<Arc<Mesh>, String> {
        let model = shapegram_export::load(&examples().join(path)).map_err(|e| e.to_string())?;
        Ok(Arc::new(model.merged_mesh()))
    }
}

/// Compiles grammar text, asserting that it is in `dialect` and has no diagnostics at all.
fn compile(name: &str, text: &str, dialect: Dialect) -> Program {
    let (program, read_as) = common::compile_clean(name, text);
    assert_eq!(read_as, dialect, "{name}");
    program
}

fn example_text(name: &str) -> String {
    std::fs::read_to_string(examples().join(name)).expect("the example exists")
}

fn example(name: &str, dialect: Dialect) -> Program {
    compile(name, &example_text(name), dialect)
}

/// Derives on the CLI's default lot (20 × 30 at the origin) with `seed` and attribute values.
fn run(program: &Program, seed: u64, attrs: &[(&str, f64)]) -> Derivation {
    let options = DeriveOptions {
        seed,
        attrs: attrs
            .iter()
            .map(|(n, v)| (n.to_string(), Value::Number(*v)))
            .collect(),
        assets: Some(Arc::new(ExampleAssets)),
        ..DeriveOptions::default()
    };
    derive(program, &[common::lot(20.0, 30.0)], &options).expect("derives")
}

/// How often `rule` was applied.
fn count(d: &Derivation, rule: &str) -> usize {
    d.stats
        .rules
        .iter()
        .find(|(n, _)| n == rule)
        .map_or(0, |r| r.1)
}

fn close(a: DVec3, b: DVec3, eps: f64) -> bool {
    a.abs_diff_eq(b, eps)
}

// --- Seed 000, Figure 12 (Müller et al. 2006 notation) ----------------------------------------

#[test]
fn figure_12_building_layout() {
    let program = example("mueller2006_fig12.mul", Dialect::Muller2006);
    let d = run(&program, 0, &[]);
    // Front block and two side wings, each with its four side facades as 30 cm slabs.
    assert_eq!(
        d.stats.rules,
        [
            ("lot".to_string(), 1),
            ("sidewings".to_string(), 1),
            ("siding".to_string(), 2),
            ("facades".to_string(), 3),
            ("facade".to_string(), 12),
        ]
    );
    assert_eq!(d.stats.leaves, 12);
    assert_eq!(d.stats.shapes, 49);

    let mut dropped = 0;
    for seed in 0..100 {
        let d = run(&program, seed, &[]);
        assert_eq!(count(&d, "lot"), 1);
        assert_eq!(count(&d, "sidewings"), 1);
        assert_eq!(count(&d, "siding"), 2);
        let facades = count(&d, "facades");
        assert!((1..=3).contains(&facades), "seed {seed}");
        dropped += 3 - facades;
        assert_eq!(count(&d, "facade"), 4 * facades);
        assert_eq!(d.stats.leaves, 4 * facades);
        for leaf in &d.leaves {
            assert_eq!(d.name(leaf.name), "facade");
            assert!((leaf.scope.size.z - 0.3).abs() < 1e-12);
            assert!(leaf.scope.size.y <= 12.0 + 1e-9);
        }
        // The front block comes first: full height, 30 % to 50 % of the lot's depth.
        let mut front = Mesh::new();
        for leaf in &d.leaves[..4] {
            assert!((leaf.scope.size.y - 12.0).abs() < 1e-9, "seed {seed}");
            front.append(&leaf.world_mesh().expect("a slab"));
        }
        let bounds = front.bounds().expect("bounds");
        assert!(close(bounds.min, DVec3::new(-0.3, 0.0, -0.3), 1e-9));
        assert!((bounds.max.x - 20.3).abs() < 1e-9);
        let depth = (bounds.size().z - 0.6) / 30.0;
        assert!((0.3..=0.5).contains(&depth), "seed {seed}: {depth}");
    }
    // ε has probability 0.2 for each of the 200 side wings: 40 ± 5.7 expected.
    assert_eq!(dropped, 32);

    let tall = run(&program, 0, &[("building_height", 20.0)]);
    let bounds = tall.to_model().bounds().expect("bounds");
    assert!((bounds.max.y - 20.0).abs() < 1e-9);
}

// --- Seed 001, Figure 7 (Müller et al. 2006 notation) -----------------------------------------

#[test]
fn figure_7_scope_rules_place_five_instances() {
    let program = example("cga_shape_fig7.mul", Dialect::Muller2006);
    let d = run(&program, 0, &[]);
    assert_eq!(d.stats.leaves, 5);
    // Inside the brackets: a cube, then a roof one unit further along z; after them the scope is
    // the lot's again: a column (cylinder), a thinner cylinder and a cone, stacked along z.
    let expected = [
        (DVec3::new(0.0, 0.0, 1.0), DVec3::new(1.0, 2.0, 1.0)),
        (DVec3::new(0.0, 0.0, 2.0), DVec3::new(1.2, 2.2, 1.0)),
        (DVec3::new(1.0, 2.0, 3.0), DVec3::new(1.0, 1.0, 3.0)),
        (DVec3::new(1.0, 2.0, 6.5), DVec3::new(0.7, 0.7, 0.5)),
        (DVec3::new(1.0, 2.0, 7.5), DVec3::new(1.0, 1.0, 0.5)),
    ];
    let mut volume = Vec::new();
    for (leaf, (origin, size)) in d.leaves.iter().zip(expected) {
        assert_eq!(d.name(leaf.name), "A");
        assert!(close(leaf.scope.origin, origin, 1e-12), "{:?}", leaf.scope);
        assert!(close(leaf.scope.size, size, 1e-12), "{:?}", leaf.scope);
        // Each instance fills its scope.
        let mesh = leaf.world_mesh().expect("an instance");
        let bounds = mesh.bounds().expect("bounds");
        assert!(close(bounds.min, origin, 1e-9) && close(bounds.max, origin + size, 1e-9));
        volume.push(mesh.signed_volume());
    }
    assert!((volume[0] - 2.0).abs() < 1e-9);
    // The roof (roof.obj) is a prism: half its box.
    assert!((volume[1] - 1.2 * 2.2 * 0.5).abs() < 1e-9);
    assert_eq!(d.leaves[1].world_mesh().expect("the roof").face_count(), 5);
    // Cylinders and the cone are inscribed in their boxes.
    for (v, size) in volume[2..].iter().zip([3.0, 0.7 * 0.7 * 0.5, 0.5]) {
        assert!(*v > 0.0 && *v < size, "{v}");
    }
}

// --- Seed 001, Figure 10: the SGL tree --------------------------------------------------------

/// Checks the posts of a tree: 0.2 × 2 × 0.2 boxes, the trunk from y = 0 to 2 on the origin, and
/// every other post starting where another one ends.
fn check_posts(d: &Derivation) {
    let base = |leaf: &shapegram_eval::Leaf| {
        leaf.scope.origin + leaf.scope.axes * DVec3::new(0.1, 0.0, 0.1)
    };
    let tops: Vec<DVec3> = d
        .leaves
        .iter()
        .map(|l| base(l) + l.scope.y_axis() * 2.0)
        .collect();
    for (i, leaf) in d.leaves.iter().enumerate() {
        assert_eq!(d.name(leaf.name), "Cube");
        assert!(close(leaf.scope.size, DVec3::new(0.2, 2.0, 0.2), 1e-12));
        let mesh = leaf.world_mesh().expect("a post");
        assert!((mesh.signed_volume() - 0.08).abs() < 1e-12);
        if i == 0 {
            let bounds = mesh.bounds().expect("bounds");
            assert!(close(bounds.min, DVec3::new(-0.1, 0.0, -0.1), 1e-12));
            assert!(close(bounds.max, DVec3::new(0.1, 2.0, 0.1), 1e-12));
        } else {
            assert!(
                tops.iter().any(|t| close(*t, base(leaf), 1e-9)),
                "post {i} does not start on another"
            );
        }
    }
}

#[test]
fn tree_posts() {
    let program = example("sgl_tree.sgl", Dialect::Sgl);
    let d = run(&program, 0, &[]);
    check_posts(&d);
    assert_eq!(d.stats.leaves, 109);
    assert_eq!(count(&d, "tree"), 1);
    assert_eq!(count(&d, "branch"), 201);
    assert_eq!(count(&d, "edge"), 201);
    // The first branch turns 20° about x, from the top of the trunk.
    let second = &d.leaves[1];
    let turned = DVec3::new(0.0, 20f64.to_radians().cos(), 20f64.to_radians().sin());
    assert!(close(second.scope.y_axis(), turned, 1e-12));
    assert!(close(
        second.scope.origin + second.scope.axes * DVec3::new(0.1, 0.0, 0.1),
        DVec3::new(0.0, 2.0, 0.0),
        1e-12
    ));
    // Deeper trees through the header variable.
    let d = run(&program, 0, &[("max_depth", 2.0)]);
    assert_eq!(d.stats.leaves, 1);
    let d = run(&program, 0, &[("max_depth", 10.0)]);
    check_posts(&d);
    assert!(d.stats.leaves > 109 && d.stats.leaves < 1023);
}

#[test]
fn tree_without_pruning_is_a_full_binary_tree() {
    // The printed tree with the pruning weight .1 set to 0.
    let text = example_text("sgl_tree.sgl").replace("(.1){", "(0){");
    let program = compile("tree", &text, Dialect::Sgl);
    for (max_depth, posts) in [(2.0, 1), (3.0, 3), (8.0, 127), (10.0, 511)] {
        let d = run(&program, 7, &[("max_depth", max_depth)]);
        check_posts(&d);
        assert_eq!(d.stats.leaves, posts, "max_depth {max_depth}");
    }
}

// --- Seed 001, Figure 11: the Menger sponge ---------------------------------------------------

/// The leaves as cells of a 3ⁿ grid over [-0.5, 0.5]³, checking that each is one cell.
fn cells(d: &Derivation, n: u32) -> Vec<[usize; 3]> {
    let side = 3usize.pow(n);
    let cell = 1.0 / side as f64;
    d.leaves
        .iter()
        .map(|leaf| {
            assert_eq!(d.name(leaf.name), "Cube");
            assert!(close(leaf.scope.size, DVec3::splat(cell), 1e-12));
            let mesh = leaf.world_mesh().expect("a cube");
            let bounds = mesh.bounds().expect("bounds");
            let index = ((bounds.min + 0.5) / cell).round();
            assert!(close(bounds.min, index * cell - 0.5, 1e-9));
            assert!(close(bounds.size(), DVec3::splat(cell), 1e-9));
            [index.x as usize, index.y as usize, index.z as usize]
        })
        .collect()
}

/// Whether a cell of the level-n sponge is solid: at no ternary digit are two coordinates 1.
fn in_sponge(mut cell: [usize; 3], n: u32) -> bool {
    for _ in 0..n {
        if cell.iter().filter(|&&c| c % 3 == 1).count() >= 2 {
            return false;
        }
        cell = cell.map(|c| c / 3);
    }
    true
}

#[test]
fn menger_sponge_three_iterations() {
    let program = example("sgl_menger.sgl", Dialect::Sgl);
    let d = run(&program, 0, &[]);
    assert_eq!(d.stats.leaves, 8000);
    assert_eq!(count(&d, "box"), 8000);
    let mut cells = cells(&d, 3);
    assert!(cells.iter().all(|&c| in_sponge(c, 3)));
    cells.sort_unstable();
    cells.dedup();
    assert_eq!(cells.len(), 8000, "no cube twice");
    let volume: f64 = d
        .leaves
        .iter()
        .map(|l| l.world_mesh().expect("a cube").signed_volume())
        .sum();
    assert!((volume - (20.0f64 / 27.0).powi(3)).abs() < 1e-9, "{volume}");
    let bounds = d.to_model().bounds().expect("bounds");
    assert!(close(bounds.min, DVec3::splat(-0.5), 1e-12));
    assert!(close(bounds.max, DVec3::splat(0.5), 1e-12));
}

#[test]
fn menger_sponge_other_iterations() {
    let text = example_text("sgl_menger.sgl");
    // As printed, AtDepth(10) places the second iteration.
    for (depth, n) in [(10, 2), (6, 1)] {
        let text = text
            .replace("max_depth = 14", &format!("max_depth = {depth}"))
            .replace("AtDepth(14,", &format!("AtDepth({depth},"));
        let d = run(&compile("menger", &text, Dialect::Sgl), 0, &[]);
        assert_eq!(d.stats.leaves, 20usize.pow(n), "AtDepth({depth})");
        assert!(cells(&d, n).iter().all(|&c| in_sponge(c, n)));
    }
}

// --- Seed 001, section 6.3: the medieval house ------------------------------------------------

const SECTIONS: [&str; 7] = [
    "end_lg_d",
    "end_lg",
    "long_hall_lg",
    "corner",
    "end_sm_d",
    "end_sm",
    "long_hall_sm",
];

fn sections(d: &Derivation) -> Vec<(&'static str, usize)> {
    SECTIONS
        .iter()
        .map(|&s| (s, count(d, s)))
        .filter(|&(_, n)| n > 0)
        .collect()
}

#[test]
fn medieval_house_sections() {
    let program = example("sgl_medieval_house.sgl", Dialect::Sgl);
    let d = run(&program, 0, &[]);
    // Front end with the door, a long hall, the back end: three sections in a row along -z.
    assert_eq!(
        sections(&d),
        [("end_lg_d", 1), ("end_lg", 1), ("long_hall_lg", 1)]
    );
    assert_eq!(d.stats.leaves, 9);
    let bounds = d.to_model().bounds().expect("bounds");
    assert!(
        close(bounds.min, DVec3::new(-0.2, 0.0, -5.0), 1e-9),
        "{bounds:?}"
    );
    assert!(
        close(bounds.max, DVec3::new(2.2, 4.0, 1.1), 1e-9),
        "{bounds:?}"
    );

    let d = run(&program, 2, &[]);
    assert_eq!(
        sections(&d),
        [
            ("end_lg_d", 1),
            ("end_lg", 1),
            ("long_hall_lg", 3),
            ("corner", 2),
            ("long_hall_sm", 1)
        ]
    );
    assert_eq!(d.stats.leaves, 19);

    let mut sizes = [0usize; 9];
    for seed in 0..200 {
        let d = run(&program, seed, &[]);
        let n: usize = sections(&d).iter().map(|s| s.1).sum();
        // One front end with its door, one back end, each section one room under one roof.
        assert_eq!(count(&d, "end_lg_d") + count(&d, "end_sm_d"), 1);
        assert_eq!(count(&d, "end_lg") + count(&d, "end_sm"), 1);
        assert_eq!(count(&d, "door_lg") + count(&d, "door_sm"), 1);
        assert_eq!(count(&d, "room_lg") + count(&d, "room_sm"), n);
        assert_eq!(count(&d, "roof_lg") + count(&d, "roof_sm"), n);
        assert!(count(&d, "corner") <= 3);
        assert_eq!(d.stats.leaves, 2 * n + 3, "seed {seed}");
        sizes[n] += 1;
    }
    // Houses of two to eight sections.
    assert_eq!(sizes[..2], [0, 0]);
    assert!(sizes[2..].iter().all(|&n| n > 0), "{sizes:?}");
}

// --- Seed 004, Algorithm 1 (Müller et al. 2006 notation with KinematicRotation) ---------------

/// The floors of the rotating tower, bottom to top: the chain of sections from the root whose
/// names start with `Floor_` or `Floors_` (the first floor keeps the section of `Floors`, which the repeat
/// split sequentially).
fn floor_chain(
    skeleton: &shapegram_geom::kinematics::Skeleton,
) -> Vec<shapegram_geom::kinematics::SectionId> {
    let mut chain = vec![skeleton.root()];
    while let Some(next) = skeleton.children(*chain.last().unwrap()).find(|c| {
        let name = &skeleton.section(*c).name();
        name.base() == "Floor" || name.base() == "Floors"
    }) {
        chain.push(next);
    }
    chain.split_off(1)
}

#[test]
fn algorithm_1_rotating_tower() {
    let program = example("rotating_tower.mul", Dialect::Muller2006);
    let d = run(&program, 0, &[("CurrentRot", 15.0)]);
    assert_eq!(count(&d, "Floor"), 6);
    let skeleton = &d.skeletons[0].1;
    assert!(skeleton.is_tree());
    let floors = floor_chain(skeleton);
    assert_eq!(
        floors.len(),
        6,
        "six floors of 3 m above the 3.5 m basement, in one chain"
    );
    let posed = skeleton.posed();
    for (k, &floor) in floors.iter().enumerate() {
        let section = skeleton.section(floor);
        // The joints on the tower's axis (the lot's centre), on the planes between floors.
        let at = section.rest().translation;
        assert!(
            close(at, DVec3::new(10.0, 3.5 + 3.0 * k as f64, 15.0), 1e-9),
            "{at}"
        );
        assert_eq!(section.limits().rotation[1].max, 45.0);
        assert_eq!(section.pose().rotation, DVec3::new(0.0, 15.0, 0.0));
        // Turns add up towards the top: floor k is turned by (k + 1) · 15° about y.
        let x = posed[floor.index()].transform_vector(DVec3::X);
        let angle = (-x.z).atan2(x.x).to_degrees();
        assert!(
            (angle - 15.0 * (k + 1) as f64).abs() < 1e-9,
            "floor {k}: {angle}°"
        );
    }
    // Beyond RotLimits is an error at the operation.
    let options = DeriveOptions {
        attrs: vec![("CurrentRot".into(), Value::Number(50.0))],
        ..DeriveOptions::default()
    };
    let error = derive(&program, &[common::lot(20.0, 30.0)], &options).unwrap_err();
    assert_eq!(
        error.message,
        "the rotation about y of 50° is outside the joint's limits (-45° to 45°)"
    );
}
