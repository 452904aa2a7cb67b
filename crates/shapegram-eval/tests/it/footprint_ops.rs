//! Footprint operations on lots of other shapes than rectangles: `convexify`, `innerRectangle`
//! and the rest, with exact areas, corners and counts.

use crate::common;

use common::{assert_close, compile_errors, numeric_reports as reports, of, try_run};
use shapegram_eval::{DeriveOptions, InitialShape};
use shapegram_geom::DVec2;

/// An L-shaped lot: 20 × 10 m along x, and a 10 × 20 m wing along z from its left half; one
/// reflex corner, at (10, 10).
fn l_lot() -> InitialShape {
    InitialShape::from_xz(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(20.0, 0.0),
        DVec2::new(20.0, 10.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(10.0, 30.0),
        DVec2::new(0.0, 30.0),
    ])
    .unwrap()
}

#[test]
fn convexify_cuts_an_l_into_two_convex_faces() {
    let r = reports(
        "Lot --> convexify report(\"faces\", geometry.nFaces) comp(f) { all : report(\"area\", geometry.area) report(\"corners\", geometry.nVertices) report(\"concave\", geometry.isConcave()) P. }",
        l_lot(),
    );
    // The cut runs from the reflex corner (10, 10) to (0, 0): a 10 m-high trapezoid under it
    // (20 and 10 m wide), and one of 10 m across (30 and 20 m long) beside it.
    assert_close(&of(&r, "faces"), &[2.0]);
    assert_close(&of(&r, "area"), &[250.0, 150.0]);
    assert_close(&of(&r, "corners"), &[4.0, 4.0]);
    assert_close(&of(&r, "concave"), &[0.0, 0.0]);
    // Cuts of √200 m are longer than 14 m: the L stays whole; up to 15 m it is cut.
    let faces = |grammar: &str| of(&reports(grammar, l_lot()), "faces");
    assert_close(
        &faces("Lot --> convexify(14) report(\"faces\", geometry.nFaces) X."),
        &[1.0],
    );
    assert_close(
        &faces("Lot --> convexify(15) report(\"faces\", geometry.nFaces) X."),
        &[2.0],
    );
    // A convex lot, and a mass whose faces are all convex, stay as they are.
    assert_close(
        &of(
            &reports(
                "Lot --> convexify extrude(3) convexify report(\"faces\", geometry.nFaces) X.",
                common::lot(20.0, 30.0),
            ),
            "faces",
        ),
        &[6.0],
    );
    let error = try_run(
        "Lot --> convexify(0) X.",
        l_lot(),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("convexify's longest cut must be more than 0, not 0"),
        "{error}"
    );
    let errors = compile_errors("Lot --> convexify(1, 2) X.").join("\n");
    assert!(
        errors.contains("the signature is `convexify([maxCutLength])`"),
        "{errors}"
    );
}

const AREA: &str = "report(\"area\", geometry.area)";

#[test]
fn inner_rectangle_takes_the_largest_rectangle_and_leaves_the_rest() {
    // In the L, the 10 × 30 m wing with the corner under it; the rest is the 10 × 10 m arm.
    let r = reports(
        &format!(
            "Lot --> innerRectangle(scope) {{ shape : report(\"sx\", scope.sx) report(\"sz\", scope.sz) {AREA} S. | remainder : report(\"rest\", geometry.area) R. }}"
        ),
        l_lot(),
    );
    assert_close(&of(&r, "area"), &[300.0]);
    assert_close(&of(&r, "sx"), &[10.0]);
    assert_close(&of(&r, "sz"), &[30.0]);
    assert_close(&of(&r, "rest"), &[100.0]);
    // A square lot turned 45°: along the world's axes the largest rectangle is half of it,
    // along an edge the lot itself.
    let diamond = || {
        InitialShape::from_xz(&[
            DVec2::new(10.0, 0.0),
            DVec2::new(20.0, 10.0),
            DVec2::new(10.0, 20.0),
            DVec2::new(0.0, 10.0),
        ])
        .unwrap()
    };
    let area = |how: &str| {
        of(
            &reports(
                &format!(
                    "Lot --> alignScopeToAxes() innerRectangle({how}) {{ shape : {AREA} S. | remainder = report(\"rest\", geometry.area) R. }}"
                ),
                diamond(),
            ),
            "area",
        )
    };
    assert_close(&area("scope"), &[100.0]);
    assert_close(&area("edge"), &[200.0]);
    // innerRect: the rectangle replaces the face.
    let r = reports(&format!("Lot --> innerRect {AREA} X."), l_lot());
    assert_close(&of(&r, "area"), &[300.0]);
    let errors = compile_errors("Lot --> innerRectangle(largest) { shape : X. }").join("\n");
    assert!(errors.contains("expected `scope` or `edge`"), "{errors}");
    let errors = compile_errors("Lot --> innerRectangle(scope) X.").join("\n");
    assert!(
        errors.contains("`innerRectangle` needs a `{ shape : … | remainder : … }` block"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> innerRectangle(edge) { front : X. }").join("\n");
    assert!(
        errors.contains("`innerRectangle` selects `shape` or `remainder`"),
        "{errors}"
    );
    let error = try_run(
        "Lot --> extrude(3) innerRect X.",
        l_lot(),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("innerRect needs a flat shape"), "{error}");
}

/// The volume and scope size of the one leaf `rule` makes on a `w` × `d` lot.
fn solid(rule: &str, w: f64, d: f64) -> (f64, shapegram_geom::DVec3) {
    let derivation = try_run(rule, common::lot(w, d), &DeriveOptions::default()).unwrap();
    let leaf = &derivation.leaves[0];
    let mesh = leaf.world_mesh().unwrap();
    assert!(mesh.is_watertight(), "{rule}");
    (mesh.signed_volume(), leaf.scope.size)
}

#[test]
fn envelope_cuts_the_volume_under_planes_from_the_edges() {
    use shapegram_geom::DVec3;
    // Only the front edge slopes, at 45° above a 2 m wall: a wedge 8 × 8 / 2 m² along 20 m goes.
    let (volume, size) = solid("Lot --> envelope(world.up, 10, 2, 45) E.", 20.0, 30.0);
    assert!((volume - (6000.0 - 32.0 * 20.0)).abs() < 1e-9, "{volume}");
    assert!(
        size.abs_diff_eq(DVec3::new(20.0, 10.0, 30.0), 1e-9),
        "{size}"
    );
    // The same from arrays in face-edge order.
    let (volume, _) = solid("Lot --> envelope(normal, 10, [2], [45]) E.", 20.0, 30.0);
    assert!((volume - 5360.0).abs() < 1e-9, "{volume}");
    // The Candler's ventilation box: every edge chamfered at 45° above 0.45 m, up to 0.6 m.
    let (volume, size) = solid(
        "Lot --> envelope(world.up, 0.6, 0.45, 45, 0.45, 45, 0.45, 45) E.",
        2.0,
        3.0,
    );
    let chamfered = 6.0 * 0.15 - 5.0 * 0.15 * 0.15 + 4.0 / 3.0 * 0.15f64.powi(3);
    assert!(
        (volume - (2.0 * 3.0 * 0.45 + chamfered)).abs() < 1e-9,
        "{volume}"
    );
    assert!(size.abs_diff_eq(DVec3::new(2.0, 0.6, 3.0), 1e-9), "{size}");
    // Right and left apart: only the right edge slopes, from the ground at 45°.
    let (volume, _) = solid(
        "Lot --> envelope(world.up, 10, 0, 90, 0, 90, 0, 45, 0, 90) E.",
        20.0,
        30.0,
    );
    assert!((volume - (6000.0 - 50.0 * 30.0)).abs() < 1e-9, "{volume}");
    let errors = compile_errors("Lot --> envelope(up, 10, 2, 45) E.").join("\n");
    assert!(
        errors.contains("expected `normal` or `world.up`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> envelope(world.up, 10, 2) E.").join("\n");
    assert!(
        errors.contains("wrong number of arguments for `envelope`"),
        "{errors}"
    );
    let error = try_run(
        "Lot --> envelope(world.up, -1, 2, 45) E.",
        common::lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("cannot build this envelope"), "{error}");
}

#[test]
fn cleanup_geometry_merges_vertices_and_drops_corners_and_faces() {
    let lot = |points: &[(f64, f64)]| {
        InitialShape::from_xz(
            &points
                .iter()
                .map(|&(x, z)| DVec2::new(x, z))
                .collect::<Vec<_>>(),
        )
        .unwrap()
    };
    let corners = |grammar: &str, points: &[(f64, f64)]| of(&reports(grammar, lot(points)), "n");
    // A corner on the straight front edge goes at tolerance 0; one bent by 5° only at 1 (10°).
    let straight = [
        (0.0, 0.0),
        (10.0, 0.0),
        (20.0, 0.0),
        (20.0, 30.0),
        (0.0, 30.0),
    ];
    let rule = |what: &str, t: f64| {
        format!("Lot --> cleanupGeometry({what}, {t}) report(\"n\", geometry.nVertices) X.")
    };
    assert_close(&corners(&rule("vertices", 0.0), &straight), &[4.0]);
    let bent = [
        (0.0, 0.0),
        (10.0, -10.0 * 5f64.to_radians().tan() / 2.0),
        (20.0, 0.0),
        (20.0, 30.0),
        (0.0, 30.0),
    ];
    assert_close(&corners(&rule("vertices", 0.0), &bent), &[5.0]);
    assert_close(&corners(&rule("all", 1.0), &bent), &[4.0]);
    // Corners 0.71 m apart merge at tolerance 1 (1 m), not at 0.5.
    let chamfered = [
        (0.0, 0.0),
        (20.0, 0.0),
        (20.0, 30.0),
        (0.5, 30.0),
        (0.0, 29.5),
    ];
    assert_close(&corners(&rule("vertices", 0.5), &chamfered), &[5.0]);
    assert_close(&corners(&rule("vertices", 1.0), &chamfered), &[4.0]);
    // A 4 cm slab of the L: at tolerance 1, side faces under 1 m² go (all but the 30 m side).
    let r = reports(
        "Lot --> extrude(0.04) cleanupGeometry(faces, 1) report(\"n\", geometry.nFaces) X.",
        l_lot(),
    );
    assert_close(&of(&r, "n"), &[3.0]);
    let r = reports(
        "Lot --> extrude(0.04) cleanupGeometry(faces, 0) report(\"n\", geometry.nFaces) X.",
        l_lot(),
    );
    assert_close(&of(&r, "n"), &[8.0]);
    let error = try_run(
        "Lot --> cleanupGeometry(all, 2) X.",
        l_lot(),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("cleanupGeometry's tolerance must be between 0 and 1, not 2"),
        "{error}"
    );
    let errors = compile_errors("Lot --> cleanupGeometry(corners, 0) X.").join("\n");
    assert!(
        errors.contains("expected `vertices`, `edges`, `faces` or `all`"),
        "{errors}"
    );
    assert_eq!(
        compile_errors("Lot --> cleanupGeometry(edges, 0) X."),
        Vec::<String>::new()
    );
}

#[test]
fn cleanup_of_edges_merges_coplanar_faces_into_one_polygon() {
    let faces = |grammar: &str| {
        let r = reports(grammar, l_lot());
        (of(&r, "faces"), of(&r, "corners"), of(&r, "area"))
    };
    let count = "report(\"faces\", geometry.nFaces) report(\"corners\", geometry.nVertices) report(\"area\", geometry.area)";
    // The L cut into convex pieces, and merged back: one face with the L's six corners.
    let (n, corners, area) = faces(&format!("Lot --> convexify {count} X."));
    assert_close(&n, &[2.0]);
    assert_eq!((corners.clone(), area.clone()), (vec![6.0], vec![400.0]));
    let (n, corners, area) = faces(&format!(
        "Lot --> convexify cleanupGeometry(edges, 0) {count} X."
    ));
    assert_close(&n, &[1.0]);
    assert_close(&corners, &[6.0]);
    assert_close(&area, &[400.0]);
    // Faces keep their tags, and faces of different tags never merge: the L's inset by 2,
    // cut in two by convexify, is one `inside` face again; the border stays its six strips.
    let r = reports(
        "Lot --> offset(-2) convexify cleanupGeometry(edges, 0) comp(f) { inside : report(\"in\", geometry.area) X. | border : report(\"border\", geometry.area) Y. }",
        l_lot(),
    );
    assert_close(&of(&r, "in"), &[16.0 * 6.0 + 6.0 * 20.0]);
    assert_eq!(of(&r, "border").len(), 6);
    assert!((of(&r, "border").iter().sum::<f64>() - 184.0).abs() < 1e-9);
    // A hip roof 3° steep over the L: six sloped faces (and its bottom), whose normals turn by
    // 4.2° between neighbours and 6° between opposite faces. At tolerance 0.3 (3°) none merge;
    // at 1 (10°) all six become one polygon round the L's six corners, the ridge's three
    // corners gone with the edges between them.
    let roof = |t: f64| {
        faces(&format!(
            "Lot --> roofHip(3) cleanupGeometry(edges, {t}) {count} X."
        ))
    };
    for t in [0.0, 0.3] {
        let (n, corners, _) = roof(t);
        assert_close(&n, &[7.0]);
        assert_close(&corners, &[9.0]);
    }
    let (n, corners, _) = roof(1.0);
    assert_close(&n, &[2.0]);
    assert_close(&corners, &[6.0]);
}

#[test]
fn footprint_projects_the_geometry_onto_the_ground() {
    // A mass of the L: its bottom, 400 m², flat, facing up; extruded again to 5 m.
    let r = reports(
        "Lot --> extrude(10) footprint() report(\"area\", geometry.area) report(\"sy\", scope.sy) report(\"faces\", geometry.nFaces) extrude(5) report(\"volume\", geometry.volume) X.",
        l_lot(),
    );
    assert_close(&of(&r, "area"), &[400.0]);
    assert_close(&of(&r, "sy"), &[0.0]);
    assert_close(&of(&r, "faces"), &[1.0]);
    assert_close(&of(&r, "volume"), &[2000.0]);
    // Under a hip roof with eaves, the eaves' outline: the 20 × 30 m lot grown by 1 m.
    let r = reports(
        "Lot --> roofHip(30, 1) footprint() report(\"area\", geometry.area) X.",
        common::lot(20.0, 30.0),
    );
    assert_close(&of(&r, "area"), &[22.0 * 32.0]);
    // A lot is its own footprint; deleteHoles has nothing to delete.
    let r = reports(
        "Lot --> footprint() deleteHoles() report(\"area\", geometry.area) X.",
        l_lot(),
    );
    assert_close(&of(&r, "area"), &[400.0]);
    let errors = compile_errors("Lot --> footprint(1) X.").join("\n");
    assert!(
        errors.contains("the signature is `footprint()`"),
        "{errors}"
    );
}

#[test]
fn translate_and_rotate_work_in_their_frames() {
    use shapegram_geom::{DMat3, DVec3};
    let scope = |rule: &str| {
        let d = try_run(rule, common::lot(20.0, 30.0), &DeriveOptions::default()).unwrap();
        d.leaves[0].scope
    };
    let close = |a: DVec3, b: DVec3| a.abs_diff_eq(b, 1e-9);
    // The lot's scope starts at the world origin with the world's axes.
    let s = scope("Lot --> translate(rel, world, 5, 0, 0) X.");
    assert!(close(s.origin, DVec3::new(5.0, 0.0, 0.0)), "{:?}", s.origin);
    // Turned a quarter about y, the scope's x is the world's -z.
    let s = scope("Lot --> r(0, 90, 0) translate(rel, scope, 5, 0, 0) X.");
    assert!(
        close(s.origin, DVec3::new(0.0, 0.0, -5.0)),
        "{:?}",
        s.origin
    );
    let s = scope("Lot --> r(0, 90, 0) translate(rel, pivot, 5, 0, 0) X.");
    assert!(
        close(s.origin, DVec3::new(0.0, 0.0, -5.0)),
        "{:?}",
        s.origin
    );
    let s = scope("Lot --> r(0, 90, 0) translate(rel, world, 5, 0, 0) X.");
    assert!(close(s.origin, DVec3::new(5.0, 0.0, 0.0)), "{:?}", s.origin);
    let s = scope("Lot --> t(3, 4, 5) translate(abs, world, 1, 2, 3) X.");
    assert!(close(s.origin, DVec3::new(1.0, 2.0, 3.0)), "{:?}", s.origin);
    let s = scope("Lot --> r(0, 90, 0) t(3, 4, 5) translate(abs, object, 0, 0, 0) X.");
    assert!(close(s.origin, DVec3::ZERO), "{:?}", s.origin);
    // rotate turns about the scope's origin: to world angles, or by them.
    let s = scope("Lot --> r(30, 40, 50) rotate(abs, world, 0, 0, 0) X.");
    assert!(s.axes.abs_diff_eq(DMat3::IDENTITY, 1e-12), "{:?}", s.axes);
    let s = scope("Lot --> t(2, 0, 0) rotate(rel, world, 0, 90, 0) X.");
    assert!(close(s.axes.x_axis, DVec3::new(0.0, 0.0, -1.0)));
    assert!(close(s.axes.z_axis, DVec3::new(1.0, 0.0, 0.0)));
    assert!(close(s.origin, DVec3::new(2.0, 0.0, 0.0)));
    // Relative to the scope, a rotation is r's.
    let a = scope("Lot --> r(10, 20, 30) rotate(rel, scope, 0, 45, 0) X.");
    let b = scope("Lot --> r(10, 20, 30) r(0, 45, 0) X.");
    assert!(a.axes.abs_diff_eq(b.axes, 1e-12) && close(a.origin, b.origin));
    let errors = compile_errors("Lot --> translate(add, world, 1, 0, 0) X.").join("\n");
    assert!(errors.contains("expected `abs` or `rel`"), "{errors}");
    let errors = compile_errors("Lot --> rotate(abs, lot, 1, 0, 0) X.").join("\n");
    assert!(
        errors.contains("expected `scope`, `pivot`, `object` or `world`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> rotate(abs, world, 1, 0) X.").join("\n");
    assert!(
        errors.contains("wrong number of arguments for `rotate`"),
        "{errors}"
    );
}

#[test]
fn split_area_cuts_parts_of_the_areas_asked_for() {
    // On the 20 × 30 lot, 200 m² is 6⅔ m of its 20 m width.
    let r = reports(
        "Lot --> splitArea(x) { 200 : report(\"a\", geometry.area) report(\"sx\", scope.sx) A. | ~1 : report(\"b\", geometry.area) B. }",
        common::lot(20.0, 30.0),
    );
    assert_close(&of(&r, "a"), &[200.0]);
    assert_close(&of(&r, "sx"), &[20.0 / 3.0]);
    assert_close(&of(&r, "b"), &[400.0]);
    // A right triangle with legs of 20 and 30 m: halves of 150 m², and repeats of 100 m².
    let triangle = || {
        InitialShape::from_xz(&[
            DVec2::new(0.0, 0.0),
            DVec2::new(20.0, 0.0),
            DVec2::new(0.0, 30.0),
        ])
        .unwrap()
    };
    let r = reports(
        "Lot --> splitArea(x) { '0.5 : report(\"a\", geometry.area) A. | '0.5 : report(\"a\", geometry.area) B. }",
        triangle(),
    );
    assert_close(&of(&r, "a"), &[150.0, 150.0]);
    let r = reports(
        "Lot --> splitArea(z) { 100 : report(\"a\", geometry.area) P. }*",
        triangle(),
    );
    assert_close(&of(&r, "a"), &[100.0, 100.0, 100.0]);
    // Sizes short of the whole leave the rest out.
    let r = reports(
        "Lot --> splitArea(x) { 50 : report(\"a\", geometry.area) P. }",
        triangle(),
    );
    assert_close(&of(&r, "a"), &[50.0]);
    let error = try_run(
        "Lot --> extrude(3) splitArea(x) { 10 : A. }",
        l_lot(),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("splitArea needs a flat shape"), "{error}");
    let errors = compile_errors("Lot --> splitArea(x, snap) { 10 : A. }").join("\n");
    assert!(
        errors.contains("`splitArea` takes `adjust` or `noAdjust` only"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> splitArea(x)").join("\n");
    assert!(
        errors.contains("`splitArea` needs a `{ size : … }` block"),
        "{errors}"
    );
}

#[test]
fn uv_splits_cut_across_a_texture_coordinate() {
    // u runs along x, 1 per 5 m: u from 0 to 4 over the 20 m lot.
    let project = "setupProjection(0, scope.xz, 5, 5) projectUV(0)";
    let r = reports(
        &format!(
            "Lot --> {project} split(u, uvSpace, 0) {{ 1 : report(\"a\", geometry.area) A. | ~1 : report(\"b\", geometry.area) B. }}"
        ),
        common::lot(20.0, 30.0),
    );
    assert_close(&of(&r, "a"), &[150.0]);
    assert_close(&of(&r, "b"), &[450.0]);
    // In metres, 4 m strips: five of 120 m², numbered by split.index.
    let r = reports(
        &format!(
            "Lot --> {project} split(u, unitSpace, 0) {{ ~4 : report(\"a\", geometry.area) report(\"i\", split.index) P. }}*"
        ),
        common::lot(20.0, 30.0),
    );
    assert_close(&of(&r, "a"), &[120.0; 5]);
    assert_close(&of(&r, "i"), &[0.0, 1.0, 2.0, 3.0, 4.0]);
    // v runs along z, 1 per 10 m.
    let r = reports(
        "Lot --> setupProjection(0, scope.xz, 5, 10) projectUV(0) split(v, uvSpace, 0) { 1 : report(\"a\", geometry.area) A. }*",
        common::lot(20.0, 30.0),
    );
    assert_close(&of(&r, "a"), &[200.0, 200.0, 200.0]);
    let error = try_run(
        "Lot --> split(u, uvSpace, 0) { 1 : A. }",
        common::lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("the shape has no uv set 0 to split along"),
        "{error}"
    );
    let errors = compile_errors("Lot --> split(u, pixelSpace, 0) { 1 : A. }").join("\n");
    assert!(
        errors.contains("expected `uvSpace` or `unitSpace`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> split(v, uvSpace) { 1 : A. }").join("\n");
    assert!(
        errors.contains("wrong number of arguments for `split`"),
        "{errors}"
    );
}

#[test]
fn scatter_makes_point_shapes_on_and_in_the_shape() {
    use shapegram_geom::DVec3;
    let points = |rule: &str| -> Vec<(DVec3, DVec3)> {
        let d = try_run(
            &format!("{rule}\nT --> s(1, 1, 1) primitiveCube()"),
            common::lot(20.0, 30.0),
            &DeriveOptions::default(),
        )
        .unwrap();
        d.leaves
            .iter()
            .map(|l| (l.scope.origin, l.scope.axes.y_axis))
            .collect()
    };
    // On the lot: 50 points on it, their y up.
    let on = points("Lot --> scatter(surface, 50, uniform) { T }");
    assert_eq!(on.len(), 50);
    for (p, up) in &on {
        assert!(p.y.abs() < 1e-9 && (0.0..=20.0).contains(&p.x) && (0.0..=30.0).contains(&p.z));
        assert!(up.abs_diff_eq(DVec3::Y, 1e-12));
    }
    // In a mass, strictly inside; on its surface, on one of its faces.
    let inside = points("Lot --> extrude(10) scatter(volume, 40, uniform) { T }");
    assert_eq!(inside.len(), 40);
    assert!(
        inside
            .iter()
            .all(|(p, _)| p.y > 0.0 && p.y < 10.0 && p.x > 0.0 && p.x < 20.0)
    );
    let surface = points("Lot --> extrude(10) scatter(surface, 40, uniform) { T }");
    let on_a_face = |p: DVec3| {
        [p.x, p.x - 20.0, p.y, p.y - 10.0, p.z, p.z - 30.0]
            .iter()
            .any(|d| d.abs() < 1e-9)
    };
    assert!(surface.iter().all(|(p, _)| on_a_face(*p)));
    // Gaussian about the centre with a small spread stays near it.
    let near = points("Lot --> scatter(scope, 100, gaussian, center, '0.05) { T }");
    assert_eq!(near.len(), 100);
    let mean = near.iter().map(|(p, _)| *p).sum::<DVec3>() / 100.0;
    assert!(
        (mean.x - 10.0).abs() < 1.0 && (mean.z - 15.0).abs() < 1.5,
        "{mean}"
    );
    assert!(
        near.iter().all(|(p, _)| (p.x - 10.0).abs() < 6.0),
        "{near:?}"
    );
    // The same grammar scatters the same points.
    assert_eq!(on, points("Lot --> scatter(surface, 50, uniform) { T }"));
    let error = try_run(
        "Lot --> scatter(surface, -1, uniform) { T. }",
        common::lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("scatter's count must be 0 or more, not -1"),
        "{error}"
    );
    let errors = compile_errors("Lot --> scatter(line, 3, uniform) { T. }").join("\n");
    assert!(
        errors.contains("expected `surface`, `volume` or `scope`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> scatter(surface, 3, evenly) { T. }").join("\n");
    assert!(
        errors.contains("expected `uniform` or `gaussian`"),
        "{errors}"
    );
}
