//! CGA's `setback` and `shapeL`, `shapeU`, `shapeO` on lots: strips, outlines and remainders
//! with their areas and scopes.

use crate::common;

use common::{assert_close, compile_errors, lot, names, numeric_reports, of, try_run};
use shapegram_eval::DeriveOptions;

/// The `(key, number)` reports of `text` derived on the 20 × 30 lot.
fn reports(text: &str) -> Vec<(String, f64)> {
    numeric_reports(text, lot(20.0, 30.0))
}

const AREA: &str = "report(\"area\", geometry.area)";

#[test]
fn a_front_yard_and_the_rest() {
    let r = reports(&format!(
        "Lot --> setback(5) {{ front : report(\"yard\", geometry.area) Yard. | remainder : {AREA} Rest. }}"
    ));
    // The front edge is 20 long.
    assert_close(&of(&r, "yard"), &[100.0]);
    assert_close(&of(&r, "area"), &[500.0]);
    // street.front reads as front, there being no streets.
    let street = reports(&format!(
        "Lot --> setback(5) {{ street.front : {AREA} Yard. | remainder : NIL }}"
    ));
    assert_close(&of(&street, "area"), &[100.0]);
}

#[test]
fn strips_run_along_their_edges_and_merge_with_equals() {
    let r = reports(&format!(
        "Lot --> setback(2) {{ side : report(\"sx\", scope.sx) report(\"sz\", scope.sz) {AREA} Path. | remainder : NIL }}"
    ));
    // Four mitred trapezoids, each as long as its edge, 2 deep, its scope flat in y.
    let mut sx = of(&r, "sx");
    sx.sort_by(f64::total_cmp);
    assert_close(&sx, &[20.0, 20.0, 30.0, 30.0]);
    assert_close(&of(&r, "sz"), &[2.0; 4]);
    let total: f64 = of(&r, "area").iter().sum();
    assert!((total - (600.0 - 16.0 * 26.0)).abs() < 1e-9);
    let merged = reports(&format!(
        "Lot --> setback(2) {{ side = {AREA} Path. | remainder : NIL }}"
    ));
    assert_close(&of(&merged, "area"), &[600.0 - 16.0 * 26.0]);
}

#[test]
fn opposite_edges_meet_in_the_middle() {
    // Set back 40 from front and back, the lot is all strips, 15 deep each.
    let r = reports(&format!(
        "Lot --> setback(40) {{ front : {AREA} A. | back : {AREA} B. | remainder : {AREA} R. }}"
    ));
    assert_close(&of(&r, "area"), &[300.0, 300.0]);
}

#[test]
fn each_edge_goes_to_the_first_entry_that_takes_it() {
    let d = try_run(
        "Lot --> setback(3) { front : Front. | side : Side. | remainder : Rest. }",
        lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap();
    assert_eq!(names(&d), ["Front", "Side", "Side", "Side", "Rest"]);
}

#[test]
fn shape_l_u_and_o() {
    let shape = |op: &str| {
        reports(&format!(
            "Lot --> {op} {{ shape : report(\"shape\", geometry.area) report(\"faces\", geometry.nFaces) X. | remainder : {AREA} R. }}"
        ))
    };
    // Front 8 deep along the 20 m edge; side wings 5 (or 4) wide along the 30 m edges.
    let l = shape("shapeL(8, 5)");
    assert_close(&of(&l, "shape"), &[20.0 * 8.0 + 5.0 * 22.0]);
    assert_close(&of(&l, "area"), &[15.0 * 22.0]);
    assert_close(&of(&l, "faces"), &[1.0]);
    let u = shape("shapeU(8, 4, 4)");
    assert_close(&of(&u, "shape"), &[160.0 + 2.0 * 4.0 * 22.0]);
    assert_close(&of(&u, "area"), &[12.0 * 22.0]);
    // The O has a hole, which a face cannot hold: it stays as its four strips.
    let o = shape("shapeO(6, 4, 6, 4)");
    assert_close(&of(&o, "shape"), &[600.0 - 12.0 * 18.0]);
    assert_close(&of(&o, "faces"), &[4.0]);
    assert_close(&of(&o, "area"), &[12.0 * 18.0]);
}

#[test]
fn bad_setbacks_are_errors() {
    let run = |text: &str| try_run(text, lot(20.0, 30.0), &DeriveOptions::default());
    let text = "Lot --> setback(-1) { all : A. }";
    let e = run(text).unwrap_err();
    assert_eq!(e.message, "setback distance -1: expected 0 or more");
    assert_eq!(&text[e.span.unwrap().range()], "-1");
    let e = run("Lot --> extrude(3) setback(1) { all : A. }").unwrap_err();
    assert!(e.message.contains("needs a flat shape"), "{}", e.message);
    // On an L-shaped lot, the top of its 10 m deep wing (edge 3) set back 25 runs onto the line
    // of the lot's bottom edge, which stays; set back 5, it is fine.
    let l_lot = shapegram_eval::InitialShape::from_xz(
        &[
            (0.0, 0.0),
            (20.0, 0.0),
            (20.0, 10.0),
            (10.0, 10.0),
            (10.0, 30.0),
            (0.0, 30.0),
        ]
        .map(|(x, z)| shapegram_geom::DVec2::new(x, z)),
    )
    .unwrap();
    let deep = "Lot --> setback(25) { 3 : A. | remainder : B. }";
    let e = try_run(deep, l_lot.clone(), &DeriveOptions::default()).unwrap_err();
    assert!(
        e.message.starts_with("setback cannot cut this shape"),
        "{}",
        e.message
    );
    let shallow = "Lot --> setback(5) { 3 : A. | remainder : B. }";
    assert_eq!(
        names(&try_run(shallow, l_lot, &DeriveOptions::default()).unwrap()),
        ["A", "B"]
    );

    let errors = compile_errors("Lot --> shapeL(1, 2) { front : A. }").join("\n");
    assert!(
        errors.contains("`shapeL` selects `shape` or `remainder`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> setback(1)").join("\n");
    assert!(
        errors.contains("`setback` needs a `{ selector : … | remainder : … }` block"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> shapeU(1, 2) { shape : A. }").join("\n");
    assert!(
        errors.contains("the signature is `shapeU(frontDepth, rightWidth, leftWidth)`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> setback(1) { vertical : A. }").join("\n");
    assert!(
        errors.contains("for faces, not the edges of a setback"),
        "{errors}"
    );
}

#[test]
fn setback_takes_a_distance_per_edge_from_an_array_or_the_comp_function() {
    let area = |grammar: &str| {
        let d = common::run(grammar, common::lot(10.0, 10.0));
        let rest: Vec<_> = d
            .leaves
            .iter()
            .filter(|l| d.name(l.name) == "Rest")
            .collect();
        assert_eq!(rest.len(), 1, "{grammar}");
        rest[0].world_mesh().unwrap().area()
    };
    // One edge 3 m in, the others 1 m: 8 × 6 m left.
    let a = area(
        "Lot --> setback(comp(fe) { front : 3 | all : 1 }) { all = Strip | remainder = Rest }",
    );
    assert!((a - 48.0).abs() < 1e-9, "{a}");
    // Face-edge order; missing entries stay.
    let a = area("Lot --> setback([2, 0, 0]) { all = Strip | remainder = Rest }");
    assert!((a - 80.0).abs() < 1e-9, "{a}");
    let d = common::run(
        "Lot --> report(\"n\", size(comp(fe) { all : 1 })) report(\"sum\", comp(fe) { front : 5 | 2 : 7 }[2])",
        common::lot(10.0, 10.0),
    );
    let values: Vec<String> = d.reports.iter().map(|(k, v)| format!("{k}={v}")).collect();
    assert_eq!(values, ["n=4", "sum=7"]);
    let e = common::try_run(
        "Lot --> setback([1, -2]) { all = Strip | remainder = Rest }",
        common::lot(10.0, 10.0),
        &shapegram_eval::DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        e.message,
        "setback distances: expected numbers of 0 or more, found -2"
    );
}

#[test]
fn setback_per_edge_evaluates_its_distance_on_each_edge() {
    // scope.sx is the edge's length: the 20 m edges move 2 m, the 30 m edges 3 m.
    let r = reports(&format!(
        "Lot --> setbackPerEdge(scope.sx / 10) {{ all = NIL | remainder : {AREA} Rest. }}"
    ));
    assert_close(&of(&r, "area"), &[(20.0 - 6.0) * (30.0 - 4.0)]);
    // comp.index counts the face edges: 0 and 2 across the depth, 1 and 3 across the width.
    let d = common::run(
        "Lot --> setbackPerEdge(comp.index) { all = NIL | remainder : Rest. }",
        common::lot(10.0, 10.0),
    );
    let rest = d.leaves[0].world_mesh().unwrap().area();
    assert!(
        (rest - (10.0 - 1.0 - 3.0) * (10.0 - 0.0 - 2.0)).abs() < 1e-9,
        "{rest}"
    );
    // Every edge moves, selected or not; the front strip is a mitred trapezoid.
    let r = reports(&format!(
        "Lot --> setbackPerEdge(2) {{ front : report(\"front\", geometry.area) F. | remainder : {AREA} R. }}"
    ));
    assert_close(&of(&r, "front"), &[(20.0 + 16.0) / 2.0 * 2.0]);
    assert_close(&of(&r, "area"), &[16.0 * 26.0]);
    let errors = compile_errors("Lot --> setbackPerEdge(1, 0, 2) { all : A. }").join("\n");
    assert!(
        errors.contains("wrong number of arguments for `setbackPerEdge`"),
        "{errors}"
    );
    let error = try_run(
        "Lot --> setbackPerEdge(comp.index - 1) { all : A. }",
        lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("setback distance -1: expected 0 or more"),
        "{error}"
    );
}

#[test]
fn setback_to_area_leaves_the_remainder_that_area() {
    let rest = |grammar: &str| of(&reports(grammar), "area");
    // One common distance d for all edges: (20 - 2d)(30 - 2d) = 300.
    assert_close(
        &rest(&format!(
            "Lot --> setbackToArea(300) {{ all = NIL | remainder : {AREA} R. }}"
        )),
        &[300.0],
    );
    // The front edge alone moves 15 m; its strip is the other half.
    let r = reports(&format!(
        "Lot --> setbackToArea(300) {{ front : report(\"strip\", scope.sz) {AREA} S. | remainder : {AREA} R. }}"
    ));
    assert_close(&of(&r, "area"), &[300.0, 300.0]);
    assert_close(&of(&r, "strip"), &[15.0]);
    // Minimum distances come first, the common distance on top: the front 10 m + d.
    assert_close(
        &rest(&format!(
            "Lot --> setbackToArea(300, [10, 0, 0, 0]) {{ all = report(\"strips\", geometry.area) NIL | remainder : {AREA} R. }}"
        )),
        &[300.0],
    );
    // Targets out of reach leave the shape whole: maxima of 1 m leave at least 18 × 28 m, and
    // no setback grows a lot.
    for (arguments, left) in [
        ("300, [0, 0, 0, 0], [1, 1, 1, 1]", 600.0),
        ("700", 600.0),
        // A number last is the uv set.
        ("300, 0", 300.0),
    ] {
        let r = reports(&format!(
            "Lot --> setbackToArea({arguments}) {{ all = S. | remainder : {AREA} R. }}"
        ));
        assert_close(&of(&r, "area"), &[left]);
    }
    for (grammar, message) in [
        (
            "Lot --> setbackToArea(-5) { all : A. }",
            "setbackToArea's area must be more than 0, not -5",
        ),
        (
            "Lot --> setbackToArea(5, \"x\") { all : A. }",
            "expected arrays of minimum and maximum distances",
        ),
        (
            "Lot --> setbackToArea(5, [1, -1]) { all : A. }",
            "expected numbers of 0 or more",
        ),
    ] {
        let error = try_run(grammar, lot(20.0, 30.0), &DeriveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains(message), "{grammar}: {error}");
    }
}
