//! `mirrorScope`, `setPivot` (new scope frames, the geometry staying where it is),
//! `resetGeometry` (back to the initial shape) and `primitiveDisk`.

use crate::common;

use common::{assert_close, compile_errors, lot, numeric_reports, of, run, try_run};
use shapegram_eval::DeriveOptions;
use shapegram_geom::{Aabb, DVec3};

/// The world bounds of each leaf of `text` derived on the 20 × 30 lot.
fn bounds(text: &str) -> Vec<Aabb> {
    run(text, lot(20.0, 30.0))
        .leaves
        .iter()
        .map(|l| l.world_mesh().unwrap().bounds().unwrap())
        .collect()
}

fn close(a: DVec3, b: DVec3) -> bool {
    a.abs_diff_eq(b, 1e-9)
}

#[test]
fn mirror_scope_turns_axes_round_and_leaves_the_geometry() {
    // The 20 × 5 × 30 mass, its scope x turned round: the origin at x = 20, so t(1, 0, 0)
    // moves the mass towards −x; without it the mass is where it was.
    let stays = bounds("Lot --> extrude(5) mirrorScope(true, false, false) X.");
    assert!(close(stays[0].min, DVec3::ZERO) && close(stays[0].max, DVec3::new(20.0, 5.0, 30.0)));
    let moved = bounds("Lot --> extrude(5) mirrorScope(true, false, true) t(1, 0, 1) X.");
    assert!(
        close(moved[0].min, DVec3::new(-1.0, 0.0, -1.0))
            && close(moved[0].max, DVec3::new(19.0, 5.0, 29.0)),
        "{:?}",
        moved[0]
    );
    let r = numeric_reports(
        "Lot --> extrude(5) mirrorScope(false, true, false) report(\"ty\", scope.ty) report(\"sy\", scope.sy) report(\"v\", geometry.volume) X.",
        lot(20.0, 30.0),
    );
    assert_close(&of(&r, "ty"), &[5.0]);
    assert_close(&of(&r, "sy"), &[5.0]);
    assert_close(&of(&r, "v"), &[3000.0]);
    let error = try_run(
        "Lot --> mirrorScope(1, false, false) X.",
        lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("mirrorScope takes true or false per axis, not 1"),
        "{error}"
    );
}

#[test]
fn set_pivot_moves_the_origin_to_a_corner_with_axes_pointing_in() {
    let report = |call: &str| {
        numeric_reports(
            &format!(
                "Lot --> extrude(5) {call} report(\"s\", scope.sx) report(\"s\", scope.sy) report(\"s\", scope.sz) report(\"v\", geometry.volume) t(1, 2, 3) X."
            ),
            lot(20.0, 30.0),
        )
    };
    // Corner 0 with xyz changes nothing; yzx puts y along the old x (20), x along z (30).
    assert_close(&of(&report("setPivot(xyz, 0)"), "s"), &[20.0, 5.0, 30.0]);
    assert_close(&of(&report("setPivot(yzx, 0)"), "s"), &[30.0, 20.0, 5.0]);
    assert_close(&of(&report("setPivot(zxy, 0)"), "s"), &[5.0, 30.0, 20.0]);
    // Corner 1 (x = 20, y = 0, z = 0): y stays up, x runs along z and z back along −x (a
    // 1 × 1 × 2 box from there is 2 long in −x).
    let at = |call: &str| bounds(&format!("Lot --> extrude(5) {call} s(1, 1, 2) X."))[0];
    let one = at("setPivot(xyz, 1)");
    assert!(
        close(one.min, DVec3::new(18.0, 0.0, 0.0)) && close(one.max, DVec3::new(20.0, 1.0, 1.0)),
        "{one:?}"
    );
    // Corner 6 (the far top corner): every axis points back in, x along −z, z along −x.
    let six = at("setPivot(xyz, 6)");
    assert!(
        close(six.min, DVec3::new(18.0, 4.0, 29.0)) && close(six.max, DVec3::new(20.0, 5.0, 30.0)),
        "{six:?}"
    );
    // The geometry stays: the same volume, the same place.
    let r = report("setPivot(zxy, 5)");
    assert_close(&of(&r, "v"), &[3000.0]);
    let whole = bounds("Lot --> extrude(5) setPivot(yzx, 7) X.");
    assert!(close(whole[0].min, DVec3::ZERO) && close(whole[0].max, DVec3::new(20.0, 5.0, 30.0)));
    for (call, message) in [
        (
            "setPivot(xyz, 8)",
            "setPivot's corner is a whole number from 0 to 7, not 8",
        ),
        ("setPivot(xyz, 1.5)", "not 1.5"),
    ] {
        let error = try_run(
            &format!("Lot --> {call} X."),
            lot(20.0, 30.0),
            &DeriveOptions::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(error.contains(message), "{call}: {error}");
    }
    let errors = compile_errors("Lot --> setPivot(xzy, 0) X.").join("\n");
    assert!(errors.contains("`xyz`, `yzx` or `zxy`"), "{errors}");
}

#[test]
fn reset_geometry_goes_back_to_the_lot() {
    // Set back twice, each from the whole lot: 1 m leaves 18 × 28, 2 m leaves 16 × 26.
    let r = numeric_reports(
        "Lot --> A(1) A(2)\nA(d) --> [ extrude(3) t(0, 1, 0) color(\"#ff0000\") resetGeometry() setback(d) { all : NIL | remainder : report(\"area\", geometry.area) report(\"ty\", scope.ty) R. } ]",
        lot(20.0, 30.0),
    );
    assert_close(&of(&r, "area"), &[18.0 * 28.0, 16.0 * 26.0]);
    assert_close(&of(&r, "ty"), &[0.0, 0.0]);
}

#[test]
fn primitive_disk_fills_the_flat_face_or_takes_a_radius() {
    let r = |call: &str| {
        numeric_reports(
            &format!(
                "Lot --> {call} report(\"area\", geometry.area) report(\"n\", geometry.nVertices) report(\"sx\", scope.sx) report(\"sz\", scope.sz) X."
            ),
            lot(20.0, 30.0),
        )
    };
    // 16 corners on the ellipse in the 20 × 30 lot: the area of the inscribed 16-gon,
    // 16/2 · sin(2π/16) · 10 · 15.
    let area = 8.0 * (std::f64::consts::TAU / 16.0).sin() * 10.0 * 15.0;
    let whole = r("primitiveDisk()");
    assert_close(&of(&whole, "area"), &[area]);
    assert_close(&of(&whole, "n"), &[16.0]);
    let square = r("primitiveDisk(4)");
    assert_close(&of(&square, "area"), &[300.0]);
    // A radius: centred on the lot, 2r across.
    let sized = r("primitiveDisk(6, 2)");
    assert_close(&of(&sized, "area"), &[3.0 * 3f64.sqrt() / 2.0 * 4.0]);
    assert_close(&of(&sized, "sx"), &[4.0]);
    assert_close(&of(&sized, "sz"), &[4.0]);
    let centre = bounds("Lot --> primitiveDisk(4, 2) X.")[0];
    assert!(
        close(centre.min, DVec3::new(8.0, 0.0, 13.0))
            && close(centre.max, DVec3::new(12.0, 0.0, 17.0)),
        "{centre:?}"
    );
    let error = try_run(
        "Lot --> primitiveDisk(2) X.",
        lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("2 subdivisions: expected 3 to 100000"),
        "{error}"
    );
}
