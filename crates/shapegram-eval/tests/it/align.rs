//! `alignScopeToGeometry` and `alignScopeToGeometryBBox`: scopes turned to the geometry.

use crate::common;

use common::{assert_close, compile, compile_errors};
use shapegram_eval::{DeriveOptions, InitialShape, Value, derive};
use shapegram_geom::DVec2;

/// A lot whose corners are `points` turned by `degrees` about the origin (in the xz-plane).
fn turned_lot(points: &[(f64, f64)], degrees: f64) -> InitialShape {
    let (s, c) = degrees.to_radians().sin_cos();
    let corners: Vec<DVec2> = points
        .iter()
        .map(|&(x, z)| DVec2::new(c * x - s * z, s * x + c * z))
        .collect();
    InitialShape::from_xz(&corners).unwrap()
}

/// The numbers `text` reports, in order, derived on `lot`.
fn reports(text: &str, lot: InitialShape) -> Vec<f64> {
    let d = derive(&compile(text), &[lot], &DeriveOptions::default()).unwrap();
    d.reports
        .iter()
        .map(|(_, v)| match v {
            Value::Number(n) => *n,
            v => panic!("{v:?}"),
        })
        .collect()
}

const SIZE: &str = "report(\"sx\", scope.sx) report(\"sy\", scope.sy) report(\"sz\", scope.sz)";

#[test]
fn a_lot_aligns_to_its_longest_edge() {
    // A 4 × 10 lot given short side first, turned by 30°: the initial scope's x runs along the
    // short side; aligned to the longest edge it runs along the long one.
    let lot = turned_lot(&[(0.0, 0.0), (4.0, 0.0), (4.0, 10.0), (0.0, 10.0)], 30.0);
    let before = reports(&format!("Lot --> {SIZE}"), lot.clone());
    assert_close(&before, &[4.0, 0.0, 10.0]);
    let after = reports(
        &format!("Lot --> alignScopeToGeometry(yUp, 0, longest) {SIZE}"),
        lot.clone(),
    );
    assert_close(&after, &[10.0, 0.0, 4.0]);
    // Edge 1 is the same long edge, chosen by index.
    let by_index = reports(
        &format!("Lot --> alignScopeToGeometry(yUp, 0, 1) {SIZE}"),
        lot.clone(),
    );
    assert_close(&by_index, &[10.0, 0.0, 4.0]);
    // With z up the lot's normal becomes z: the scope is flat in z instead.
    let z_up = reports(
        &format!("Lot --> alignScopeToGeometry(zUp, 0, -1) {SIZE}"),
        lot,
    );
    assert_close(&z_up, &[10.0, 4.0, 0.0]);
}

#[test]
fn faces_are_picked_by_selector() {
    // A 2 × 3 × 4 box: its largest face is a 3 × 4 side, its lowest the bottom.
    let text = |face: &str, edge: &str| {
        format!(
            "Lot --> extrude(3) alignScopeToGeometry(yUp, {face}, {edge}) {SIZE} \
             report(\"up\", scope.ry)"
        )
    };
    let lot = turned_lot(&[(0.0, 0.0), (2.0, 0.0), (2.0, 4.0), (0.0, 4.0)], 0.0);
    let largest = reports(&text("largest", "longest"), lot.clone());
    // x along the 4 m edge, y out of the face (the box is 2 deep that way), z the 3 m height.
    assert_close(&largest[..3], &[4.0, 2.0, 3.0]);
    let lowest = reports(&text("world.lowest", "longest"), lot.clone());
    // The bottom faces down: y points down, and the box reaches 3 m the other way.
    assert_close(&lowest[..3], &[4.0, 3.0, 2.0]);
    // On the slopes of a gable roof (ridge along the 4 m side), the lowest edge is the eave:
    // x runs along it, y up the slope (1 m / cos 45°), z out of the roof.
    let slopes = reports(
        &format!(
            "Lot --> roofGable(45) comp(f) {{ aslant : alignScopeToGeometry(zUp, any, world.lowest) {SIZE} }}"
        ),
        lot,
    );
    let slope = 2f64.sqrt();
    assert_close(&slopes, &[4.0, slope, 0.0, 4.0, slope, 0.0]);
}

#[test]
fn bbox_alignment_finds_the_tightest_rectangle() {
    // A 6 × 3 rectangle with one corner cut off at 45°, turned by 25°: its tightest rectangle
    // is the 6 × 3 one, where the initial scope lies too.
    let shape = [(0.0, 1.0), (1.0, 0.0), (6.0, 0.0), (6.0, 3.0), (0.0, 3.0)];
    let lot = turned_lot(&shape, 25.0);
    let initial = reports(&format!("Lot --> {SIZE}"), lot.clone());
    assert_close(&initial, &[6.0, 0.0, 3.0]);
    // Turned away from the geometry, the scope grows; aligned again, it is the tight one.
    let turned = reports(
        &format!("Lot --> rotateScope(0, 20, 0) {SIZE}"),
        lot.clone(),
    );
    assert!(turned[0] * turned[2] > 18.0 + 1.0, "{turned:?}");
    let sizes = reports(
        &format!("Lot --> rotateScope(0, 20, 0) alignScopeToGeometryBBox(xz) {SIZE}"),
        lot.clone(),
    );
    assert_close(&sizes, &[6.0, 0.0, 3.0]);
    // `zx` puts the longer side along z.
    let sizes = reports(&format!("Lot --> alignScopeToGeometryBBox(zx) {SIZE}"), lot);
    assert_close(&sizes, &[3.0, 0.0, 6.0]);
}

#[test]
fn geometry_keeps_its_place_in_world_space() {
    let lot = turned_lot(&[(0.0, 0.0), (4.0, 0.0), (4.0, 10.0), (0.0, 10.0)], 30.0);
    let program = compile("Lot --> extrude(2) alignScopeToGeometry(yUp, largest, longest) X.");
    let plain = compile("Lot --> extrude(2) X.");
    let world = |p| {
        let d = derive(&p, std::slice::from_ref(&lot), &DeriveOptions::default()).unwrap();
        d.to_model().bounds().unwrap()
    };
    let (a, b) = (world(program), world(plain));
    assert!((a.min - b.min).abs().max_element() < 1e-9, "{a:?} {b:?}");
    assert!((a.max - b.max).abs().max_element() < 1e-9, "{a:?} {b:?}");
}

#[test]
fn bad_selectors_are_errors() {
    let all = |text: &str| compile_errors(text).join("\n");
    let e = all("Lot --> alignScopeToGeometry(xUp, 0, 0) X");
    assert!(
        e.contains("expected `yUp` or `zUp` (`xUp` is not supported)"),
        "{e}"
    );
    let e = all("Lot --> alignScopeToGeometry(yUp, any, 0) X");
    assert!(e.contains("`any` needs an edge selector"), "{e}");
    let e = all("Lot --> alignScopeToGeometry(yUp, 0, shortest) X");
    assert!(
        e.contains("expected an edge index, `world.lowest` or `longest`"),
        "{e}"
    );
    let e = all("Lot --> alignScopeToGeometryBBox(xx) X");
    assert!(e.contains("expected two axes"), "{e}");
    let e = all("Lot --> alignScopeToGeometry(yUp) X");
    assert!(e.contains("the signature is `alignScopeToGeometry("), "{e}");
    let err = derive(
        &compile("Lot --> alignScopeToGeometry(yUp, 0.5, 0) X"),
        &[turned_lot(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)], 0.0)],
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(err.message, "index 0.5: expected a whole number");
}

#[test]
fn aligning_one_axis_keeps_the_x_axis_as_cityengine_does() {
    // The front wall (20 × 10) of a 20 × 30 lot turned by 30°, thickened by 0.1: the slab's
    // scope has x along the wall, y out of it, z down the wall. Aligning y to the world's keeps
    // x (projected off y) and turns z out of the wall: the slab's own box, 20 × 10 × 0.1 (keeping
    // z instead, which runs down the wall, would leave nothing to keep and turn the box to the
    // world's axes).
    let lot = turned_lot(&[(0.0, 0.0), (20.0, 0.0), (20.0, 30.0), (0.0, 30.0)], 30.0);
    let slab = reports(
        &format!(
            "Lot --> extrude(10) comp(f) {{ front : W }}\n\
             W --> extrude(0.1) alignScopeToAxes(y) {SIZE}"
        ),
        lot,
    );
    assert_close(&slab, &[20.0, 10.0, 0.1]);
}

#[test]
fn strips_of_a_wall_keep_its_first_edge() {
    // A wall aligned to the world's y axis (its geometry a mesh now) and split into 2 m strips:
    // each strip's first edge runs along its foot, so its face scope is 20 wide and 2 high,
    // as the wall's was 20 × 10.
    let lot = turned_lot(&[(0.0, 0.0), (20.0, 0.0), (20.0, 30.0), (0.0, 30.0)], 30.0);
    let strips = reports(
        "Lot --> extrude(10) comp(f) { front : W }\n\
         W --> alignScopeToAxes(y) split(y) { ~2 : T }*\n\
         T --> comp(f) { all : F }\n\
         F --> report(\"sx\", scope.sx) report(\"sy\", scope.sy)",
        lot,
    );
    assert_close(&strips, &[20.0, 2.0].repeat(5));
}
