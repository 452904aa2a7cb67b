//! `taper`, `twist` and `shear`: deformed boxes, meshes and solids measured against exact
//! values, and the errors of wrong arguments.

use crate::common;

use common::{lot, names, run, try_run};
use shapegram_eval::{DeriveOptions, Geometry, Program};
use shapegram_geom::{DVec3, Mesh};
use shapegram_syntax::{Severity, SourceFile, parse};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// The world mesh of the only leaf of `text` derived on a `w` × `d` lot.
fn only_mesh(text: &str, w: f64, d: f64) -> Mesh {
    let d = run(text, lot(w, d));
    assert_eq!(d.leaves.len(), 1, "{:?}", names(&d));
    d.leaves[0].world_mesh().unwrap()
}

/// World positions of the vertices at height `y`.
fn at_height(mesh: &Mesh, y: f64) -> Vec<DVec3> {
    mesh.positions()
        .iter()
        .copied()
        .filter(|p| close(p.y, y, 1e-9))
        .collect()
}

fn has_point(points: &[DVec3], p: DVec3) -> bool {
    points.iter().any(|q| q.abs_diff_eq(p, 1e-9))
}

/// The diagnostics of compiling `text`: severity, message and the text under the span.
fn diagnostics(text: &str) -> Vec<(Severity, String, String)> {
    let source = SourceFile::new("test.cga", text);
    let parsed = parse(&source);
    let (_, diagnostics) = Program::compile(&parsed.grammar);
    parsed
        .diagnostics
        .iter()
        .chain(&diagnostics)
        .map(|d| {
            (
                d.severity,
                d.message.clone(),
                text[d.span.range()].to_string(),
            )
        })
        .collect()
}

#[test]
fn an_extruded_lot_tapered_to_half_is_a_frustum() {
    let mesh = only_mesh("Lot --> extrude(10) taper(y, 0.5)", 4.0, 6.0);
    assert!(mesh.is_watertight());
    // h/3 · (A₀ + A₁ + √(A₀A₁)) = 10/3 · (24 + 6 + 12).
    assert!(
        close(mesh.signed_volume(), 140.0, 1e-9),
        "{}",
        mesh.signed_volume()
    );
    // The top is the middle half of the lot, 10 up.
    let top = at_height(&mesh, 10.0);
    assert_eq!(top.len(), 4);
    for p in [(1.0, 1.5), (3.0, 1.5), (3.0, 4.5), (1.0, 4.5)] {
        assert!(has_point(&top, DVec3::new(p.0, 10.0, p.1)), "{top:?}");
    }
    // Tapered to 0, a pyramid with its apex over the lot's centre; the scope stays.
    let d = run("Lot --> extrude(10) taper(y, 0) Spire", lot(4.0, 6.0));
    let spire = &d.leaves[0];
    assert!(
        spire
            .scope
            .size
            .abs_diff_eq(DVec3::new(4.0, 10.0, 6.0), 1e-12)
    );
    let mesh = spire.world_mesh().unwrap();
    assert!(mesh.is_watertight());
    assert!(close(mesh.signed_volume(), 80.0, 1e-9));
    assert_eq!(at_height(&mesh, 10.0), [DVec3::new(2.0, 10.0, 3.0)]);
}

#[test]
fn taper_along_other_axes_and_of_a_facade() {
    // Along x, to twice the size: 4/3 · (60 + 240 + 120) = 560, on an 4 × 6 lot 10 high.
    let mesh = only_mesh("Lot --> extrude(10) taper(x, 2)", 4.0, 6.0);
    assert!(
        close(mesh.signed_volume(), 560.0, 1e-9),
        "{}",
        mesh.signed_volume()
    );
    // A facade tapered to 0 across its height is a gable triangle.
    let d = run(
        "Lot --> extrude(3) comp(f) { front : taper(y, 0) Gable | all : NIL }",
        lot(6.0, 4.0),
    );
    assert_eq!(names(&d), ["Gable"]);
    let gable = d.leaves[0].world_mesh().unwrap();
    assert_eq!(gable.face_count(), 1);
    assert_eq!(gable.face(0).len(), 3);
    assert!(close(gable.area(), 9.0, 1e-9));
}

#[test]
fn a_twisted_tower_keeps_its_volume_and_turns_its_top() {
    let mesh = only_mesh("Lot --> extrude(10) twist(y, 30)", 4.0, 4.0);
    assert!(mesh.is_watertight());
    // The walls run straight between slices of 7.5°: 0.14 % of the volume goes.
    let volume = mesh.signed_volume();
    assert!(
        volume < 160.0 && close(volume, 160.0, 160.0 * 2e-3),
        "{volume}"
    );
    // The top has turned 30° about the vertical centre line (right-handed about +y).
    let top = at_height(&mesh, 10.0);
    let (sin, cos) = 30f64.to_radians().sin_cos();
    for (x, z) in [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)] {
        let (dx, dz) = (x - 2.0, z - 2.0);
        let turned = DVec3::new(2.0 + dx * cos + dz * sin, 10.0, 2.0 - dx * sin + dz * cos);
        assert!(has_point(&top, turned), "{turned} not in {top:?}");
    }
    // The bottom stays.
    let bottom = at_height(&mesh, 0.0);
    for (x, z) in [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)] {
        assert!(has_point(&bottom, DVec3::new(x, 0.0, z)));
    }
}

#[test]
fn a_twist_by_half_a_turn_along_the_tower() {
    let mesh = only_mesh("Lot --> extrude(24) twist(y, 180)", 4.0, 4.0);
    assert!(mesh.is_watertight());
    let volume = mesh.signed_volume();
    assert!(close(volume, 384.0, 384.0 * 2e-3), "{volume}");
    // 24 slices, each wall piece a fan of four triangles: the walls alone have 384 faces.
    assert_eq!(mesh.face_count(), 24 * 4 * 4 + 2);
    // Halfway up, a quarter turn: (0, 12, 0) is at (0, 12, 4).
    assert!(has_point(
        &at_height(&mesh, 12.0),
        DVec3::new(0.0, 12.0, 4.0)
    ));
    // At the top, half a turn: each corner is where the opposite one was.
    assert!(has_point(
        &at_height(&mesh, 24.0),
        DVec3::new(4.0, 24.0, 4.0)
    ));
}

#[test]
fn shear_moves_the_top_by_the_amount() {
    let d = run("Lot --> extrude(10) shear(y, x, 3) Lean", lot(4.0, 6.0));
    let leaf = &d.leaves[0];
    let mesh = leaf.world_mesh().unwrap();
    assert!(mesh.is_watertight());
    assert!(close(mesh.signed_volume(), 240.0, 1e-9));
    // The scope keeps its size; the geometry leans out of it along the scope's x.
    assert!(
        leaf.scope
            .size
            .abs_diff_eq(DVec3::new(4.0, 10.0, 6.0), 1e-12)
    );
    let lean = leaf.scope.x_axis() * 3.0;
    let bottom = at_height(&mesh, 0.0);
    let top = at_height(&mesh, 10.0);
    assert_eq!((bottom.len(), top.len()), (4, 4));
    for p in &bottom {
        assert!(
            has_point(&top, *p + DVec3::new(0.0, 10.0, 0.0) + lean),
            "{p}"
        );
    }
    // Halfway: a split of the sheared mass leans half as far at its cut.
    let d = run(
        "Lot --> extrude(10) shear(y, z, -2) split(y) { 5 : Low | ~1 : High }",
        lot(4.0, 6.0),
    );
    assert_eq!(names(&d), ["Low", "High"]);
    let low = d.leaves[0].world_mesh().unwrap();
    let high = d.leaves[1].world_mesh().unwrap();
    assert!(close(low.signed_volume(), 120.0, 1e-9));
    assert!(close(high.signed_volume(), 120.0, 1e-9));
    let lean = d.leaves[0].scope.z_axis() * -1.0;
    let cut = at_height(&low, 5.0);
    for p in at_height(&low, 0.0) {
        assert!(has_point(&cut, p + DVec3::new(0.0, 5.0, 0.0) + lean), "{p}");
    }
}

#[test]
fn deformations_compose_and_split_like_any_mesh() {
    // A spire tapered to a point and split: the parts share the pyramid's volume.
    let d = run(
        "Lot --> extrude(12) taper(y, 0) split(y) { 6 : Base | ~1 : Tip }",
        lot(6.0, 6.0),
    );
    let volume = |i: usize| d.leaves[i].world_mesh().unwrap().signed_volume();
    // The top half of a pyramid is an eighth of it.
    assert!(close(volume(0) + volume(1), 144.0, 1e-9));
    assert!(close(volume(1), 18.0, 1e-9), "{}", volume(1));
    // Tapered, twisted and sheared in one go: still one closed solid.
    let mesh = only_mesh(
        "Lot --> extrude(20) taper(y, 0.6) twist(y, 45) shear(y, x, 2)",
        5.0,
        5.0,
    );
    assert!(mesh.is_watertight());
    let frustum = 20.0 / 3.0 * (25.0 + 9.0 + 15.0);
    assert!(close(mesh.signed_volume(), frustum, frustum * 2e-3));
}

#[test]
fn identity_deformations_leave_a_box_a_box() {
    let d = run(
        "Lot --> extrude(10) taper(y, 1) twist(x, 0) shear(z, y, 0) Mass",
        lot(4.0, 6.0),
    );
    assert_eq!(d.leaves[0].geometry, Geometry::Box);
    let d = run("Lot --> extrude(10) twist(z, 10) Mass", lot(4.0, 6.0));
    assert!(matches!(d.leaves[0].geometry, Geometry::Mesh(..)));
}

#[test]
fn offset_tags_survive_a_twist() {
    // A lot twisted along x bends its faces into fans; each piece keeps its face's tag.
    let d = run(
        "Lot --> offset(-1) twist(x, 40) comp(f) { inside = In | border = Ring }",
        lot(8.0, 6.0),
    );
    assert_eq!(names(&d), ["In", "Ring"]);
    let area = |i: usize| d.leaves[i].world_mesh().unwrap().area();
    // A twisted strip has a little more area than the flat one: 6 × 4 inside, 48 − 24 around.
    assert!(area(0) > 24.0 && close(area(0), 24.0, 0.5), "{}", area(0));
    assert!(area(1) > 24.0 && close(area(1), 24.0, 0.5), "{}", area(1));
}

#[test]
fn implicit_solids_shear_but_do_not_taper_or_twist() {
    let d = run(
        "Lot --> extrude(4) implicit(box) shear(y, x, 2) S.",
        lot(4.0, 4.0),
    );
    let Geometry::Implicit(implicit) = &d.leaves[0].geometry else {
        panic!("{:?}", d.leaves[0].geometry);
    };
    let bounds = implicit.solid.bounds().unwrap();
    assert!(
        close(bounds.min.x, 0.0, 1e-9) && close(bounds.max.x, 6.0, 1e-9),
        "{bounds:?}"
    );
    assert!(close(bounds.max.y, 4.0, 1e-9));
    for op in ["twist(y, 30)", "taper(y, 0.5)"] {
        let text = format!("Lot --> extrude(4) implicit(sphere) {op} S");
        let err = try_run(&text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
        let name = &op[..5];
        assert_eq!(
            err.message,
            format!(
                "`{name}` cannot deform this shape: deformation of implicit solids is not supported"
            )
        );
        assert_eq!(&text[err.span.unwrap().range()], op);
    }
}

#[test]
fn wrong_arguments_are_errors_at_their_place() {
    let error = |text: &str| {
        let all = diagnostics(text);
        let errors: Vec<(String, String)> = all
            .into_iter()
            .filter(|d| d.0 == Severity::Error)
            .map(|d| (d.1, d.2))
            .collect();
        assert_eq!(errors.len(), 1, "{errors:?}");
        errors.into_iter().next().unwrap()
    };
    assert_eq!(
        error("Lot --> extrude(1) taper(w, 0.5) X"),
        ("expected the axis `x`, `y` or `z`".into(), "w".into())
    );
    assert_eq!(
        error("Lot --> extrude(1) twist(\"up\", 10) X"),
        ("expected the axis `x`, `y` or `z`".into(), "\"up\"".into())
    );
    assert_eq!(
        error("Lot --> extrude(1) shear(y, q, 1) X"),
        ("expected the axis `x`, `y` or `z`".into(), "q".into())
    );
    assert_eq!(
        error("Lot --> extrude(1) twist(y) X"),
        (
            "wrong number of arguments for `twist`".into(),
            "twist(y)".into()
        )
    );
    assert_eq!(
        error("Lot --> extrude(1) shear(y, 1) X"),
        (
            "wrong number of arguments for `shear`".into(),
            "shear(y, 1)".into()
        )
    );
    assert_eq!(
        error("Lot --> extrude(1) taper(y, 0.5, 2) X"),
        (
            "wrong number of arguments for `taper`".into(),
            "taper(y, 0.5, 2)".into()
        )
    );
    assert_eq!(
        error("Lot --> extrude(1) shear(y, y, 2) X"),
        (
            "`shear` needs two different axes, not `y` twice: points move along the second by \
             their position along the first"
                .into(),
            "y".into()
        )
    );
    assert_eq!(
        error("Lot --> extrude(1) twist(y, 10) { 1 : A }"),
        (
            "`twist` takes no `{…}` block".into(),
            "twist(y, 10) { 1 : A }".into()
        )
    );
}

#[test]
fn bad_amounts_fail_the_derivation_at_the_argument() {
    let text = "attr f = -0.5\nLot --> extrude(10) taper(y, f) X";
    let err = try_run(text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    assert_eq!(
        err.message,
        "taper factor -0.5: expected a number of at least 0 (0 draws the far end into a point, \
         1 changes nothing)"
    );
    assert_eq!(&text[err.span.unwrap().range()], "f");
    let text = "Lot --> extrude(10) twist(y, \"a lot\") X";
    let err = try_run(text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    assert_eq!(err.message, "expected a number, found a string");
    assert_eq!(&text[err.span.unwrap().range()], "\"a lot\"");
}

#[test]
fn cga_taper_by_height_builds_a_pyramid_over_the_face() {
    // Over the 4 × 4 m lot, 6 m up: 4 · 4 · 6 / 3 m³, closed, its scope 6 m high.
    let d = run("Lot --> taper(6) X.", lot(4.0, 4.0));
    let mesh = d.leaves[0].world_mesh().unwrap();
    assert!(mesh.is_watertight());
    assert!((mesh.signed_volume() - 32.0).abs() < 1e-9);
    assert!((d.leaves[0].scope.size.y - 6.0).abs() < 1e-9);
    let apex = mesh
        .positions()
        .iter()
        .copied()
        .fold(DVec3::splat(f64::MIN), DVec3::max);
    assert!((apex.y - 6.0).abs() < 1e-9);
    // Downward, the apex 3 m below the lot's centre.
    let d = run("Lot --> taper(-3) X.", lot(4.0, 4.0));
    let mesh = d.leaves[0].world_mesh().unwrap();
    assert!(mesh.is_watertight());
    assert!((mesh.signed_volume() - 16.0).abs() < 1e-9);
    assert!((mesh.bounds().unwrap().min.y + 3.0).abs() < 1e-9);
    // taper(height) needs a face; taper(axis, factor) deforms volumes.
    let err = try_run(
        "Lot --> extrude(10) taper(5) X.",
        lot(4.0, 4.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(
        err.message.contains("taper needs a flat shape"),
        "{}",
        err.message
    );
    let err = try_run(
        "Lot --> taper(0) X.",
        lot(4.0, 4.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert!(
        err.message.contains("cannot build a pyramid 0 high"),
        "{}",
        err.message
    );
}

#[test]
fn goal_grammars_deform_with_the_same_operations() {
    // Michelangelo's notation lowers its taper, twist and shear rules to these operations.
    let text = r#"new Axiom("post").Size(2, 8, 2);
new Rules.Split(Axis.Y, Relative(0.5).Goal("twisted"), Relative(0.5).Goal("tapered")).Fulfills("post");
new Rules.Twist(Axis.Y, 90).Fulfills("twisted");
new Rules.Taper(Axis.Y, 0).Fulfills("tapered");
"#;
    let source = SourceFile::new("post", text);
    let parsed = parse(&source);
    let shown: String = parsed
        .diagnostics
        .iter()
        .map(|d| source.render(d))
        .collect();
    assert!(parsed.diagnostics.is_empty(), "{shown}");
    let (program, diagnostics) = Program::compile(&parsed.grammar);
    let shown: String = diagnostics.iter().map(|d| source.render(d)).collect();
    let program = program.unwrap_or_else(|| panic!("{shown}"));
    let d = shapegram_eval::derive(&program, &[], &DeriveOptions::default()).unwrap();
    assert_eq!(d.leaves.len(), 2, "{:?}", names(&d));
    let volumes: Vec<f64> = d
        .leaves
        .iter()
        .map(|l| {
            let mesh = l.world_mesh().unwrap();
            assert!(mesh.is_watertight());
            mesh.signed_volume()
        })
        .collect();
    // A 2 × 4 × 2 box twisted a quarter turn, and a pyramid over 2 × 2, 4 high.
    assert!(
        volumes[0] < 16.0 && close(volumes[0], 16.0, 16.0 * 2e-3),
        "{volumes:?}"
    );
    assert!(close(volumes[1], 16.0 / 3.0, 1e-9), "{volumes:?}");
}
