//! Implicit solids as shapes: `implicit(kind)` fits a solid to the scope, `csg(group, mode)`
//! combines the members of a group per initial shape, and the derivation meshes them.

use crate::common;

use std::f64::consts::PI;

use common::{compile, compile_errors, lot, run, try_run};
use shapegram_eval::{DeriveOptions, derive};
use shapegram_geom::{DVec3, Part};

/// The meshed solids of `text` derived on a `w` × `d` lot.
fn solids(text: &str, w: f64, d: f64) -> Vec<Part> {
    run(text, lot(w, d)).solids
}

fn volume(part: &Part) -> f64 {
    part.mesh.signed_volume()
}

fn assert_near(actual: f64, expected: f64, tolerance: f64) {
    assert!(
        (actual - expected).abs() <= tolerance * expected.abs(),
        "{actual} is not within {}% of {expected}",
        tolerance * 100.0
    );
}

#[test]
fn a_sphere_fills_its_scope_closed_with_outward_unit_normals() {
    let parts = solids(
        "Lot --> extrude(2) color(\"#aa5500\") implicit(sphere) Ball.",
        2.0,
        2.0,
    );
    assert_eq!(parts.len(), 1);
    let ball = &parts[0];
    assert_eq!(ball.name, "Ball");
    assert_eq!(ball.color.to_hex(), "#aa5500");
    assert!(ball.mesh.is_watertight());
    assert_near(volume(ball), 4.0 / 3.0 * PI, 0.01);
    assert_near(ball.mesh.area(), 4.0 * PI, 0.01);
    assert_eq!(ball.normals.len(), ball.mesh.vertex_count());
    let centre = DVec3::ONE;
    let bounds = ball.mesh.bounds().unwrap();
    assert!((bounds.center() - centre).length() < 0.01, "{bounds:?}");
    for (p, n) in ball.mesh.positions().iter().zip(&ball.normals) {
        assert!((n.length() - 1.0).abs() < 1e-9);
        assert!(n.dot((*p - centre).normalize()) > 0.99, "{p} {n}");
    }
}

#[test]
fn every_kind_fits_its_scope() {
    // Each kind in a 4 × 2 × 4 box, but the torus, which needs one more than twice as wide as
    // high.
    let expected = [
        ("box", 4.0, 32.0),
        ("sphere", 4.0, 4.0 / 3.0 * PI * 2.0 * 1.0 * 2.0),
        ("cylinder", 4.0, PI * 4.0 * 2.0),
        ("cone", 4.0, PI * 4.0 * 2.0 / 3.0),
        ("pyramid", 4.0, 32.0 / 3.0),
        // Ring radius 2, tube radius 1: 2π²Rr².
        ("torus", 6.0, 2.0 * PI * PI * 2.0),
        // Lower than wide: a ball squashed to the box's height.
        ("capsule", 4.0, 4.0 / 3.0 * PI * 2.0 * 1.0 * 2.0),
    ];
    for (kind, w, v) in expected {
        let parts = solids(&format!("Lot --> extrude(2) implicit({kind}) S."), w, w);
        assert_eq!(parts.len(), 1, "{kind}");
        assert!(parts[0].mesh.is_watertight(), "{kind}");
        assert_near(volume(&parts[0]), v, 0.03);
        let size = parts[0].mesh.bounds().unwrap().size();
        // Apexes are points, which the mesh reaches only to within a cell.
        let tolerance = if matches!(kind, "cone" | "pyramid") {
            0.3
        } else {
            0.05
        };
        assert!(
            (size - DVec3::new(w, 2.0, w)).abs().max_element() < tolerance,
            "{kind}: {size}"
        );
    }
}

#[test]
fn a_group_unions_its_members_into_one_surface() {
    // Two unit-radius balls whose centres are 1.5 apart: twice a ball less the lens they
    // share, π(4r + d)(2r − d)²/12.
    let parts = run(
        "Lot --> extrude(2) split(x) { 2 : A | 1 : B }
         A --> implicit(sphere) csg(\"pair\", union) Done.
         B --> s(2, '1, '1) t(-0.5, 0, 0) implicit(sphere) csg(\"pair\", union) Done.",
        lot(3.0, 2.0),
    )
    .solids;
    assert_eq!(parts.len(), 1);
    assert_eq!(parts[0].name, "pair");
    assert!(parts[0].mesh.is_watertight());
    let ball = 4.0 / 3.0 * PI;
    let lens = PI * 5.5 * 0.25 / 12.0;
    assert_near(volume(&parts[0]), 2.0 * ball - lens, 0.01);
}

#[test]
fn carving_does_not_depend_on_derivation_order() {
    // A 4 × 4 × 4 block with a round tunnel of radius 1 along z, carved by a shape derived
    // before the block and by one derived after it.
    let before = "Lot --> extrude(4) [ Tunnel ] Block
                  Tunnel --> s(2, '1, 2) center(xz) implicit(cylinder) csg(\"rock\", subtract) Hole.
                  Block --> csg(\"rock\", union) Rock.";
    let after = "Lot --> extrude(4) [ Block ] Tunnel
                 Tunnel --> s(2, '1, 2) center(xz) implicit(cylinder) csg(\"rock\", subtract) Hole.
                 Block --> csg(\"rock\", union) Rock.";
    let expected = 64.0 - PI * 4.0;
    for text in [before, after] {
        let parts = solids(text, 4.0, 4.0);
        assert_eq!(parts.len(), 1);
        assert_eq!(parts[0].name, "rock");
        assert!(parts[0].mesh.is_watertight());
        assert_near(volume(&parts[0]), expected, 0.02);
    }
    let first = solids(before, 4.0, 4.0);
    let second = solids(after, 4.0, 4.0);
    assert_eq!(first[0].mesh, second[0].mesh);
}

#[test]
fn intersect_keeps_the_common_part_and_morph_blends() {
    // A 2-cube trimmed by the ball it encloses is that ball.
    let parts = solids(
        "Lot --> extrude(2) [ csg(\"g\", union) A. ] implicit(sphere) csg(\"g\", intersect) B.",
        2.0,
        2.0,
    );
    assert_near(volume(&parts[0]), 4.0 / 3.0 * PI, 0.01);
    // Morphing a ball towards ball ∪ cube by 0 and by 1 gives the two ends.
    let morph = |a: &str| {
        solids(
            &format!(
                "Lot --> extrude(2) [ implicit(sphere) csg(\"g\", union) A. ] csg(\"g\", morph, {a}) B."
            ),
            2.0,
            2.0,
        )
    };
    assert_near(volume(&morph("0")[0]), 4.0 / 3.0 * PI, 0.01);
    assert_near(volume(&morph("1")[0]), 8.0, 0.02);
    let half = volume(&morph("0.5")[0]);
    assert!(half > 4.5 && half < 7.5, "{half}");
}

#[test]
fn a_fillet_adds_material_where_members_meet() {
    // Two unit balls 1.5 apart meet in a sharp crease; a fillet of 0.5 fills it in.
    let text = |k: &str| {
        format!(
            "Lot --> extrude(2) split(x) {{ 2 : A | 1 : NIL | 2 : B }}
             A --> implicit(sphere) csg(\"g\", union{k}) Done.
             B --> t(-1.5, 0, 0) implicit(sphere) csg(\"g\", union{k}) Done."
        )
    };
    let sharp = volume(&solids(&text(""), 5.0, 2.0)[0]);
    let round = volume(&solids(&text(", 0.5"), 5.0, 2.0)[0]);
    let ball = 4.0 / 3.0 * PI;
    assert_near(sharp, 2.0 * ball - PI * 5.5 * 0.25 / 12.0, 0.01);
    assert!(round > sharp + 0.1, "{round} is not above {sharp}");
    // A fillet larger than the solids would swell them into a blob: an error.
    let e = try_run(&text(", 1000"), lot(5.0, 2.0), &DeriveOptions::default()).unwrap_err();
    assert!(
        e.message
            .starts_with("fillet radius 1000 is larger than the solids"),
        "{}",
        e.message
    );
}

#[test]
fn turns_zero_sizes_and_adjusted_splits_keep_scopes_tight() {
    // Turning the scope there and back leaves it as it was (fitted to the surface, not to a
    // box that grows with every turn).
    let d = run(
        "Lot --> extrude(10) implicit(sphere) rotateScope(0, 45, 0) rotateScope(0, -45, 0)
         report(\"sx\", scope.sx) S.",
        lot(10.0, 10.0),
    );
    let sx = match d.reports[0].1 {
        shapegram_eval::Value::Number(n) => n,
        _ => unreachable!(),
    };
    assert!((sx - 10.0).abs() < 0.5, "{sx}");
    // A zero size squashes a solid to nothing.
    let flat = run(
        "Lot --> extrude(10) implicit(sphere) s('1, 0, '1) S.",
        lot(10.0, 10.0),
    );
    assert!(flat.solids.is_empty());
    // Slabs of a ball are fitted to the ball's cross-section at them.
    let d = run(
        "Lot --> extrude(10) implicit(sphere) split(x) { 1 : report(\"sy\", scope.sy) X. }*",
        lot(10.0, 10.0),
    );
    let sy: Vec<f64> = d
        .reports
        .iter()
        .map(|(_, v)| match v {
            shapegram_eval::Value::Number(n) => *n,
            _ => unreachable!(),
        })
        .collect();
    assert_eq!(sy.len(), 10);
    assert!(sy[0] < 7.0 && sy[4] > 9.5, "{sy:?}");
}

#[test]
fn members_too_thin_to_mesh_are_errors_and_the_time_budget_holds() {
    let plate = "Lot --> extrude(0.02) implicit(box) Plate.";
    let e = try_run(plate, lot(20.0, 20.0), &DeriveOptions::default()).unwrap_err();
    assert!(
        e.message.starts_with("`Plate` is 0.02 thin"),
        "{}",
        e.message
    );
    assert_eq!(&plate[e.span.unwrap().range()], "implicit(box)");
    // Thin slabs of a thick solid are no trouble.
    let slabs = "Lot --> extrude(10) implicit(sphere) csg(\"g\", union) split(x) { 0.5 : A. }*";
    assert_eq!(
        try_run(slabs, lot(10.0, 10.0), &DeriveOptions::default())
            .unwrap()
            .solids
            .len(),
        1
    );
    // With a cell size given, it is meshed as asked.
    let fine = DeriveOptions {
        implicit_cell: Some(0.005),
        ..DeriveOptions::default()
    };
    assert_eq!(
        try_run(plate, lot(2.0, 2.0), &fine).unwrap().solids.len(),
        1
    );
    let slow = DeriveOptions {
        implicit_cell: Some(0.002),
        time_budget: Some(std::time::Duration::from_millis(1)),
        ..DeriveOptions::default()
    };
    let e = try_run(
        "Lot --> extrude(4) implicit(sphere) Ball.",
        lot(4.0, 4.0),
        &slow,
    )
    .unwrap_err();
    assert!(
        e.message.contains("took longer than the time allowed"),
        "{}",
        e.message
    );
}

#[test]
fn groups_are_per_initial_shape_and_solids_alone_per_rule() {
    let program = compile(
        "Lot --> extrude(1) [ implicit(sphere) csg(\"g\", union) A. ] t(0, 1, 0) implicit(box) Alone.",
    );
    let lots = [lot(1.0, 1.0), {
        let mut far = lot(1.0, 1.0);
        for p in &mut far.footprint {
            p.x += 5.0;
        }
        far
    }];
    let d = derive(&program, &lots, &DeriveOptions::default()).unwrap();
    let names: Vec<&str> = d.solids.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["g", "Alone", "g", "Alone"]);
    let model = d.to_model();
    assert_eq!(model.parts.len(), 4);
    assert!(
        model
            .parts
            .iter()
            .all(|p| p.normals.len() == p.mesh.vertex_count())
    );
}

#[test]
fn a_split_cuts_the_solid_into_slabs() {
    // A ball split in half along x: each half is closed and half the volume; as members of one
    // group the halves make the ball again.
    // Coloured apart, the halves are two parts (solids of one rule and colour would merge).
    let halves = solids(
        "Lot --> extrude(2) implicit(sphere) split(x) { '0.5 : color(\"#ff0000\") Half | '0.5 : Half }
         Half --> Done.",
        2.0,
        2.0,
    );
    assert_eq!(halves.len(), 2);
    for half in &halves {
        assert!(half.mesh.is_watertight());
        assert_near(volume(half), 2.0 / 3.0 * PI, 0.02);
        assert!(half.mesh.bounds().unwrap().size().x < 1.01);
    }
    let joined = solids(
        "Lot --> extrude(2) implicit(sphere) csg(\"ball\", union) split(x) { '0.5 : H | '0.5 : H }
         H --> Done.",
        2.0,
        2.0,
    );
    assert_eq!(joined.len(), 1);
    assert_near(volume(&joined[0]), 4.0 / 3.0 * PI, 0.01);
}

#[test]
fn scaling_moving_and_mirroring_carry_the_solid_along() {
    let parts = solids(
        "Lot --> extrude(2) implicit(cone) s(4, 4, 4) t(10, 0, 0) mirror(false, true, false) S.",
        2.0,
        2.0,
    );
    let bounds = parts[0].mesh.bounds().unwrap();
    // The apex, a point, is reached to within a cell.
    assert!(
        (bounds.min - DVec3::new(10.0, 0.0, 0.0))
            .abs()
            .max_element()
            < 0.2,
        "{bounds:?}"
    );
    assert!(
        (bounds.max - DVec3::new(14.0, 4.0, 4.0))
            .abs()
            .max_element()
            < 0.05,
        "{bounds:?}"
    );
    assert_near(volume(&parts[0]), PI * 4.0 * 4.0 / 3.0, 0.03);
    // Mirrored in y, the apex points down: the widest slice is at the top.
    let top = parts[0]
        .mesh
        .positions()
        .iter()
        .filter(|p| p.y > 3.9)
        .map(|p| p.x)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(top > 13.5, "{top}");
}

#[test]
fn the_cell_size_option_sets_the_detail() {
    let text = "Lot --> extrude(2) implicit(sphere) S.";
    let coarse = DeriveOptions {
        implicit_cell: Some(0.25),
        ..DeriveOptions::default()
    };
    let fine = DeriveOptions {
        implicit_cell: Some(0.05),
        ..DeriveOptions::default()
    };
    let coarse = try_run(text, lot(2.0, 2.0), &coarse).unwrap().solids;
    let fine = try_run(text, lot(2.0, 2.0), &fine).unwrap().solids;
    assert!(fine[0].mesh.face_count() > 10 * coarse[0].mesh.face_count());
    let bad = DeriveOptions {
        implicit_cell: Some(0.0),
        ..DeriveOptions::default()
    };
    let err = try_run(text, lot(2.0, 2.0), &bad).unwrap_err();
    assert_eq!(
        err.message,
        "implicit cell size 0: expected a finite number above 0"
    );
}

#[test]
fn results_are_the_same_on_any_number_of_threads() {
    let text = "Lot --> extrude(3) split(x) { ~1 : B }*
                B --> s('1, rand(1, 3), '1) implicit(sphere) csg(\"g\", union, 0.3) Done.";
    let program = compile(text);
    let lots: Vec<_> = (0..6)
        .map(|i| {
            let mut l = lot(6.0, 3.0);
            for p in &mut l.footprint {
                p.z += 4.0 * f64::from(i);
            }
            l
        })
        .collect();
    let options = DeriveOptions::default();
    let on = |threads| common::derive_on_threads(&program, &lots, &options, threads).solids;
    let one = on(1);
    assert_eq!(one.len(), 6);
    assert_eq!(one, on(4));
}

#[test]
fn bad_uses_are_errors_with_spans() {
    let err = |text: &str| try_run(text, lot(2.0, 2.0), &DeriveOptions::default()).unwrap_err();
    let flat = "Lot --> implicit(sphere) S.";
    let e = err(flat);
    assert_eq!(
        e.message,
        "implicit(sphere) needs a scope with volume, but its size is 2 × 0 × 2"
    );
    assert_eq!(&flat[e.span.unwrap().range()], "implicit(sphere)");
    let e = err("Lot --> csg(\"g\", union) S.");
    assert!(
        e.message.contains("needs an implicit solid or a box"),
        "{}",
        e.message
    );
    let e = err("Lot --> extrude(3) implicit(torus) S.");
    assert!(
        e.message.contains("more than twice as wide"),
        "{}",
        e.message
    );
    let morph = "Lot --> extrude(1) csg(\"g\", morph, 1.5) S.";
    let e = err(morph);
    assert!(e.message.starts_with("morph amount 1.5"), "{}", e.message);
    assert_eq!(&morph[e.span.unwrap().range()], "1.5");
    let e = err("Lot --> extrude(1) csg(\"g\", union, -1) S.");
    assert!(e.message.starts_with("fillet radius -1"), "{}", e.message);
    let e = err("Lot --> extrude(1) csg(3, union) S.");
    assert_eq!(
        e.message,
        "expected a group name (a string), found a number"
    );
    let e = err("Lot --> extrude(1) implicit(box) comp(f) { all : F. }");
    assert!(e.message.starts_with("comp needs faces"), "{}", e.message);
    let e = err("Lot --> extrude(1) implicit(box) reverseNormals() F.");
    assert!(
        e.message.starts_with("reverseNormals needs faces"),
        "{}",
        e.message
    );
    let e = err("Lot --> extrude(1) implicit(box) alignScopeToGeometry(yUp, 0, 0) F.");
    assert!(
        e.message.starts_with("alignScopeToGeometry needs faces"),
        "{}",
        e.message
    );

    let errors = compile_errors("Lot --> implicit(blob) S.").join("\n");
    assert!(
        errors.contains("expected a solid: `box`, `sphere`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> csg(\"g\", merge) S.").join("\n");
    assert!(
        errors.contains("expected `union`, `subtract`, `intersect` or `morph`"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> csg(\"g\", morph) S.").join("\n");
    assert!(errors.contains("the signature is `csg("), "{errors}");
}

/// Serves one implicit grammar, `ball.cave`, whose solid is a unit ball.
struct OneBall;

impl shapegram_eval::AssetLoader for OneBall {
    fn load(&self, path: &str) -> Result<std::sync::Arc<shapegram_geom::Mesh>, String> {
        Err(format!("no mesh `{path}`"))
    }

    fn solid(&self, path: &str) -> Result<shapegram_implicit::Solid, String> {
        match path {
            "ball.cave" => shapegram_implicit::Solid::sphere(1.0).map_err(|e| e.to_string()),
            _ => Err("no such grammar".to_owned()),
        }
    }
}

#[test]
fn an_implicit_grammar_is_stretched_to_the_scope() {
    let options = DeriveOptions {
        assets: Some(std::sync::Arc::new(OneBall)),
        ..DeriveOptions::default()
    };
    let text = "Lot --> extrude(2) implicit(\"ball.cave\") csg(\"g\", union) B.";
    let d = try_run(text, lot(4.0, 4.0), &options).unwrap();
    assert_near(volume(&d.solids[0]), 4.0 / 3.0 * PI * 2.0 * 1.0 * 2.0, 0.01);
    let size = d.solids[0].mesh.bounds().unwrap().size();
    assert!(
        (size - DVec3::new(4.0, 2.0, 4.0)).abs().max_element() < 0.05,
        "{size}"
    );

    let missing = "Lot --> extrude(2) implicit(\"rock.cave\") B.";
    let e = try_run(missing, lot(4.0, 4.0), &options).unwrap_err();
    assert_eq!(e.message, "cannot run `rock.cave`: no such grammar");
    assert_eq!(&missing[e.span.unwrap().range()], "\"rock.cave\"");
    let e = try_run(missing, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    assert_eq!(e.message, "cannot run `rock.cave`: no asset folder is set");
}
