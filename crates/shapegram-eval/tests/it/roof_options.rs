//! Roofs by height, with separate overhangs at eaves and gable ends, and with the ridge along a
//! chosen edge: scope sizes and volumes.

use crate::common;

use common::{compile_errors, lot, try_run};
use shapegram_eval::DeriveOptions;
use shapegram_geom::DVec3;

/// The roof leaf's scope size and volume for `roof` on a `w` × `d` lot.
fn roof(roof: &str, w: f64, d: f64) -> (DVec3, f64) {
    let derivation = try_run(
        &format!("Lot --> {roof} Roof."),
        lot(w, d),
        &DeriveOptions::default(),
    )
    .unwrap();
    let leaf = &derivation.leaves[0];
    let volume = leaf.world_mesh().unwrap().signed_volume();
    (leaf.scope.size, volume)
}

fn close(a: DVec3, b: DVec3) -> bool {
    a.abs_diff_eq(b, 1e-9)
}

#[test]
fn roofs_by_height_reach_that_height() {
    // Hip and gable over 10 × 4 m rise over 2 m; a shed over the 4 m depth; a pyramid over 3 m.
    let (size, volume) = roof("roofHip(byHeight, 3)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 3.0, 4.0)), "{size}");
    // Two end pyramids (4 × 2 × 3 / 3 each... a 4 × 4 base in all) and a 6 m prism between.
    assert!((volume - (0.5 * 4.0 * 3.0 * 6.0 + 4.0 * 4.0 * 3.0 / 3.0)).abs() < 1e-9);
    let (size, volume) = roof("roofGable(byHeight, 3)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 3.0, 4.0)), "{size}");
    assert!((volume - 0.5 * 4.0 * 3.0 * 10.0).abs() < 1e-9);
    let (size, volume) = roof("roofShed(byHeight, 2)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 2.0, 4.0)), "{size}");
    assert!((volume - 0.5 * 4.0 * 2.0 * 10.0).abs() < 1e-9);
    let (size, _) = roof("roofPyramid(byHeight, 3)", 6.0, 6.0);
    assert!(close(size, DVec3::new(6.0, 3.0, 6.0)), "{size}");
    // byAngle is the default.
    assert_eq!(
        roof("roofHip(byAngle, 45)", 10.0, 4.0),
        roof("roofHip(45)", 10.0, 4.0)
    );
}

#[test]
fn a_gable_ridge_follows_the_edge_it_is_given() {
    // Along the 4 m edge (index 1) the ridge runs across the lot: 10 m wide, 5 m high at 45°.
    let (size, _) = roof("roofGable(45, 0, 0, false, 1)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 5.0, 4.0)), "{size}");
    let (size, _) = roof("roofGable(45, 0, 0, false, 0)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 2.0, 4.0)), "{size}");
    // Negative indices count from the end: -1 is edge 3, across again.
    let (size, _) = roof("roofGable(45, 0, 0, false, -1)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 5.0, 4.0)), "{size}");
    // A shed from edge 1 rises across the 10 m.
    let (size, _) = roof("roofShed(byHeight, 5, 1)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 5.0, 4.0)), "{size}");
}

#[test]
fn gable_overhangs_differ_at_eaves_and_ends() {
    // Eaves 1 m out (and 1 m below the lot at 45°), gable ends 2 m out: 14 × 6 m, from -1 to 2.
    let (size, _) = roof("roofGable(45, 1, 2)", 10.0, 4.0);
    assert!(close(size, DVec3::new(14.0, 3.0, 6.0)), "{size}");
    // overhangY is overhangX unless given; negative shortens the roof.
    let (size, _) = roof("roofGable(45, 1)", 10.0, 4.0);
    assert!(close(size, DVec3::new(12.0, 3.0, 6.0)), "{size}");
    let (size, _) = roof("roofGable(45, 1, 0)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 3.0, 6.0)), "{size}");
    let (size, volume) = roof("roofGable(45, 0, -1)", 10.0, 4.0);
    assert!(close(size, DVec3::new(8.0, 2.0, 4.0)), "{size}");
    assert!((volume - 0.5 * 4.0 * 2.0 * 8.0).abs() < 1e-9);
}

#[test]
fn bad_roof_options_are_errors() {
    for (grammar, message) in [
        (
            "Lot --> roofHip(byHeight, 0) R.",
            "cannot build this roof 0 high",
        ),
        (
            "Lot --> roofGable(30, 0, 0, false, 1.5) R.",
            "a roof's edge index must be a whole number, not 1.5",
        ),
        ("Lot --> roofGable(45, 0, -5) R.", "cannot build this roof"),
    ] {
        let error = try_run(grammar, lot(10.0, 4.0), &DeriveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains(message), "{grammar}: {error}");
    }
    let errors = compile_errors("Lot --> roofHip(30, 1, false, 2) R.").join("\n");
    assert!(
        errors.contains(
            "the signature is `roofHip([byAngle | byHeight,] value [, overhang [, even]])`"
        ),
        "{errors}"
    );
}

#[test]
fn a_ridge_roof_runs_along_the_scopes_x_axis() {
    // Over a rectangle it is the gable along x: 2 m high at 45° over the 4 m depth.
    let (size, volume) = roof("roofRidge(byAngle, 45)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 2.0, 4.0)), "{size}");
    assert!((volume - 40.0).abs() < 1e-9);
    let (size, _) = roof("roofRidge(byHeight, 3)", 10.0, 4.0);
    assert!(close(size, DVec3::new(10.0, 3.0, 4.0)), "{size}");
    // Turned a quarter, the ridge runs across: 5 m high.
    let (_, volume) = roof("rotateScope(0, 90, 0) roofRidge(45)", 10.0, 4.0);
    assert!((volume - 0.5 * 10.0 * 5.0 * 4.0).abs() < 1e-9, "{volume}");
    // Over an L (10 m wide over 30 m, and a 10 × 10 m arm), the planes rise from z = 0 and
    // z = 30 to a 15 m ridge; the arm ends in an upright wall 10 m high.
    let derivation = try_run(
        "Lot --> roofRidge(45) Roof.",
        shapegram_eval::InitialShape::from_xz(&[
            shapegram_geom::DVec2::new(0.0, 0.0),
            shapegram_geom::DVec2::new(20.0, 0.0),
            shapegram_geom::DVec2::new(20.0, 10.0),
            shapegram_geom::DVec2::new(10.0, 10.0),
            shapegram_geom::DVec2::new(10.0, 30.0),
            shapegram_geom::DVec2::new(0.0, 30.0),
        ])
        .unwrap(),
        &DeriveOptions::default(),
    )
    .unwrap();
    let mesh = derivation.leaves[0].world_mesh().unwrap();
    assert!(mesh.is_watertight());
    assert!((mesh.signed_volume() - (2250.0 + 500.0)).abs() < 1e-9);
    assert!((mesh.bounds().unwrap().max.y - 15.0).abs() < 1e-9);
}
