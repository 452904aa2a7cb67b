//! The selectors of component splits and setbacks in their frames (`front`, `object.*`,
//! `street.*`, `world.*`, `streetSide`, slopes) and `comp(fe)`.

use crate::common;

use common::{compile_errors, lot, names, run};
use shapegram_eval::{Derivation, Leaf};
use shapegram_geom::DVec3;

/// Rules that give edges (which have no geometry) a beam, so that they become leaves.
const BEAMS: &str = "
    V --> s('1, 0.2, 0.2) primitiveCube()
    O --> s('1, 0.2, 0.2) primitiveCube()
    E --> s('1, 0.2, 0.2) primitiveCube()
    Up --> s('1, 0.2, 0.2) primitiveCube()
    F --> s('1, 0.2, 0.2) primitiveCube()
    B --> s('1, 0.2, 0.2) primitiveCube()
    S --> s('1, 0.2, 0.2) primitiveCube()
    Fifth --> s('1, 0.2, 0.2) primitiveCube()
";

/// Derives `rule` with [`BEAMS`] on a `w` × `d` lot.
fn beams(rule: &str, w: f64, d: f64) -> Derivation {
    run(&format!("{rule}\n{BEAMS}"), lot(w, d))
}

/// The leaves named `name`.
fn named<'d>(d: &'d Derivation, name: &str) -> Vec<&'d Leaf> {
    d.leaves.iter().filter(|l| d.name(l.name) == name).collect()
}

/// The world bounding box of a leaf's geometry.
fn bounds(leaf: &Leaf) -> (DVec3, DVec3) {
    let mesh = leaf.world_mesh().expect("geometry");
    mesh.positions().iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

fn area(leaf: &Leaf) -> f64 {
    leaf.world_mesh().expect("geometry").area()
}

fn close(a: DVec3, b: DVec3) -> bool {
    a.abs_diff_eq(b, 1e-9)
}

#[test]
fn object_and_street_selectors_keep_the_initial_shapes_frame() {
    // Turned a quarter about y, the scope's front is the 30 m edge at x = 20; the object's
    // front stays the first edge, 20 m long.
    let grammar = |selector: &str| {
        format!(
            "Lot --> rotateScope(0, 90, 0) setback(5) {{ {selector} : Strip. | remainder : NIL }}"
        )
    };
    let strip_area = |selector: &str| {
        let d = run(&grammar(selector), lot(20.0, 30.0));
        named(&d, "Strip").iter().map(|l| area(l)).sum::<f64>()
    };
    assert!((strip_area("front") - 150.0).abs() < 1e-9);
    for selector in ["object.front", "street.front", "streetSide"] {
        assert!((strip_area(selector) - 100.0).abs() < 1e-9, "{selector}");
    }
    // The other three edges, mitred where they meet: 600 m² less a 10 × 25 m rest.
    assert!((strip_area("noStreetSide") - (600.0 - 10.0 * 25.0)).abs() < 1e-9);
    assert!((strip_area("object.back") - 100.0).abs() < 1e-9);
    assert!((strip_area("object.side") - (600.0 - 10.0 * 20.0)).abs() < 1e-9);
}

#[test]
fn world_selectors_use_compass_directions() {
    // The lot spans x 0..20 and z 0..30; south is +z, east +x.
    let d = run(
        "Lot --> setback(2) { world.south : S. | world.east : E. | world.north : N. | remainder : R. }",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d).len(), 4);
    let (lo, hi) = bounds(named(&d, "S")[0]);
    assert!(close(lo, DVec3::new(0.0, 0.0, 28.0)) && close(hi, DVec3::new(20.0, 0.0, 30.0)));
    let (lo, hi) = bounds(named(&d, "E")[0]);
    assert!(close(lo, DVec3::new(18.0, 0.0, 0.0)) && close(hi, DVec3::new(20.0, 0.0, 30.0)));
    let (lo, hi) = bounds(named(&d, "N")[0]);
    assert!(close(lo, DVec3::new(0.0, 0.0, 0.0)) && close(hi, DVec3::new(20.0, 0.0, 2.0)));
    let (lo, hi) = bounds(named(&d, "R")[0]);
    assert!(close(lo, DVec3::new(0.0, 0.0, 2.0)) && close(hi, DVec3::new(18.0, 0.0, 28.0)));
    // Faces too: the top of a mass faces world.up, its walls world.side.
    let d = run(
        "Lot --> extrude(10) comp(f) { world.up : Up. | world.down : Down. | world.side : Wall. }",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["Up", "Down", "Wall", "Wall", "Wall", "Wall"]);
}

#[test]
fn comp_sel_names_frame_selectors() {
    let d = run(
        "Lot --> setback(1) { object.front : S(comp.sel) | world.side : S(comp.sel) | remainder : NIL }
         S(n) --> case n == \"object.front\" : Front. else : case n == \"world.side\" : Side. else : Other.",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["Front", "Side", "Side", "Side"]);
}

#[test]
fn slope_selectors_follow_cityengines_bounds() {
    // A 45° gable roof has aslant slopes; its gable ends are vertical and its bottom is
    // horizontal. The roof's scope has y up.
    let d = run(
        "Lot --> roofGable(45) comp(f) { aslant : A. | vertical : V. | horizontal : H. | all : O. }",
        lot(10.0, 20.0),
    );
    let mut n = names(&d);
    n.sort();
    assert_eq!(n, ["A", "A", "H", "V", "V"]);
    // Vertical edges of a prism: its four corners.
    let d = beams(
        "Lot --> extrude(3) comp(e) { vertical : V | all : O }",
        4.0,
        6.0,
    );
    assert_eq!(named(&d, "V").len(), 4);
    assert_eq!(named(&d, "O").len(), 8);
    for leaf in named(&d, "V") {
        assert!((leaf.scope.size.x - 3.0).abs() < 1e-9);
    }
}

#[test]
fn nutant_takes_faces_looking_down_at_a_slant() {
    // Seen from a scope turned upside down, the slopes of a hip roof (60° above the world's
    // horizon) are 60° below the scope's xz-plane; its bottom is horizontal either way.
    let d = run(
        "Lot --> roofHip(30) rotateScope(180, 0, 0) comp(f) { nutant : N. | aslant : A. | all : O. }",
        lot(10.0, 10.0),
    );
    assert_eq!(named(&d, "N").len(), 4);
    assert_eq!(named(&d, "A").len(), 0);
    assert_eq!(named(&d, "O").len(), 1);
}

#[test]
fn face_edges_are_one_shape_per_edge_of_each_face() {
    let d = beams("Lot --> comp(fe) { all : E }", 20.0, 30.0);
    let edges = named(&d, "E");
    assert_eq!(edges.len(), 4);
    let lengths: Vec<f64> = edges.iter().map(|l| l.scope.size.x).collect();
    assert_eq!(lengths, [20.0, 30.0, 20.0, 30.0]);
    // x along the edge from its first corner, y the face's normal (up), z out of the face.
    let first = edges[0];
    assert!(close(first.scope.axes.y_axis, DVec3::Y));
    assert!(close(
        first.scope.axes.z_axis,
        first
            .scope
            .axes
            .y_axis
            .cross(first.scope.axes.x_axis)
            .normalize()
            * -1.0
    ));
    assert!(close(first.scope.origin, DVec3::new(0.0, 0.0, 30.0)));
    // The first edge is the front: its outward direction classifies as front.
    let d = beams(
        "Lot --> comp(fe) { front : F | back : B | side : S }",
        20.0,
        30.0,
    );
    assert_eq!(names(&d), ["F", "B", "S", "S"]);
    // A box: 6 faces × 4 edges, shared edges once per face; the walls' top edges look up.
    let d = beams(
        "Lot --> extrude(10) comp(fe) { world.up : Up | all : O }",
        20.0,
        30.0,
    );
    assert_eq!(named(&d, "Up").len(), 4);
    assert_eq!(named(&d, "O").len(), 20);
    // Indices count face after face, edge after edge.
    let d = beams("Lot --> extrude(10) comp(fe) { 5 : Fifth }", 20.0, 30.0);
    assert_eq!(named(&d, "Fifth").len(), 1);
}

#[test]
fn face_selectors_in_a_setback_are_a_warning() {
    let errors = compile_errors("Lot --> setback(1) { nutant : A. }").join("\n");
    assert!(
        errors.contains("for faces, not the edges of a setback"),
        "{errors}"
    );
    let errors = compile_errors("Lot --> comp(f) { world.sideways : A. }").join("\n");
    assert!(
        errors.contains("this component selector is not supported yet"),
        "{errors}"
    );
}
