//! Rules, operations, attributes, randomness and limits.

use crate::common;

use common::{compile, compile_errors, lot, names, run, try_run};
use shapegram_eval::{DeriveOptions, Geometry, InitialShape, Value, derive};
use shapegram_geom::{DVec2, DVec3};

fn close(a: DVec3, b: DVec3) -> bool {
    a.abs_diff_eq(b, 1e-9)
}

#[test]
fn extrude_and_component_split_of_a_rectangular_lot() {
    let d = run(
        "Lot --> extrude(10) comp(f) { front : F | back : B | left : L | right : R | top : T | bottom : Bottom }",
        lot(20.0, 30.0),
    );
    // Components go to the entries in entry order.
    assert_eq!(names(&d), ["F", "B", "L", "R", "T", "Bottom"]);
    for leaf in &d.leaves {
        assert_eq!(
            leaf.geometry,
            Geometry::Box,
            "{} stays a rectangle",
            d.name(leaf.name)
        );
        assert_eq!(leaf.scope.size.z, 0.0);
    }
    let front = &d.leaves[0];
    // The front faces +z (the lot's first edge, at z = 30), 20 wide and 10 high, y up.
    assert!(close(front.scope.size, DVec3::new(20.0, 10.0, 0.0)));
    assert!(close(front.scope.z_axis(), DVec3::Z));
    assert!(close(front.scope.y_axis(), DVec3::Y));
    assert!(close(front.scope.origin, DVec3::new(0.0, 0.0, 30.0)));
    let left = &d.leaves[2];
    assert!(close(left.scope.size, DVec3::new(30.0, 10.0, 0.0)));
    let model = d.to_model();
    let mesh = model.merged_mesh().welded(1e-9);
    assert!(mesh.is_watertight());
    assert!((mesh.signed_volume() - 6000.0).abs() < 1e-9);
}

#[test]
fn side_selector_and_first_match_wins() {
    let d = run(
        "Lot --> extrude(10) comp(f) { front : F | side : S | all : Other }",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["F", "S", "S", "S", "Other", "Other"]);
    let d = run(
        "Lot --> extrude(10) comp(f) { horizontal : H | vertical : V }",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["H", "H", "V", "V", "V", "V"]);
    let d = run("Lot --> extrude(10) comp(f) { 3 : Third }", lot(20.0, 30.0));
    assert_eq!(names(&d), ["Third"]);
}

#[test]
fn comp_sel_names_the_selector() {
    let d = run(
        "Lot --> extrude(1) comp(f) { front : S(comp.sel) | side : S(comp.sel) | 3 : S(comp.sel) }
         S(n) --> case n == \"front\" : Front else : case n == \"side\" : Side else : None",
        lot(2.0, 3.0),
    );
    assert_eq!(names(&d), ["Front", "Side", "Side", "Side", "None"]);
}

#[test]
fn comp_index_and_total_and_merging() {
    let d = run(
        "Lot --> extrude(10) comp(f) { side : S(comp.index, comp.total) }
         S(i, n) --> case i == n - 1 : Last else : NotLast",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["NotLast", "NotLast", "NotLast", "Last"]);
    let d = run(
        "Lot --> extrude(10) comp(f) { side = Walls }",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["Walls"]);
    let walls = d.leaves[0].world_mesh().unwrap();
    assert_eq!(walls.face_count(), 4);
    assert!((walls.area() - 2.0 * (200.0 + 300.0)).abs() < 1e-9);
}

#[test]
fn edges_and_vertices_have_scopes_but_no_geometry() {
    let d = run(
        "Lot --> extrude(10) comp(e) { all : E(scope.sx) }
         E(len) --> s('1, 0.2, 0.2) primitiveCube() Beam(len)",
        lot(20.0, 30.0),
    );
    assert_eq!(d.leaves.len(), 12);
    let mut lengths: Vec<f64> = d.leaves.iter().map(|l| l.scope.size.x).collect();
    lengths.sort_by(f64::total_cmp);
    assert_eq!(
        lengths,
        [
            10.0, 10.0, 10.0, 10.0, 20.0, 20.0, 20.0, 20.0, 30.0, 30.0, 30.0, 30.0
        ]
    );
    let d = run("Lot --> extrude(10) comp(v) { all : V }", lot(20.0, 30.0));
    assert_eq!(d.stats.leaves, 0, "vertices have no geometry to show");
    // The lot, the eight components, and the eight `V` successors.
    assert_eq!(d.stats.shapes, 1 + 8 + 8);
}

#[test]
fn non_rectangular_lots_extrude_and_split_as_meshes() {
    let l = InitialShape::from_xz(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(4.0, 0.0),
        DVec2::new(4.0, 2.0),
        DVec2::new(2.0, 2.0),
        DVec2::new(2.0, 4.0),
        DVec2::new(0.0, 4.0),
    ])
    .unwrap();
    let d = run("Lot --> extrude(9) split(y) { ~3 : Floor }*", l.clone());
    assert_eq!(names(&d), ["Floor", "Floor", "Floor"]);
    for leaf in &d.leaves {
        let m = leaf.world_mesh().unwrap();
        assert!(m.is_watertight());
        assert!((m.signed_volume() - 36.0).abs() < 1e-9);
    }
    let d = run("Lot --> extrude(3) comp(f) { side : W | top : T }", l);
    assert_eq!(names(&d).iter().filter(|n| **n == "W").count(), 6);
    let top = d.leaves.iter().find(|l| d.name(l.name) == "T").unwrap();
    assert!((top.world_mesh().unwrap().area() - 12.0).abs() < 1e-9);
}

#[test]
fn scope_operations() {
    let d = run(
        "Lot --> s(2, 4, 6) primitiveCube() t('0.5, 1, 0) A
         A --> [ t(0, 5, 0) Up ] r(scopeCenter, 0, 90, 0) Turned",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["Up", "Turned"]);
    assert!(close(d.leaves[0].scope.origin, DVec3::new(1.0, 6.0, 0.0)));
    let turned = &d.leaves[1].scope;
    assert!(close(turned.center(), DVec3::new(2.0, 3.0, 3.0)));
    assert!(close(turned.x_axis(), -DVec3::Z));
    let d = run(
        "Lot --> s('0.5, 0, '0.5) center(xz) primitiveCube() X",
        lot(10.0, 20.0),
    );
    let s = &d.leaves[0].scope;
    assert!(close(s.origin, DVec3::new(2.5, 0.0, 5.0)));
    assert!(
        close(s.size, DVec3::new(5.0, 7.5, 10.0)),
        "a flat cube is as high as the mean of its other sizes, as in CityEngine"
    );
}

/// An asset whose box is not at the origin: 1 × 2 × 3 from (1, 2, 3).
struct OffsetBox;

impl shapegram_eval::AssetLoader for OffsetBox {
    fn load(&self, _: &str) -> Result<std::sync::Arc<shapegram_geom::Mesh>, String> {
        let cuboid = shapegram_geom::primitives::cuboid(DVec3::new(1.0, 2.0, 3.0));
        let moved = shapegram_geom::DAffine3::from_translation(DVec3::new(1.0, 2.0, 3.0));
        Ok(std::sync::Arc::new(cuboid.transformed(&moved)))
    }
}

#[test]
fn inserts_into_scopes_with_zero_sizes_follow_cityengine() {
    let options = DeriveOptions {
        assets: Some(std::sync::Arc::new(OffsetBox)),
        ..DeriveOptions::default()
    };
    // The scope and the world box of the inserted asset, on a 10 × 20 lot at the origin.
    let insert = |scale: &str| {
        let text = format!("Lot --> extrude(8) t(1, 1, 1) s({scale}) i(\"box.obj\") X");
        let d = try_run(&text, lot(10.0, 20.0), &options).unwrap();
        let leaf = &d.leaves[0];
        let mesh = leaf.world_mesh().unwrap();
        let bounds = mesh.bounds().unwrap();
        (leaf.scope.origin, leaf.scope.size, bounds.min, bounds.max)
    };
    let near = |a: DVec3, b: [f64; 3]| close(a, DVec3::from_array(b));
    // All zero: the asset as it is, relative to the scope's origin; the scope moves onto it.
    let (origin, size, min, max) = insert("0, 0, 0");
    assert!(
        near(origin, [2.0, 3.0, 4.0]) && near(size, [1.0, 2.0, 3.0]),
        "{origin} {size}"
    );
    assert!(
        near(min, [2.0, 3.0, 4.0]) && near(max, [3.0, 5.0, 7.0]),
        "{min} {max}"
    );
    // Two zero: one factor (4 / 1) for all, and the asset's offset scaled along the zero axes.
    let (origin, size, min, max) = insert("4, 0, 0");
    assert!(
        near(origin, [1.0, 9.0, 13.0]) && near(size, [4.0, 8.0, 12.0]),
        "{origin} {size}"
    );
    assert!(
        near(min, [1.0, 9.0, 13.0]) && near(max, [5.0, 17.0, 25.0]),
        "{min} {max}"
    );
    // One zero: the mean of the other factors (2 and 4 / 3) along it, and no move.
    let (origin, size, _, max) = insert("2, 0, 4");
    let mean = (2.0 + 4.0 / 3.0) / 2.0;
    assert!(near(origin, [1.0, 1.0, 1.0]), "{origin}");
    assert!(near(size, [2.0, 2.0 * mean, 4.0]), "{size}");
    assert!(near(max, [3.0, 1.0 + 2.0 * mean, 5.0]), "{max}");
    // A primitive is a unit asset: on a flat 20 × 30 lot, a cube 25 high (PRT's measure).
    let d = run("Lot --> primitiveCube() X", lot(20.0, 30.0));
    assert!(close(d.leaves[0].scope.size, DVec3::new(20.0, 25.0, 30.0)));
    for cube in ["builtin:cube", "builtin:cube:notex"] {
        let d = run(&format!("Lot --> i(\"{cube}\") X"), lot(20.0, 30.0));
        assert!(
            close(d.leaves[0].scope.size, DVec3::new(20.0, 25.0, 30.0)),
            "{cube}"
        );
        assert_eq!(d.leaves[0].world_mesh().unwrap().face_count(), 6, "{cube}");
    }
    // A flat unit quad keeps its flatness: on a 2 × 0 × 0 line, a 2 × 2 square.
    let d = run("Lot --> s(2, 0, 0) primitiveQuad() X", lot(20.0, 30.0));
    assert!(close(d.leaves[0].scope.size, DVec3::new(2.0, 2.0, 0.0)));
}

#[test]
fn insert_modes_and_up_axis_place_the_asset_as_cityengine() {
    let options = DeriveOptions {
        assets: Some(std::sync::Arc::new(OffsetBox)),
        ..DeriveOptions::default()
    };
    // The scope and the world box of the asset inserted with `args` into a 10 × 8 × 20 scope
    // at (1, 1, 1).
    let insert = |args: &str| {
        let text = format!("Lot --> extrude(8) t(1, 1, 1) i(\"box.obj\"{args}) X");
        let d = try_run(&text, lot(10.0, 20.0), &options).unwrap();
        let leaf = &d.leaves[0];
        let bounds = leaf.world_mesh().unwrap().bounds().unwrap();
        [leaf.scope.origin, leaf.scope.size, bounds.min, bounds.max]
    };
    let expect = |args: &str, want: [[f64; 3]; 4]| {
        let got = insert(args);
        assert!(
            got.iter()
                .zip(want)
                .all(|(g, w)| close(*g, DVec3::from_array(w))),
            "i(\"box.obj\"{args}): origin, size, min, max {got:?}, expected {want:?}"
        );
    };
    // The default stretches the asset's box onto the scope's.
    expect(
        "",
        [
            [1.0, 1.0, 1.0],
            [10.0, 8.0, 20.0],
            [1.0, 1.0, 1.0],
            [11.0, 9.0, 21.0],
        ],
    );
    expect(
        ", yUp, alignSizeAndPosition",
        [
            [1.0, 1.0, 1.0],
            [10.0, 8.0, 20.0],
            [1.0, 1.0, 1.0],
            [11.0, 9.0, 21.0],
        ],
    );
    // keepSizeAndPosition: the asset as it is, relative to the scope's origin, as after s(0,0,0).
    expect(
        ", yUp, keepSizeAndPosition",
        [
            [2.0, 3.0, 4.0],
            [1.0, 2.0, 3.0],
            [2.0, 3.0, 4.0],
            [3.0, 5.0, 7.0],
        ],
    );
    // keepSizeAlignPosition: its own size, centred in x and z, on the scope's floor.
    expect(
        ", yUp, keepSizeAlignPosition, noCleanup",
        [
            [5.5, 1.0, 9.5],
            [1.0, 2.0, 3.0],
            [5.5, 1.0, 9.5],
            [6.5, 3.0, 12.5],
        ],
    );
    // zUp turns the asset −90° about x first: (x, y, z) → (x, z, −y), so its box is
    // [1, 2] × [3, 6] × [−4, −2].
    expect(
        ", zUp, keepSizeAndPosition",
        [
            [2.0, 4.0, -3.0],
            [1.0, 3.0, 2.0],
            [2.0, 4.0, -3.0],
            [3.0, 7.0, -1.0],
        ],
    );
    let errors = compile_errors("Lot --> i(\"box.obj\", xUp)");
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("expected the asset's up axis, `yUp` or `zUp`")
            && errors[0].contains("test.cga:1:22"),
        "{}",
        errors[0]
    );
    let errors = compile_errors("Lot --> i(\"box.obj\", yUp, stretch)");
    assert!(
        errors[0].contains("`alignSizeAndPosition`, `keepSizeAndPosition` or"),
        "{errors:?}"
    );
}

#[test]
fn insert_fits_assets_into_the_scope() {
    let d = run(
        "Lot --> extrude(3) i(\"builtin:cylinder\") Column",
        lot(2.0, 2.0),
    );
    let mesh = d.leaves[0].world_mesh().unwrap();
    let b = mesh.bounds().unwrap();
    assert!(close(b.min, DVec3::ZERO) && close(b.max, DVec3::new(2.0, 3.0, 2.0)));
    assert!(mesh.is_watertight());
    let err = try_run(
        "Lot --> i(\"chair.obj\")",
        lot(2.0, 2.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        err.message,
        "cannot insert `chair.obj`: no asset folder is set"
    );
    assert!(err.span.is_some());
}

#[test]
fn attributes_defaults_overrides_and_set() {
    let grammar = "attr height = 10
                   attr ground = height / 2
                   Lot --> extrude(height) A
                   A --> set(height, 99) B(height, ground)
                   B(h, g) --> case h == 99 && g == 5 : Ok else : Wrong";
    assert_eq!(names(&run(grammar, lot(5.0, 5.0))), ["Ok"]);
    let program = compile(grammar);
    let options = DeriveOptions {
        attrs: vec![("height".into(), Value::Number(4.0))],
        ..Default::default()
    };
    let d = derive(&program, &[lot(5.0, 5.0)], &options).unwrap();
    assert_eq!(
        names(&d),
        ["Wrong"],
        "ground follows the overridden height: 2"
    );
    assert_eq!(d.leaves[0].scope.size.y, 4.0);
    let bad = DeriveOptions {
        attrs: vec![("heigth".into(), Value::Number(4.0))],
        ..Default::default()
    };
    let err = derive(&program, &[lot(5.0, 5.0)], &bad).unwrap_err();
    assert_eq!(err.message, "the grammar has no attribute `heigth`");
    assert_eq!(err.hints, ["did you mean `height`?"]);
}

#[test]
fn functions_constants_and_recursion_with_parameters() {
    let d = run(
        "const n = 3
         twice(x) = x * 2
         Lot --> Row(twice(n))
         Row(k) --> case k > 0 : [ t(k, 0, 0) s(1, 1, 1) primitiveCube() Box ] Row(k - 1)
                    else : NIL",
        lot(1.0, 1.0),
    );
    assert_eq!(d.leaves.len(), 6);
    let xs: Vec<f64> = d.leaves.iter().map(|l| l.scope.origin.x).collect();
    assert_eq!(xs, [6.0, 5.0, 4.0, 3.0, 2.0, 1.0]);
}

#[test]
fn stochastic_rules_are_deterministic_per_seed() {
    let grammar = "Lot --> extrude(1) split(x) { 1 : Pick }*
                   Pick --> 30% : A 30% : B else : C";
    let program = compile(grammar);
    let with_seed = |seed| {
        let options = DeriveOptions {
            seed,
            ..Default::default()
        };
        let d = derive(&program, &[lot(300.0, 1.0)], &options).unwrap();
        d.leaves
            .iter()
            .map(|l| d.name(l.name).to_string())
            .collect::<Vec<_>>()
    };
    let first = with_seed(1);
    assert_eq!(first, with_seed(1));
    assert_ne!(first, with_seed(2));
    let count = |name: &str| first.iter().filter(|n| *n == name).count();
    assert_eq!(first.len(), 300);
    for (name, expected) in [("A", 90.0), ("B", 90.0), ("C", 120.0)] {
        assert!(
            (count(name) as f64 - expected).abs() < 30.0,
            "{name}: {}",
            count(name)
        );
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let program = compile(
        "Lot --> extrude(rand(5, 20)) split(y) { ~3 : F }*
         F --> split(x) { ~2 : T }*
         T --> 50% : color(rand(), rand(), rand()) W. else : NIL",
    );
    let lots: Vec<InitialShape> = (0..40)
        .map(|i| {
            let x = f64::from(i) * 30.0;
            InitialShape::from_xz(&[
                DVec2::new(x, 0.0),
                DVec2::new(x + 20.0, 0.0),
                DVec2::new(x + 20.0, 25.0),
                DVec2::new(x, 25.0),
            ])
            .unwrap()
        })
        .collect();
    let options = DeriveOptions::default();
    let in_pool = |threads| common::derive_on_threads(&program, &lots, &options, threads);
    let (one, four) = (in_pool(1), in_pool(4));
    assert!(one.leaves.len() > 500, "{}", one.leaves.len());
    assert_eq!(one.leaves, four.leaves);
    // Each leaf has a colour of its own: batches of lots number their paints apart, and the
    // merged numbers are those of one batch.
    assert_eq!(one.paints.len(), one.leaves.len());
    assert_eq!(one.paints, four.paints);
}

#[test]
fn generations_stop_rewriting_after_n_steps() {
    let program = compile("A --> s(1, 1, 1) primitiveCube() [ t(1, 0, 0) A ] A");
    let options = DeriveOptions {
        generations: Some(3),
        ..Default::default()
    };
    let d = derive(&program, &[lot(1.0, 1.0)], &options).unwrap();
    assert_eq!(d.leaves.len(), 8);
}

#[test]
fn runaway_recursion_names_the_rule() {
    let options = DeriveOptions {
        max_depth: 50,
        ..Default::default()
    };
    let err = try_run("Lot --> A\nA --> t(1, 0, 0) A", lot(1.0, 1.0), &options).unwrap_err();
    assert!(
        err.message.contains("more than 50 shapes deep at `A`"),
        "{}",
        err.message
    );
    let options = DeriveOptions {
        max_shapes: 1000,
        ..Default::default()
    };
    let err = try_run("Lot --> Grow\nGrow --> Grow Grow", lot(1.0, 1.0), &options).unwrap_err();
    assert!(
        err.message.contains("rule `Grow` was applied most often"),
        "{}",
        err.message
    );
}

#[test]
fn the_time_budget_stops_endless_derivations() {
    let options = DeriveOptions {
        max_depth: u32::MAX,
        max_shapes: usize::MAX,
        time_budget: Some(std::time::Duration::from_millis(200)),
        ..Default::default()
    };
    let started = std::time::Instant::now();
    let err = try_run(
        "Lot --> extrude(1) A\nA --> split(x) { ~1 : A | ~1 : A }",
        lot(1.0, 1.0),
        &options,
    )
    .unwrap_err();
    assert!(
        err.message
            .starts_with("the derivation took longer than 200ms"),
        "{}",
        err.message
    );
    assert!(err.message.contains("busiest: `A`"), "{}", err.message);
    assert!(started.elapsed().as_secs_f64() < 5.0);
}

#[test]
fn runtime_errors_carry_spans() {
    let text = "attr zero = 0\nLot --> extrude(10 / zero) X";
    let err = try_run(text, lot(1.0, 1.0), &DeriveOptions::default()).unwrap_err();
    assert_eq!(err.message, "division by zero");
    let span = err.span.unwrap();
    assert_eq!(&text[span.range()], "zero");
    let err = try_run(
        "Lot --> extrude(sqrt(-1)) X",
        lot(1.0, 1.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(err.message.contains("no finite number"), "{}", err.message);
    let err = try_run(
        "Lot --> extrude(1) extrude(1) X",
        lot(1.0, 1.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(err.message.contains("is a volume"), "{}", err.message);
}

#[test]
fn compile_errors_name_the_problem_with_hints() {
    let errors = compile_errors("attr height = 10\nLot --> extrude(heigth) A(1)\nA --> X");
    let all = errors.join("\n");
    assert!(all.contains("unknown name `heigth`"), "{all}");
    assert!(all.contains("did you mean `height`?"), "{all}");
    assert!(all.contains("rule `A` takes 0 arguments, not 1"), "{all}");
    assert!(all.contains("test.cga:2:17"), "{all}");
    let errors = compile_errors("Lot --> extrude(max(1)) X").join("\n");
    assert!(errors.contains("the signature is `max(a, b)`"), "{errors}");
    let errors = compile_errors("Lot --> split(w) { 1 : A }").join("\n");
    assert!(errors.contains("expected the split axis"), "{errors}");
    let warnings = compile_errors("Lot --> Facade\n").join("\n");
    assert!(
        warnings.contains("warning: no rule `Facade`: its shapes become leaves"),
        "{warnings}"
    );
}

#[test]
fn nil_deletes_and_terminal_marks_leaves() {
    let d = run(
        "Lot --> extrude(1) split(x) { 1 : NIL | 1 : Keep. | 1 : Keep }
         Keep --> Never",
        lot(3.0, 1.0),
    );
    assert_eq!(names(&d), ["Keep", "Never"]);
}

#[test]
fn reports_and_prints_are_collected_in_order() {
    let d = run(
        "Lot --> extrude(2) comp(f) { side : W }
         W --> report(\"wall.area\", geometry.area) print(\"wall \" + comp.index)",
        lot(3.0, 4.0),
    );
    let areas: Vec<f64> = d
        .reports
        .iter()
        .map(|(k, v)| {
            assert_eq!(k, "wall.area");
            match v {
                Value::Number(n) => *n,
                other => panic!("{other:?}"),
            }
        })
        .collect();
    assert_eq!(areas, [8.0, 8.0, 6.0, 6.0]);
    assert_eq!(d.prints, ["wall 0", "wall 1", "wall 2", "wall 3"]);
}

#[test]
fn reports_name_the_tree_node_of_their_shape_when_the_tree_is_kept() {
    let program = compile(
        "Lot --> report(\"lot\", geometry.area) extrude(6) split(y) { ~3 : Floor }*
         Floor --> report(\"floor\", split.index) Slab.",
    );
    // Three lots, so that batches derived on other threads are renumbered into one tree.
    let lots = [lot(4.0, 5.0), lot(2.0, 3.0), lot(1.0, 1.0)];
    let kept = derive(
        &program,
        &lots,
        &DeriveOptions {
            keep_tree: true,
            ..DeriveOptions::default()
        },
    )
    .unwrap();
    assert_eq!(kept.reports.len(), 9);
    assert_eq!(kept.report_nodes.len(), 9);
    let made_on: Vec<(String, u32)> = kept
        .report_nodes
        .iter()
        .map(|&n| {
            let node = &kept.tree[n as usize];
            (node.name.to_string(), node.lot)
        })
        .collect();
    let expected: Vec<(String, u32)> = (0..3)
        .flat_map(|lot| {
            ["Lot", "Floor", "Floor"]
                .into_iter()
                .map(move |name| (name.to_owned(), lot))
        })
        .collect();
    assert_eq!(made_on, expected);
    // A floor's report is made on the floor whose successor is the leaf.
    let floor_of_first_slab = kept.tree[kept.leaves[0].node().unwrap() as usize].parent;
    assert_eq!(floor_of_first_slab, Some(kept.report_nodes[1]));
    // Without the tree there is nothing to point at, and nothing is kept.
    let plain = derive(&program, &lots, &DeriveOptions::default()).unwrap();
    assert!(plain.report_nodes.is_empty());
    assert_eq!(plain.reports, kept.reports);
}

#[test]
fn the_derivation_tree_links_every_shape_to_its_parent() {
    let program = compile(
        "Lot --> extrude(6) split(y) { ~3 : Floor }*
         Floor --> comp(f) { side : Wall | top : Top. }",
    );
    let options = DeriveOptions {
        keep_tree: true,
        ..Default::default()
    };
    let d = derive(&program, &[lot(4.0, 4.0), lot(2.0, 2.0)], &options).unwrap();
    assert_eq!(d.tree.len(), d.stats.shapes);
    let roots: Vec<usize> = (0..d.tree.len())
        .filter(|&i| d.tree[i].parent.is_none())
        .collect();
    assert_eq!(roots.len(), 2, "one root per lot");
    for (i, node) in d.tree.iter().enumerate() {
        if let Some(p) = node.parent {
            assert!((p as usize) < i, "parents come first");
        }
    }
    for leaf in &d.leaves {
        let node = &d.tree[leaf.node().unwrap() as usize];
        assert_eq!(&*node.name, d.name(leaf.name));
        // Wall leaf ← comp part (Floor) ← split part (Lot) ← Lot.
        let mut depth = 0;
        let mut at = leaf.node().unwrap();
        while let Some(p) = d.tree[at as usize].parent {
            at = p;
            depth += 1;
        }
        assert_eq!(depth, 4, "{}", d.name(leaf.name));
    }
    let without = derive(&program, &[lot(4.0, 4.0)], &DeriveOptions::default()).unwrap();
    assert!(without.tree.is_empty() && without.leaves[0].node().is_none());
}

#[test]
fn negative_sizes_mirror_the_scope_and_its_geometry() {
    let d = run(
        "Lot --> s(2, 1, 1) i(\"builtin:pyramid\") t(3, 0, 0) s(-2, 1, 1) Mirrored",
        lot(1.0, 1.0),
    );
    let leaf = &d.leaves[0];
    assert!((leaf.scope.axes.determinant() + 1.0).abs() < 1e-12);
    let mesh = leaf.world_mesh().unwrap();
    let b = mesh.bounds().unwrap();
    // Mirrored about x = 3: the pyramid now spans x from 1 to 3.
    assert!(close(b.min, DVec3::new(1.0, 0.0, 0.0)) && close(b.max, DVec3::new(3.0, 1.0, 1.0)));
    assert!(mesh.is_watertight());
    assert!(
        (mesh.signed_volume() - 2.0 / 3.0).abs() < 1e-9,
        "faces still face outward"
    );
    let d = run(
        "Lot --> s(1, 1, 1) t(0, 0, 0) A\nA --> D(shape.depth)\nD(n) --> s(n, 1, 1) X",
        lot(1.0, 1.0),
    );
    assert_eq!(
        d.leaves[0].scope.size.x, 1.0,
        "A is one successor below the lot"
    );
}

#[test]
fn roofs_sit_on_the_top_face() {
    let d = run(
        "Lot --> extrude(6) comp(f) { top : roofGable(30) Roof | side : Wall }",
        lot(20.0, 10.0),
    );
    let roof = d.leaves.iter().find(|l| d.name(l.name) == "Roof").unwrap();
    let mesh = roof.world_mesh().unwrap();
    assert!(mesh.is_watertight());
    // A triangular prism along the 20 m side: base 10, ridge 5·tan 30° above the eaves.
    let ridge = 5.0 * 30f64.to_radians().tan();
    assert!((mesh.signed_volume() - 0.5 * 10.0 * ridge * 20.0).abs() < 1e-9);
    let b = mesh.bounds().unwrap();
    assert!((b.min.y - 6.0).abs() < 1e-9 && (b.max.y - 6.0 - ridge).abs() < 1e-9);
    assert!(close(roof.scope.y_axis(), DVec3::Y));
    let d = run(
        "Lot --> extrude(3) comp(f) { top : roofHip(45) Roof }",
        lot(10.0, 10.0),
    );
    let hip = d.leaves[0].world_mesh().unwrap();
    assert!((hip.signed_volume() - 100.0 * 5.0 / 3.0).abs() < 1e-9);
    let d = run("Lot --> roofPyramid(45) R", lot(10.0, 10.0));
    assert!((d.leaves[0].world_mesh().unwrap().signed_volume() - 500.0 / 3.0).abs() < 1e-9);
    let d = run("Lot --> roofShed(45) R", lot(10.0, 4.0));
    // A wedge rising from the front edge across the 4 m depth to 4 m high.
    assert!(
        (d.leaves[0].world_mesh().unwrap().signed_volume() - 0.5 * 4.0 * 4.0 * 10.0).abs() < 1e-9
    );
    let err = try_run(
        "Lot --> roofGable(95) R",
        lot(10.0, 4.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(
        err.message.starts_with("cannot build this roof"),
        "{}",
        err.message
    );
    let err = try_run(
        "Lot --> extrude(2) roofHip(30) R",
        lot(10.0, 4.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(err.message.contains("is a volume"), "{}", err.message);
}

#[test]
fn offset_splits_a_lot_into_inside_and_border() {
    let d = run(
        "Lot --> offset(-1) comp(f) { inside : Yard | border : Path }",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["Yard", "Path", "Path", "Path", "Path"]);
    let area = |name: &str| -> f64 {
        d.leaves
            .iter()
            .filter(|l| d.name(l.name) == name)
            .map(|l| l.world_mesh().unwrap().area())
            .sum()
    };
    assert!((area("Yard") - 64.0).abs() < 1e-9);
    assert!((area("Path") - 36.0).abs() < 1e-9);
    let d = run("Lot --> offset(-1, inside) Yard", lot(10.0, 10.0));
    assert_eq!(d.leaves.len(), 1);
    assert!(close(d.leaves[0].scope.size, DVec3::new(8.0, 0.0, 8.0)));
    let d = run(
        "Lot --> offset(-6) comp(f) { inside : Yard | border : Path }",
        lot(10.0, 10.0),
    );
    assert_eq!(
        names(&d),
        ["Path", "Path", "Path", "Path"],
        "the inset vanished"
    );
}

#[test]
fn a_start_rule_with_parameters_is_an_error_not_a_crash() {
    // Without @StartRule, the first rule without parameters starts.
    let d = run(
        "Wing(w) --> s(w, '1, '1) X\nLot --> Wing(3)",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["X"]);
    let err = try_run(
        "@StartRule\nWing(w, h) --> X",
        lot(1.0, 1.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        err.message,
        "the start rule `Wing` takes 2 parameters, but a lot has no values for them"
    );
    // Only rules with parameters: the first is the start, and the same error.
    let err = try_run("Wing(w) --> X", lot(1.0, 1.0), &DeriveOptions::default()).unwrap_err();
    assert!(
        err.message
            .starts_with("the start rule `Wing` takes 1 parameter,"),
        "{}",
        err.message
    );
}

#[test]
fn rint_rounds_halves_to_even_and_numbers_are_never_nan_or_infinite() {
    let d = run(
        "Lot --> print(rint(2.5) + \" \" + rint(3.5) + \" \" + rint(-2.5) + \" \" + rint(2.6))
               print(isnan(1) + \" \" + isinf(1e300 * 10))",
        lot(3.0, 4.0),
    );
    assert_eq!(d.prints, ["2 4 -2 3", "false false"]);
}

#[test]
fn inserts_below_a_face_split_end_on_the_corner_mitres() {
    // A 10 × 10 tower; each facade gets a ledge 20 % too long, centred, 0.5 m deep.
    let ledges = |extra: &str, op: &str| {
        let text = format!(
            "Lot --> extrude(6) comp(f) {{ side {op} Facade }}
Facade --> {extra} t(0, 3, 0) s('1, 0.3, 0.5) s('1.2, '1, '1) center(x) primitiveCube() Ledge."
        );
        let d = run(&text, lot(10.0, 10.0));
        let mut all = shapegram_geom::Mesh::new();
        for leaf in &d.leaves {
            all.append(&leaf.world_mesh().unwrap());
        }
        (d.leaves.len(), all.bounds().unwrap())
    };
    // Trimmed: every ledge ends on the mitres, so the ring is 10.5 m across (0.5 m proud on
    // every side) and nothing reaches past the corners' diagonals.
    let (n, trimmed) = ledges("", ":");
    assert_eq!(n, 4);
    assert!(
        close(trimmed.min, DVec3::new(-0.5, 3.0, -0.5)),
        "{trimmed:?}"
    );
    assert!(
        close(trimmed.max, DVec3::new(10.5, 3.3, 10.5)),
        "{trimmed:?}"
    );
    // Untrimmed (vertical trimming off, or faces merged with `=`): they stick out 1 m.
    for (extra, op) in [("set(trim.vertical, false)", ":"), ("", "=")] {
        let (_, loose) = ledges(extra, op);
        assert!(
            loose.max.x > 10.9 || loose.max.z > 10.9,
            "{extra} {op}: {loose:?}"
        );
    }
    // Horizontal planes (the facade's top and bottom edges) cut only when asked to.
    let tall = "Lot --> extrude(6) comp(f) { side : Facade }
Facade --> SET s('1, 8, 0.5) center(x) primitiveCube() Pier.";
    let top = |set: &str| {
        let d = run(&tall.replace("SET", set), lot(10.0, 10.0));
        let mut y: f64 = 0.0;
        for leaf in &d.leaves {
            y = y.max(leaf.world_mesh().unwrap().bounds().unwrap().max.y);
        }
        y
    };
    assert!((top("") - 8.0).abs() < 1e-9);
    assert!(top("set(trim.horizontal, true)") < 6.0 + 0.5 + 1e-9);
}

#[test]
fn trim_cuts_the_shape_s_own_geometry() {
    // Each facade extruded into a 0.5 m slab, 20 % too wide: trim() mitres it at the corners.
    let text = |trim: &str| {
        format!(
            "Lot --> extrude(6) comp(f) {{ side : Facade }}
Facade --> s('1.2, '1, '1) center(x) extrude(0.5) {trim} Slab."
        )
    };
    let bounds = |text: &str| {
        let d = run(text, lot(10.0, 10.0));
        let mut all = shapegram_geom::Mesh::new();
        for leaf in &d.leaves {
            all.append(&leaf.world_mesh().unwrap());
        }
        all.bounds().unwrap()
    };
    let trimmed = bounds(&text("trim()"));
    assert!(
        close(trimmed.min, DVec3::new(-0.5, 0.0, -0.5)),
        "{trimmed:?}"
    );
    assert!(
        close(trimmed.max, DVec3::new(10.5, 6.0, 10.5)),
        "{trimmed:?}"
    );
    let loose = bounds(&text(""));
    assert!(loose.max.x > 10.9, "{loose:?}");
}

#[test]
fn a_lot_numbered_apart_derives_as_it_does_among_all_lots() {
    let program = compile(
        "attr height = rand(3, 30)\n\
         Lot --> print(initialShape.name) extrude(height) split(y) { ~1 : Floor }*\n\
         Floor --> 50% : A. else : B.",
    );
    let options = DeriveOptions {
        seed: 11,
        ..DeriveOptions::default()
    };
    let all = common::lots_in_a_row(5, 8.0, 8.0, 10.0);
    let whole = derive(&program, &all, &options).unwrap();
    let of_lot = |d: &shapegram_eval::Derivation, lot: u32| {
        d.leaves
            .iter()
            .filter(|l| l.lot == lot)
            .map(|l| (d.name(l.name).to_string(), l.scope))
            .collect::<Vec<_>>()
    };
    // Lots 3 and 1 alone, in that order, numbered as in the whole list.
    let apart: Vec<InitialShape> = [3, 1]
        .iter()
        .map(|&i| InitialShape {
            index: Some(i),
            ..all[i as usize].clone()
        })
        .collect();
    let d = derive(&program, &apart, &options).unwrap();
    assert_eq!(d.prints, ["shape_3", "shape_1"]);
    assert_eq!(of_lot(&d, 0), of_lot(&whole, 3));
    assert_eq!(of_lot(&d, 1), of_lot(&whole, 1));
    assert!(of_lot(&d, 0).len() > 1);
    // Unnumbered, the first lot takes the seed of lot 0: another building.
    let unnumbered = derive(&program, &all[3..4], &options).unwrap();
    assert_eq!(unnumbered.prints, ["shape_0"]);
    assert_ne!(of_lot(&unnumbered, 0), of_lot(&whole, 3));
}
