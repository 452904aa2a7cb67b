//! Context-sensitive rules: occlusion queries and snap lines, derived in two phases.

use crate::common;

use common::{compile, compile_errors, lot, run, try_run};
use shapegram_eval::{Derivation, DeriveOptions, InitialShape, derive};
use shapegram_geom::DVec2;

/// How many leaves have this name.
fn count(d: &Derivation, name: &str) -> usize {
    d.leaves.iter().filter(|l| d.name(l.name) == name).count()
}

/// The x sizes of the leaves with this name, in leaf order.
fn widths(d: &Derivation, name: &str) -> Vec<f64> {
    d.leaves
        .iter()
        .filter(|l| d.name(l.name) == name)
        .map(|l| (l.scope.size.x * 1e9).round() / 1e9)
        .collect()
}

/// Two blocks side by side on a 20 × 10 lot: A (x from 0 to 10, 6 high) and B (x from 10 to
/// 20, 4 high). A's face at x = 10 meets B's over the lower 4 m: A's touches B without being
/// inside it; B's lies wholly on A's (inside, on the surface, but not overlapping).
const TWO_BLOCKS: &str = "
Lot --> split(x) { 10 : A | 10 : B }
A --> extrude(6) Mass
B --> extrude(4) Mass
Mass --> comp(f) { side : Face | top : Top. | bottom : NIL }
";

#[test]
fn faces_of_touching_blocks_are_classified_by_hand() {
    let grammar = format!(
        "{TWO_BLOCKS}
Face --> case inside() : Hidden.
         case overlaps() : Crossing.
         case touches() : Touching.
         else : Free."
    );
    let d = run(&grammar, lot(20.0, 10.0));
    assert_eq!(count(&d, "Hidden"), 1, "B's face against A");
    assert_eq!(count(&d, "Touching"), 1, "A's face against B");
    assert_eq!(count(&d, "Crossing"), 0);
    assert_eq!(count(&d, "Free"), 6);
    assert_eq!(count(&d, "Top"), 2);
    let hidden = d
        .leaves
        .iter()
        .find(|l| d.name(l.name) == "Hidden")
        .unwrap();
    assert!(
        (hidden.scope.size.y - 4.0).abs() < 1e-9,
        "the low block's face"
    );
    // Phase 1 leaves come first, then the shapes that waited, in derivation order.
    assert_eq!(d.name(d.leaves[0].name), "Top");
    assert_eq!(d.stats.leaves, 10);
}

#[test]
fn reports_of_shapes_that_waited_for_phase_two_name_their_nodes() {
    let grammar = format!(
        "{TWO_BLOCKS}
Face --> case inside() : report(\"hidden\", geometry.area) Hidden.
         else : report(\"seen\", 1) Seen."
    );
    let options = DeriveOptions {
        keep_tree: true,
        ..DeriveOptions::default()
    };
    let d = derive(&compile(&grammar), &[lot(20.0, 10.0)], &options).unwrap();
    assert_eq!(d.reports.len(), 8);
    assert_eq!(d.report_nodes.len(), 8);
    for (&node, (key, _)) in d.report_nodes.iter().zip(&d.reports) {
        assert_eq!(&*d.tree[node as usize].name, "Face", "{key}");
    }
    // Each leaf hangs below the face whose report says what became of it.
    let hidden = d
        .leaves
        .iter()
        .find(|l| d.name(l.name) == "Hidden")
        .unwrap();
    let at = d.reports.iter().position(|(k, _)| k == "hidden").unwrap();
    assert_eq!(
        d.tree[hidden.node().unwrap() as usize].parent,
        Some(d.report_nodes[at])
    );
}

#[test]
fn queries_never_see_their_own_ancestors() {
    // Every face lies on its own mass; only the other block can occlude it.
    let grammar = format!(
        "{TWO_BLOCKS}
Face --> case touches() : Touching. else : Free."
    );
    let d = run(&grammar, lot(20.0, 10.0));
    assert_eq!(count(&d, "Touching"), 2);
    assert_eq!(count(&d, "Free"), 6);
}

#[test]
fn muller_occ_returns_none_part_and_full() {
    let grammar = "
lot ~> Subdiv(\"X\", 10, 10){ a | b }
a ~> S(1r, 6, 1r) mass
b ~> S(1r, 4, 1r) mass
mass ~> Comp(\"sidefaces\"){ facade }
facade : Shape.occ(\"noparent\") == \"none\" ~> free
facade : Shape.occ(\"noparent\") == \"part\" ~> part
facade : Shape.occ(\"noparent\") == \"full\" ~> full
";
    let d = run(grammar, lot(20.0, 10.0));
    assert_eq!(
        [count(&d, "free"), count(&d, "part"), count(&d, "full")],
        [6, 1, 1]
    );
}

#[test]
fn a_box_inside_another_and_a_box_crossing_it() {
    let d = run(
        "Lot --> [ extrude(10) Big. ]
                 [ t(2, 0, 2) s(2, 0, 2) extrude(2) Probe ]
                 [ t(19, 0, 5) s(2, 0, 2) extrude(2) Probe ]
                 [ t(25, 0, 5) s(2, 0, 2) extrude(2) Probe ]
         Probe --> case inside() : In. case overlaps() : Across. case touches() : On. else : Out.",
        lot(20.0, 10.0),
    );
    assert_eq!(
        [
            count(&d, "In"),
            count(&d, "Across"),
            count(&d, "On"),
            count(&d, "Out")
        ],
        [1, 1, 0, 1]
    );
}

/// Two 10 × 10 lots side by side: x from 0 to 10 and from 10 to 20.
fn neighbours() -> Vec<InitialShape> {
    let square = |x: f64| {
        InitialShape::from_xz(&[
            DVec2::new(x, 0.0),
            DVec2::new(x + 10.0, 0.0),
            DVec2::new(x + 10.0, 10.0),
            DVec2::new(x, 10.0),
        ])
        .unwrap()
    };
    vec![square(0.0), square(10.0)]
}

#[test]
fn targets_choose_the_lots_that_occlude() {
    for (target, touching) in [("all", 2), ("inter", 2), ("intra", 0)] {
        let program = compile(&format!(
            "Lot --> extrude(5) comp(f) {{ side : Face | top : Top. | bottom : NIL }}
             Face --> case touches({target}) : Touching. else : Free."
        ));
        let d = derive(&program, &neighbours(), &DeriveOptions::default()).unwrap();
        assert_eq!(count(&d, "Touching"), touching, "target {target}");
        assert_eq!(count(&d, "Free"), 8 - touching, "target {target}");
    }
}

#[test]
fn labels_and_rule_names_filter_occluders() {
    let grammar = "
Lot --> split(x) { 10 : A | 10 : B }
A --> extrude(6) label(\"tower\") Tower
B --> extrude(4) comp(f) { side : Face | top : Top. | bottom : NIL }
Face --> case touches(all, \"tower\") : ByTower.
         case touches(all, \"Tower\") : ByRule.
         else : Free.
";
    let d = run(grammar, lot(20.0, 10.0));
    assert_eq!(count(&d, "ByTower"), 1);
    let by_rule = grammar.replace("\"tower\") : ByTower", "\"nothing\") : ByTower");
    let d = run(&by_rule, lot(20.0, 10.0));
    assert_eq!([count(&d, "ByTower"), count(&d, "ByRule")], [0, 1]);
}

/// A 20-wide, 10-high box with a tower over x from 7.2 to 12.2 that leaves snap planes across
/// x; the front facade is split along x with snapping.
fn snapping(split: &str) -> Derivation {
    run(
        &format!(
            "Lot --> [ t(7.2, 0, 0) s(5, 0, 5) extrude(15) snap(x) Tower. ]
                     extrude(10) comp(f) {{ front : Front | top : Top. | side : Side. | bottom : NIL }}
             Front --> {split}"
        ),
        lot(20.0, 10.0),
    )
}

#[test]
fn snapping_repeat_spreads_the_repetitions_evenly_between_snap_lines() {
    // Seven tiles of 20/7; the boundary nearest 7.2 (at 60/7) moves onto it and the tiles
    // spread evenly on either side; then the one nearest 12.2 (at 13.6) moves onto that.
    let d = snapping("split(x, snap) { { ~3 : Tile. }* }");
    assert_eq!(widths(&d, "Tile"), [2.4, 2.4, 2.4, 2.5, 2.5, 3.9, 3.9]);
    let without = snapping("split(x) { { ~3 : Tile. }* }");
    let plain = 20.0 / 7.0;
    assert!(
        widths(&without, "Tile")
            .iter()
            .all(|w| (w - plain).abs() < 1e-9)
    );
}

#[test]
fn snapping_split_moves_only_the_nearest_boundary() {
    let d = snapping("split(x, snap) { 5 : A. | 5 : B. | ~1 : C. }");
    assert_eq!(
        [widths(&d, "A"), widths(&d, "B"), widths(&d, "C")],
        [[7.2], [5.0], [7.8]]
    );
    // A tag that no snap plane has: nothing moves.
    let d = snapping("split(x, snap, \"other\") { 5 : A. | 5 : B. | ~1 : C. }");
    assert_eq!(
        [widths(&d, "A"), widths(&d, "B"), widths(&d, "C")],
        [[5.0], [5.0], [10.0]]
    );
}

#[test]
fn muller_snapping_repeat_matches_the_main_syntax() {
    let muller = "
lot ~> [ T(7.2, 0, 0) S(5, 15, 5) Snap(\"X\") tower ] S(1r, 10, 1r) Comp(\"frontface\"){ front }
front ~> Repeat(\"XS\", 3){ tile }
";
    let d = run(muller, lot(20.0, 10.0));
    assert_eq!(widths(&d, "tile"), [2.4, 2.4, 2.4, 2.5, 2.5, 3.9, 3.9]);
}

#[test]
fn results_with_occlusion_do_not_depend_on_the_thread_count() {
    let program = common::example("courtyard.cga");
    let lots: Vec<InitialShape> = (0..12)
        .map(|i| {
            let x = f64::from(i % 4) * 20.0;
            let z = f64::from(i / 4) * 30.0;
            InitialShape::from_xz(&[
                DVec2::new(x, z),
                DVec2::new(x + 20.0, z),
                DVec2::new(x + 20.0, z + 30.0),
                DVec2::new(x, z + 30.0),
            ])
            .unwrap()
        })
        .collect();
    let options = DeriveOptions::default();
    let with = |threads| common::derive_on_threads(&program, &lots, &options, threads);
    let one = with(1);
    let four = with(4);
    assert_eq!(one.leaves, four.leaves);
    assert_eq!(one.stats, four.stats);
}

#[test]
fn occlusion_errors_have_locations() {
    let errors = compile_errors("attr hidden = inside()\nLot --> X.");
    assert!(
        errors[0].contains("attribute values cannot ask about other shapes"),
        "{errors:?}"
    );
    let e = try_run(
        "Lot --> extrude(3) comp(f) { side : F | top : T. | bottom : NIL }
         F --> case inside(somewhere) : A. else : B.",
        lot(10.0, 10.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("expected the target `all`, `intra` or `inter`, found `somewhere`"),
        "{e}"
    );
}

#[test]
fn the_setback_example_lines_piers_up_with_the_tower() {
    let text = std::fs::read_to_string(common::examples().join("setback.cga")).unwrap();
    // World x of pier edges on the base's front (the face at z = 30).
    let edges = |text: &str| -> Vec<f64> {
        let d = run(text, lot(20.0, 30.0));
        d.leaves
            .iter()
            .filter(|l| d.name(l.name) == "PierBlock")
            .filter_map(|l| l.world_mesh()?.bounds())
            .filter(|b| (b.min.z - 30.0).abs() < 1e-6 && b.max.y <= 4.0 * 3.4 + 1e-6)
            .flat_map(|b| [b.min.x, b.max.x])
            .collect()
    };
    let at = |edges: &[f64], x: f64| edges.iter().any(|e| (e - x).abs() < 1e-9);
    let snapped = edges(&text);
    // The tower spans x from 6.1 to 6.1 + 8.3.
    assert!(at(&snapped, 6.1) && at(&snapped, 14.4), "{snapped:?}");
    let plain = edges(&text.replace("split(x, snap)", "split(x)"));
    assert!(!at(&plain, 6.1) && !at(&plain, 14.4), "{plain:?}");
}

#[test]
fn courtyard_windows_stay_out_of_the_other_wings() {
    use shapegram_eval::Value;
    // The wings as (x0, x1, z0, z1) on the 20 × 30 lot.
    let u = [
        (0.0, 7.0, 0.0, 30.0),
        (13.0, 20.0, 0.0, 30.0),
        (4.0, 16.0, 21.0, 29.0),
    ];
    let l = [(0.0, 7.0, 0.0, 30.0), (4.0, 20.0, 21.0, 29.0)];
    let text = std::fs::read_to_string(common::examples().join("courtyard.cga")).unwrap();
    // Windows whose glass lies more than 0.2 m deep inside a wing (their own is 0.12 m).
    let buried = |text: &str, shape: &str, wings: &[(f64, f64, f64, f64)]| {
        let options = DeriveOptions {
            attrs: vec![("shape".into(), Value::string(shape))],
            ..DeriveOptions::default()
        };
        let d = try_run(text, lot(20.0, 30.0), &options).unwrap();
        let glass: Vec<_> = d
            .leaves
            .iter()
            .filter(|leaf| d.name(leaf.name) == "Glass")
            .map(|leaf| leaf.world_mesh().unwrap().bounds().unwrap().center())
            .collect();
        let inside = glass
            .iter()
            .filter(|c| {
                wings.iter().any(|&(x0, x1, z0, z1)| {
                    c.x > x0 + 0.2 && c.x < x1 - 0.2 && c.z > z0 + 0.2 && c.z < z1 - 0.2
                })
            })
            .count();
        (glass.len(), inside)
    };
    let blind = text.replace("case overlaps() : Wall", "case false : Wall");
    for (shape, wings) in [("U", &u[..]), ("L", &l[..])] {
        let (windows, inside) = buried(&text, shape, wings);
        assert!(windows > 80, "{shape}: {windows} windows");
        assert_eq!(inside, 0, "{shape}");
        let (_, without) = buried(&blind, shape, wings);
        assert!(
            without > 0,
            "{shape}: without the queries windows end up inside wings"
        );
    }
}

#[test]
fn answers_do_not_depend_on_the_evaluation_order() {
    // Depth first and in parallel generations, the queries give the same model (the leaves
    // come out in another order).
    let program = common::example("courtyard.cga");
    let depth_first = derive(&program, &[lot(20.0, 30.0)], &DeriveOptions::default()).unwrap();
    let generations = DeriveOptions {
        generations: Some(1000),
        ..DeriveOptions::default()
    };
    let in_steps = derive(&program, &[lot(20.0, 30.0)], &generations).unwrap();
    let census = |d: &Derivation| {
        let mut leaves: Vec<String> = d
            .leaves
            .iter()
            .map(|l| {
                format!(
                    "{} {:.6?} {:.6?}",
                    d.name(l.name),
                    l.scope.origin,
                    l.scope.size
                )
            })
            .collect();
        leaves.sort();
        leaves
    };
    assert_eq!(census(&depth_first), census(&in_steps));
    assert!(count(&depth_first, "Glass") > 100);
}

#[test]
fn the_derivation_tree_links_shapes_of_both_phases() {
    let grammar = format!("{TWO_BLOCKS}\nFace --> case touches() : Touching. else : Free.");
    let options = DeriveOptions {
        keep_tree: true,
        ..DeriveOptions::default()
    };
    let d = try_run(&grammar, lot(20.0, 10.0), &options).unwrap();
    assert_eq!(d.leaves.len(), 10);
    for leaf in &d.leaves {
        // Up the tree from every leaf, phase 2 or not, to the lot.
        let mut path = Vec::new();
        let mut at = leaf.node();
        while let Some(node) = at {
            let node = &d.tree[node as usize];
            path.push(&*node.name);
            at = node.parent;
        }
        assert_eq!(path.last(), Some(&"Lot"), "{}: {path:?}", d.name(leaf.name));
        assert!(path.contains(&"Mass"), "{}: {path:?}", d.name(leaf.name));
    }
}

#[test]
fn context_functions_count_rank_and_measure_the_labelled_shapes() {
    // Three 10 × 10 lots 15 m apart, each a labelled block 6 m high; each block asks about the
    // others (its own label is its ancestor, which context queries never see).
    let program = compile(
        "Lot --> extrude(6) label(\"block\") Ask
         Ask --> print(contextCount(inter, \"block\") + \" \" + contextCount(intra, \"block\")
                       + \" \" + minimumDistance(inter, \"block\")
                       + \" \" + contextCompare(all, \"block\", world.easternmost)
                       + \" \" + contextCompare(all, \"block\", world.highest)
                       + \" \" + isinf(minimumDistance(intra, \"block\"))
                       + \" \" + contextCount(all, \"\")) X.",
    );
    let d = derive(
        &program,
        &common::lots_in_a_row(3, 10.0, 10.0, 15.0),
        &DeriveOptions::default(),
    )
    .unwrap();
    assert_eq!(
        d.prints,
        ["2 0 5 2 0 true 0", "2 0 5 1 0 true 0", "2 0 5 0 0 true 0"]
    );
    let failed = try_run(
        "Lot --> extrude(6) label(\"b\") Ask\nAsk --> print(contextCompare(all, \"b\", area.largest)) X.",
        lot(10.0, 10.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(
        failed
            .to_string()
            .starts_with("expected `world.northernmost`"),
        "{failed}"
    );
}
