//! CGA's `splitAndSetbackPerimeter` on lots: sections laid out along the perimeter, each set
//! back by its own depth, overlaps to the deeper, and the remainder.

use crate::common;

use common::{assert_close, compile_errors, lot, numeric_reports, of, try_run};
use shapegram_eval::DeriveOptions;

/// The `(key, number)` reports of `text` derived on the 20 × 30 lot, whose first edge is its
/// 20 m front.
fn reports(text: &str) -> Vec<(String, f64)> {
    numeric_reports(text, lot(20.0, 30.0))
}

const AREA: &str = "report(\"area\", geometry.area)";

#[test]
fn two_sections_along_the_front_and_the_rest() {
    let r = reports(&format!(
        "Lot --> splitAndSetbackPerimeter(0) {{ 10 : 2 : report(\"sx\", scope.sx) report(\"sz\", scope.sz) {AREA} A. | 10 : 4 : {AREA} B. }} {{ remainder : report(\"rest\", geometry.area) R. }}"
    ));
    // Each a rectangle on half the front, as deep as its depth; at the lot's corners they run
    // along the side edges, which stay.
    assert_close(&of(&r, "area"), &[20.0, 40.0]);
    assert_close(&of(&r, "sx"), &[10.0]);
    assert_close(&of(&r, "sz"), &[2.0]);
    assert_close(&of(&r, "rest"), &[540.0]);
}

#[test]
fn repeated_sections_take_their_depth_from_split_index_and_the_deeper_wins() {
    let r = reports(&format!(
        "Lot --> splitAndSetbackPerimeter(0) {{ ~25 : split.index + 1 : report(\"i\", split.index) {AREA} A. }}* {{ remainder : report(\"rest\", geometry.area) R. }}"
    ));
    // Four sections of 25 m round the 100 m perimeter, 1, 2, 3 and 4 m deep. The first (front
    // and 5 m of the right side, mitred between them: 24 m²) loses 4 m² to the fourth (4 × 25
    // along the left side); the second (2 × 25 up the right side) loses 2 × 3 to the third (the
    // back with 5 m of the left side, mitred: 66 m²).
    assert_close(&of(&r, "i"), &[0.0, 1.0, 2.0, 3.0]);
    assert_close(&of(&r, "area"), &[20.0, 44.0, 66.0, 100.0]);
    assert_close(&of(&r, "rest"), &[370.0]);
}

#[test]
fn the_first_edge_the_mask_and_a_relative_offset_pick_the_stretch() {
    // Only the back edge (face edge 2, 20 m): the pattern starts a quarter along it.
    let r = reports(&format!(
        "Lot --> splitAndSetbackPerimeter('0.25, 2, [false, false, true]) {{ '0.5 : 3 : report(\"sx\", scope.sx) {AREA} A. }} {{ remainder : report(\"rest\", geometry.area) R. }}"
    ));
    assert_close(&of(&r, "area"), &[30.0]);
    assert_close(&of(&r, "sx"), &[10.0]);
    assert_close(&of(&r, "rest"), &[570.0]);
    // A first edge past the end wraps: 6 is edge 2 of 4.
    let wrapped = reports(&format!(
        "Lot --> splitAndSetbackPerimeter('0.25, 6, [false, false, true]) {{ '0.5 : 3 : {AREA} A. }} {{ remainder : NIL }}"
    ));
    assert_close(&of(&wrapped, "area"), &[30.0]);
    // A pattern starting near the end comes round to the start: the last 10 m of the left side
    // and the first 10 of the front, 1 deep and mitred at the corner between them, one shape.
    let round = reports(&format!(
        "Lot --> splitAndSetbackPerimeter(90) {{ 20 : 1 : {AREA} report(\"faces\", geometry.nFaces) A. }} {{ remainder : NIL }}"
    ));
    assert_close(&of(&round, "area"), &[2.0 * 9.5]);
    assert_close(&of(&round, "faces"), &[1.0]);
    // A section's scope runs along the edge it starts on: here the last 20 m of the left side
    // (then 10 m of the front), so x runs up the side.
    let start = reports(
        "Lot --> splitAndSetbackPerimeter(80) { 30 : 1 : report(\"sx\", scope.sx) report(\"sz\", scope.sz) A. } { remainder : NIL }",
    );
    assert_close(&of(&start, "sx"), &[20.0]);
    assert_close(&of(&start, "sz"), &[10.0]);
}

#[test]
fn bad_arguments_are_errors_with_their_place() {
    for (grammar, message) in [
        (
            "Lot --> splitAndSetbackPerimeter(0) { 10 : -1 : A. } { remainder : R. }",
            "a section's setback depth must be 0 or more, not -1",
        ),
        (
            "Lot --> splitAndSetbackPerimeter(0, 0, 5) { 10 : 1 : A. }",
            "edge mask is an array of booleans",
        ),
        (
            "Lot --> splitAndSetbackPerimeter(0, 0, [1]) { 10 : 1 : A. }",
            "edge mask holds booleans, not number",
        ),
        (
            "Lot --> extrude(3) splitAndSetbackPerimeter(0) { 10 : 1 : A. }",
            "needs a flat shape",
        ),
    ] {
        let error = try_run(grammar, lot(20.0, 30.0), &DeriveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains(message), "{grammar}: {error}");
    }
    for (grammar, message) in [
        (
            "Lot --> splitAndSetbackPerimeter(0, 1) { 10 : 1 : A. }",
            "arguments",
        ),
        (
            "Lot --> splitAndSetbackPerimeter(0) A.",
            "needs a `{ length : depth : … }` block",
        ),
        (
            "Lot --> splitAndSetbackPerimeter(0) { 10 : 1 : A. } { front : B. }",
            "holds one `remainder : …` entry",
        ),
    ] {
        let errors = compile_errors(grammar);
        assert!(
            errors
                .iter()
                .any(|e| e.contains(message) && e.contains("1:")),
            "{grammar}: {errors:?}"
        );
    }
}

#[test]
fn an_l_shaped_lot_all_round_and_the_reference_examples_run() {
    use shapegram_eval::InitialShape;
    use shapegram_geom::DVec2;
    // 20 × 20 less its 10 × 10 back-right quarter: 300 m², perimeter 80 m.
    let l = InitialShape::from_xz(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(20.0, 0.0),
        DVec2::new(20.0, 10.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(10.0, 20.0),
        DVec2::new(0.0, 20.0),
    ])
    .unwrap();
    let r = numeric_reports(
        &format!(
            "Lot --> splitAndSetbackPerimeter(0) {{ ~1 : 1 : {AREA} A. }} {{ remainder : report(\"rest\", geometry.area) R. }}"
        ),
        l.clone(),
    );
    // One section all round, 1 deep: the rest is the L inset by 1 (18 × 8 + 8 × 10).
    assert_close(&of(&r, "rest"), &[18.0 * 8.0 + 8.0 * 10.0]);
    assert_close(&of(&r, "area"), &[300.0 - 224.0]);
    for grammar in [
        "Lot --> splitAndSetbackPerimeter(6) { 40 : 5 : Y | 20 : 10 : B } { remainder : G }",
        "Lot --> splitAndSetbackPerimeter('0.1) { '0.5 : 10 : extrude(15) Y | ~1 : 0 : NIL | '0.4 : 8 : extrude(10) B | ~1 : 0 : NIL } { remainder : G }",
        "Lot --> splitAndSetbackPerimeter(0) { ~30 : rand(3, 15) : extrude(rand(2, 10)) Y }* { remainder : G }",
        "Lot --> splitAndSetbackPerimeter(3) { 2 : 6 : Y | 2 : 0 : NIL | 2 : 4 : B } { remainder : G }",
    ] {
        for shape in [l.clone(), lot(20.0, 30.0)] {
            try_run(grammar, shape, &DeriveOptions::default())
                .unwrap_or_else(|e| panic!("{grammar}: {e}"));
        }
    }
}

#[test]
fn random_depths_are_drawn_per_section_and_the_same_each_run() {
    let grammar = format!(
        "Lot --> splitAndSetbackPerimeter(0) {{ ~25 : rand(1, 3) : {AREA} A. }}* {{ remainder : {AREA} R. }}"
    );
    let first = of(&reports(&grammar), "area");
    assert_eq!(first.len(), 5);
    // Four sections, each its own depth: no two of the same area, and all of them with the
    // remainder the lot.
    let mut sections = first[..4].to_vec();
    sections.sort_by(f64::total_cmp);
    sections.dedup();
    assert_eq!(sections.len(), 4, "{first:?}");
    assert!((first.iter().sum::<f64>() - 600.0).abs() < 1e-9);
    assert_eq!(of(&reports(&grammar), "area"), first);
}
