//! `union`, `subtract`, `intersect` and `inline`: exact volumes, areas and triangle counts of
//! the results, the target's attributes, determinism, and the errors of bad forms.

use crate::common;

use common::{
    assert_close, compile, compile_errors, derive_on_threads, lot, lots_in_a_row, names,
    numeric_reports, of, run, try_run,
};
use shapegram_eval::{Derivation, DeriveOptions, derive, derive_again};
use shapegram_geom::primitives::cylinder_volume;
use shapegram_geom::{Color, DVec3, Mesh};

/// The world mesh of the only leaf of `text` derived on a `w` × `d` lot.
fn only_mesh(text: &str, w: f64, d: f64) -> Mesh {
    let d = run(text, lot(w, d));
    assert_eq!(d.leaves.len(), 1, "{:?}", names(&d));
    d.leaves[0].world_mesh().unwrap()
}

fn assert_near(actual: f64, expected: f64) {
    assert!(
        (actual - expected).abs() < 1e-9,
        "{actual} is not {expected}"
    );
}

/// A 1 × 1 × 3 bar through the middle of the 2 × 2 × 2 box, along the scope's z.
const BAR: &str = "s(1, 1, 3) t(0.5, 0.5, -0.5) primitiveCube()";

#[test]
fn a_box_minus_a_bar_through_it_keeps_six_cubic_metres() {
    let mesh = only_mesh(
        &format!("Lot --> extrude(2) subtract {{ {BAR} }} Mass."),
        2.0,
        2.0,
    );
    assert_near(mesh.signed_volume(), 6.0);
    assert!(mesh.is_watertight());
    // 24 m² outside, less the two 1 m² mouths, plus the tunnel's four 2 m² walls.
    assert_near(mesh.area(), 30.0);
    assert_eq!(mesh.face_count(), 32);
}

#[test]
fn union_and_intersect_of_two_boxes() {
    let moved = "t(1, 1, 1) primitiveCube()";
    let union = only_mesh(&format!("Lot --> extrude(2) union {{ {moved} }}"), 2.0, 2.0);
    assert_near(union.signed_volume(), 15.0);
    assert!(union.is_watertight());
    assert_eq!(union.face_count(), 36);
    let both = only_mesh(
        &format!("Lot --> extrude(2) intersect {{ {moved} }}"),
        2.0,
        2.0,
    );
    assert_near(both.signed_volume(), 1.0);
    assert_eq!(both.face_count(), 12);
}

#[test]
fn a_box_minus_a_cylinder_through_it() {
    let text = "Lot --> extrude(2) subtract { s(1, 3, 1) t(0.5, -0.5, 0.5) primitiveCylinder(16) }";
    let mesh = only_mesh(text, 2.0, 2.0);
    let hole = cylinder_volume(DVec3::new(1.0, 2.0, 1.0), 16);
    assert_near(mesh.signed_volume(), 8.0 - hole);
    // Two 16-gon mouths in the top and bottom, and 16 walls of two triangles.
    assert_eq!(mesh.face_count(), 80);
    assert!(mesh.is_watertight());
}

#[test]
fn the_rule_forms_name_operand_b_and_swap_makes_it_the_target() {
    let rules = format!("Bar --> {BAR}\n");
    let plain = only_mesh(
        &format!("Lot --> extrude(2) subtract Bar\n{rules}"),
        2.0,
        2.0,
    );
    assert_near(plain.signed_volume(), 6.0);
    // The bar without the box: its two ends, each 1 × 1 × 0.5.
    let swapped = only_mesh(
        &format!("Lot --> extrude(2) subtract(swap) Bar\n{rules}"),
        2.0,
        2.0,
    );
    assert_near(swapped.signed_volume(), 1.0);
    let explicit = only_mesh(
        &format!("Lot --> extrude(2) subtract {{ Bar | X. }}\n{rules}"),
        2.0,
        2.0,
    );
    assert_near(explicit.signed_volume(), 1.0);
}

#[test]
fn a_lot_minus_a_volume_is_punched_and_intersected_is_clipped() {
    let cube = "s(1, 1, 1) t(1, -0.5, 1) primitiveCube()";
    let punched = only_mesh(&format!("Lot --> subtract {{ {cube} }}"), 4.0, 4.0);
    assert_near(punched.area(), 15.0);
    // A square with a square hole: eight triangles.
    assert_eq!(punched.face_count(), 8);
    assert!(punched.positions().iter().all(|p| p.y.abs() < 1e-12));
    let clipped = only_mesh(&format!("Lot --> intersect {{ {cube} }}"), 4.0, 4.0);
    assert_near(clipped.area(), 1.0);
    // A plane has no volume: subtracting it leaves the box as it was.
    let kept = only_mesh(
        "Lot --> extrude(2) subtract { s('1, 0, '1) t(0, 1, 0) }",
        2.0,
        2.0,
    );
    assert_near(kept.signed_volume(), 8.0);
}

#[test]
fn flat_operands_in_one_plane_combine_in_two_dimensions() {
    let area = |operation: &str| {
        only_mesh(&format!("Lot --> {operation} {{ t(2, 0, 2) }}"), 4.0, 4.0).area()
    };
    assert_near(area("union"), 28.0);
    assert_near(area("subtract"), 12.0);
    assert_near(area("intersect"), 4.0);
    // The parts of a split lot unified: one region, a square whose sides keep the seam's
    // ends as corners (six corners, four triangles).
    let yard = only_mesh(
        "Lot --> inline(unify) split(x) { 1 : A. | ~1 : B. }",
        4.0,
        4.0,
    );
    assert_near(yard.area(), 16.0);
    assert_eq!((yard.vertex_count(), yard.face_count()), (6, 4));
    // Overlaps wear the target's colour; the rest of B its own.
    let model = run(
        "Lot --> color(\"#ff0000\") union { t(2, 0, 2) color(\"#0000ff\") } Yard.",
        lot(4.0, 4.0),
    )
    .to_model();
    let blue = Color::from_hex("#0000ff").unwrap();
    let (b, a): (Vec<_>, Vec<_>) = model.parts.iter().partition(|p| p.color == blue);
    assert_near(b.iter().map(|p| p.mesh.area()).sum(), 12.0);
    assert_near(a.iter().map(|p| p.mesh.area()).sum(), 16.0);
}

#[test]
fn the_result_has_the_targets_attributes() {
    let report = |operation: &str| {
        let text = format!(
            "attr h = 10\nLot --> extrude(2) {operation} {{ set(h, 5) t(1, 0, 0) }} report(\"h\", h)"
        );
        of(&numeric_reports(&text, lot(2.0, 2.0)), "h")
    };
    assert_close(&report("union"), &[10.0]);
    assert_close(&report("union(swap)"), &[5.0]);
}

#[test]
fn the_faces_of_operand_b_keep_its_colour() {
    let text = "Lot --> extrude(2) color(\"#ff0000\") \
                subtract { s(1, 1, 3) t(0.5, 0.5, -0.5) primitiveCube() color(\"#0000ff\") } Mass.";
    let model = run(text, lot(2.0, 2.0)).to_model();
    let area_of = |hex: &str| -> f64 {
        let color = Color::from_hex(hex).unwrap();
        model
            .parts
            .iter()
            .filter(|p| p.color == color)
            .map(|p| p.mesh.area())
            .sum()
    };
    // The box's faces, less the mouths, stay red; the tunnel's walls are the bar's, blue.
    assert_near(area_of("#ff0000"), 22.0);
    assert_near(area_of("#0000ff"), 8.0);
    let blue = model
        .parts
        .iter()
        .find(|p| p.color == Color::from_hex("#0000ff").unwrap());
    assert_eq!(blue.unwrap().material.as_deref(), Some("bool.B"));
    // A colour set afterwards paints every face.
    let repainted = run(
        &text.replace("Mass.", "color(\"#00ff00\") Mass."),
        lot(2.0, 2.0),
    );
    let model = repainted.to_model();
    let green = Color::from_hex("#00ff00").unwrap();
    assert!(model.parts.iter().all(|p| p.color == green));
}

#[test]
fn several_shapes_of_an_operand_are_unioned_first() {
    // Two bars through the box, each 1 × 1 × 3, crossing in a 1 × 1 × 1 cube.
    let text = "Lot --> extrude(2) subtract { [ s(1, 1, 3) t(0.5, 0.5, -0.5) primitiveCube() A. ] \
                [ s(3, 1, 1) t(-0.5, 0.5, 0.5) primitiveCube() B. ] }";
    let mesh = only_mesh(text, 2.0, 2.0);
    // Each bar takes 2 m³ of the box, and they share 1 m³.
    assert_near(mesh.signed_volume(), 8.0 - 3.0);
    assert!(mesh.is_watertight());
}

#[test]
fn inline_unify_append_and_recompose() {
    let split = "split(x) { 1 : A. | ~1 : B. }";
    let unify = only_mesh(
        &format!("Lot --> extrude(2) inline(unify) {split}"),
        2.0,
        2.0,
    );
    assert_near(unify.signed_volume(), 8.0);
    // The faces where the parts touched are gone.
    assert_near(unify.area(), 24.0);
    assert!(unify.is_watertight());
    let append = only_mesh(&format!("Lot --> extrude(2) inline {split}"), 2.0, 2.0);
    assert_eq!(append.face_count(), 12);
    assert_near(append.area(), 32.0);
    let recompose = only_mesh(
        &format!("Lot --> extrude(2) inline(recompose) {split}"),
        2.0,
        2.0,
    );
    assert_eq!(recompose.face_count(), 12);
    assert_eq!(recompose.vertex_count(), 12);
    // The shape goes on with the merged geometry: a later split cuts the whole.
    let d = run(
        &format!("Lot --> extrude(2) inline(unify) {split} split(y) {{ 1 : Low. | ~1 : High. }}"),
        lot(2.0, 2.0),
    );
    assert_eq!(names(&d), ["Low", "High"]);
    let low = d.leaves[0].world_mesh().unwrap();
    assert_near(low.signed_volume(), 4.0);
}

#[test]
fn deriving_twice_gives_the_same_bytes() {
    let text = "Lot --> extrude(2) subtract { r(scopeCenter, 0, rand(10, 40), 0) s(1, 3, 1) t(0.5, -0.5, 0.5) primitiveCylinder(24) } \
                union { t(rand(0.5, 1.5), 1, 0) primitiveSphere(8) }";
    let bytes = || {
        let d = run(text, lot(2.0, 2.0));
        let mesh = d.leaves[0].world_mesh().unwrap();
        let positions: Vec<u64> = mesh
            .positions()
            .iter()
            .flat_map(|p| p.to_array().map(f64::to_bits))
            .collect();
        let faces: Vec<Vec<u32>> = mesh.faces().map(<[u32]>::to_vec).collect();
        (positions, faces)
    };
    let first = bytes();
    assert!(!first.1.is_empty());
    assert_eq!(first, bytes());
}

/// Every bit of every leaf's world mesh.
fn leaf_bits(d: &Derivation) -> Vec<(Vec<u64>, Vec<Vec<u32>>)> {
    d.leaves
        .iter()
        .map(|leaf| {
            let mesh = leaf.world_mesh().unwrap();
            let positions = mesh
                .positions()
                .iter()
                .flat_map(|p| p.to_array().map(f64::to_bits))
                .collect();
            (positions, mesh.faces().map(<[u32]>::to_vec).collect())
        })
        .collect()
}

#[test]
fn lots_derived_on_several_threads_give_the_same_bytes() {
    let program = compile(
        "Lot --> extrude(rand(3, 9)) subtract { s('0.5, 20, '0.5) center(xz) t(0, -1, 0) primitiveCylinder(12) } \
         union { t('0.5, 0, '0.5) primitiveSphere(6) } A.",
    );
    let lots = lots_in_a_row(6, 4.0, 4.0, 6.0);
    let options = DeriveOptions::default();
    let one = derive_on_threads(&program, &lots, &options, 1);
    let many = derive_on_threads(&program, &lots, &options, 4);
    assert_eq!(one.leaves.len(), 6);
    assert_eq!(leaf_bits(&one), leaf_bits(&many));
}

#[test]
fn deriving_again_starts_afresh_as_an_operand_rule_may_have_changed() {
    let before =
        compile("Lot --> extrude(2) subtract Hole Mass.\nHole --> s(1, 3, 1) primitiveCube()");
    let after =
        compile("Lot --> extrude(2) subtract Hole Mass.\nHole --> s(1, 1, 1) primitiveCube()");
    let lots = [lot(2.0, 2.0)];
    let options = DeriveOptions {
        trace: true,
        ..DeriveOptions::default()
    };
    let previous = derive(&before, &lots, &options).unwrap();
    let again = derive_again(&previous, &after, &lots, &options).unwrap();
    assert!(again.fallback.unwrap().contains("union, subtract"));
    let fresh = derive(&after, &lots, &options).unwrap();
    assert_eq!(leaf_bits(&again.derivation), leaf_bits(&fresh));
    // A cube of 1 × 1 × 1 at the corner comes off.
    assert_near(
        again.derivation.leaves[0]
            .world_mesh()
            .unwrap()
            .signed_volume(),
        7.0,
    );
}

#[test]
fn an_operand_with_a_context_query_is_an_error_at_the_operation() {
    let text = "Lot --> extrude(2) subtract Probe Mass.\n\
                Probe --> case inside() : s(1, 1, 1) primitiveCube() else : NIL";
    let error = try_run(text, lot(2.0, 2.0), &DeriveOptions::default()).unwrap_err();
    assert!(
        error.message.contains("asks about other shapes"),
        "{error:?}"
    );
    assert_eq!(&text[error.span.unwrap().range()], "subtract Probe");
}

#[test]
fn bad_forms_are_errors_at_their_span() {
    let errors = compile_errors("Lot --> extrude(2) union { A. | B. | C. }");
    assert!(
        errors[0].contains("`union` takes one operand (`union { ops }`) or two"),
        "{errors:?}"
    );
    assert!(errors[0].contains("1:26"), "{errors:?}");
    let errors = compile_errors("Lot --> subtract(sideways) Hole\nHole --> X.");
    assert!(
        errors[0].contains("expected `swap` or `noSwap`"),
        "{errors:?}"
    );
    assert!(errors[0].contains("1:18"), "{errors:?}");
    let errors = compile_errors("Lot --> extrude(2) intersect");
    assert!(
        errors[0].contains("`intersect` needs what to derive"),
        "{errors:?}"
    );
    assert!(errors[0].contains("1:20"), "{errors:?}");
    let errors = compile_errors("Lot --> inline(unify) { A. | B. }");
    assert!(
        errors[0].contains("`inline` takes one operand"),
        "{errors:?}"
    );
    let errors = compile_errors("Lot --> inline(weld) A.");
    assert!(
        errors[0].contains("expected `append`, `unify` or `recompose`"),
        "{errors:?}"
    );
}
