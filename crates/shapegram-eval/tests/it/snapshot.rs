//! Visual debugging (§4.3 of "Procedural Skeletons"): the model of the derivation as it stood at
//! a node of the derivation tree, posed like the finished model.

use crate::common;

use common::{lot, run, try_run};
use shapegram_eval::{Derivation, DeriveOptions, Value};
use shapegram_geom::{Color, DVec3, Model};

/// A wall and a door hinged on its left edge, opened by `open` degrees about y, then split
/// into a panel and a lintel that is rewritten once more. On a 3 × 4 lot the wall spans
/// x ∈ [0, 1] and the door x ∈ [1, 3]; both are 3 high and 4 deep.
const DOOR: &str = "attr open = 90
Lot --> extrude(3) split(x) { 1 : Wall. | ~1 : Door }
Door --> joint(0, 0, 0) rotationLimits(y, 0, 100) rotateJoint(0, open, 0)
         split(y) { ~1 : Panel. | 0.5 : Lintel }
Lintel --> color(\"#ff0000\") Beam.
";

fn door(open: f64) -> Derivation {
    let options = DeriveOptions {
        keep_tree: true,
        attrs: vec![("open".into(), Value::Number(open))],
        ..DeriveOptions::default()
    };
    try_run(DOOR, lot(3.0, 4.0), &options).unwrap()
}

/// Each part's name, section and rest bounds.
fn parts(model: &Model) -> Vec<(&str, Option<u32>, [DVec3; 2])> {
    model
        .parts
        .iter()
        .map(|p| {
            let b = p.mesh.bounds().unwrap();
            (p.name.as_str(), p.bone.map(|b| b.section.0), [b.min, b.max])
        })
        .collect()
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

#[test]
fn the_state_at_a_node_is_the_shapes_made_so_far_without_children() {
    let d = door(90.0);
    // The tree: a split part is a node named after the shape split, its successor another.
    let tree: Vec<(&str, Option<u32>)> = d.tree.iter().map(|n| (&*n.name, n.parent)).collect();
    assert_eq!(
        tree,
        [
            ("Lot", None),
            ("Lot", Some(0)),
            ("Wall", Some(1)),
            ("Lot", Some(0)),
            ("Door", Some(3)),
            ("Door", Some(4)),
            ("Panel", Some(5)),
            ("Door", Some(4)),
            ("Lintel", Some(7)),
            ("Beam", Some(8)),
        ]
    );
    let wall = ("Wall", Some(0), [v(0.0, 0.0, 0.0), v(1.0, 3.0, 4.0)]);
    let panel = ("Panel", Some(1), [v(1.0, 0.0, 0.0), v(3.0, 2.5, 4.0)]);
    let top = [v(1.0, 2.5, 0.0), v(3.0, 3.0, 4.0)];

    // The lot: its flat scope, a rectangle at y = 0.
    let at_0 = d.model_at_node(0).unwrap();
    assert_eq!(
        parts(&at_0),
        [("Lot", Some(0), [v(0.0, 0.0, 0.0), v(3.0, 0.0, 4.0)])]
    );
    assert_eq!(at_0.parts[0].mesh.face_count(), 1);
    assert_eq!(at_0.parts[0].mesh.vertex_count(), 4);
    // The root split's parts are made and named: the wall (a leaf) and the door's box at birth.
    assert_eq!(
        parts(&d.model_at_node(4).unwrap()),
        [
            wall,
            ("Door", Some(1), [v(1.0, 0.0, 0.0), v(3.0, 3.0, 4.0)])
        ]
    );
    // The door's split has made both its parts: the panel (a leaf) and the upper part, not
    // yet named; the door itself is gone (it has children).
    assert_eq!(
        parts(&d.model_at_node(7).unwrap()),
        [wall, panel, ("Door", Some(2), top)]
    );
    // The upper part named: the lintel, rewritten later, as its box in the colour of
    // uncoloured shapes (the red it gets comes after its birth).
    let at_8 = d.model_at_node(8).unwrap();
    assert_eq!(parts(&at_8), [wall, panel, ("Lintel", Some(2), top)]);
    assert_eq!(at_8.parts[2].color, Color::default());
    assert_eq!(at_8.parts[2].mesh.face_count(), 6);
    // The last node: exactly the model's leaves.
    let last = d.model_at_node(9).unwrap();
    assert_eq!(parts(&last), [wall, panel, ("Beam", Some(2), top)]);
    assert_eq!(last.parts[2].color, Color::from_hex("#ff0000").unwrap());
    assert_eq!(last.skeletons, d.to_model().skeletons);
    assert_eq!(last.merged_mesh().area(), d.to_model().merged_mesh().area());
}

#[test]
fn a_state_is_posed_by_the_joints_of_its_shapes() {
    let d = door(90.0);
    // The door turns by 90° about y through its hinge at (1, 0, 0): (x, y, z) goes to
    // (1 + z, y, 1 − x). The wall stays.
    let turn = |p: DVec3| v(1.0 + p.z, p.y, 1.0 - p.x);
    for node in [4, 7, 8, 9] {
        let rest = d.model_at_node(node).unwrap();
        let posed = rest.posed();
        assert!(posed.skeletons.is_empty());
        for (r, p) in rest.parts.iter().zip(&posed.parts) {
            let moves = r.name != "Wall";
            for (a, b) in r.mesh.positions().iter().zip(p.mesh.positions()) {
                let want = if moves { turn(*a) } else { *a };
                assert!(
                    (*b - want).length() < 1e-12,
                    "node {node}: {} {a} to {b}",
                    r.name
                );
            }
        }
        // The same motion as the node's own, from its birth snapshot.
        let motion = d.node_motion(node).unwrap();
        let corner = d.tree[node].scope.to_world(d.tree[node].scope.size);
        assert!((motion.transform_point(corner) - turn(corner)).length() < 1e-12);
    }
    // What a file without skins holds (STL): the posed state, in f32. Closed, the door stays
    // within the lot; open, it reaches 4 m along x and 2 m behind the lot's front.
    let stl_bounds = |d: &Derivation, node: usize| {
        let bytes = shapegram_export::write_stl(&d.model_at_node(node).unwrap());
        let b = shapegram_export::read_stl(&bytes)
            .unwrap()
            .bounds()
            .unwrap();
        [b.min, b.max]
    };
    let close = |got: [DVec3; 2], want: [DVec3; 2]| {
        assert!(
            (got[0] - want[0]).length() < 1e-6 && (got[1] - want[1]).length() < 1e-6,
            "{got:?} instead of {want:?}"
        );
    };
    close(stl_bounds(&d, 8), [v(0.0, 0.0, -2.0), v(5.0, 3.0, 4.0)]);
    close(
        stl_bounds(&door(0.0), 8),
        [v(0.0, 0.0, 0.0), v(3.0, 3.0, 4.0)],
    );
}

#[test]
fn later_lots_start_after_earlier_ones_and_deleted_shapes_are_left_out() {
    let text = "Lot --> extrude(2) split(x) { 1 : Block. | 1 : Gone }\nGone --> NIL\n";
    let program = common::compile(text);
    let lots = [lot(2.0, 2.0), lot(2.0, 2.0)];
    let options = DeriveOptions {
        keep_tree: true,
        ..DeriveOptions::default()
    };
    let d = shapegram_eval::derive(&program, &lots, &options).unwrap();
    // Per lot: the lot, two parts and their successors Block and Gone.
    assert_eq!(d.tree.len(), 10);
    let names = |node: usize| -> Vec<String> {
        let model = d.model_at_node(node).unwrap();
        assert!(model.parts.iter().all(|p| p.bone.is_none()));
        model.parts.iter().map(|p| p.name.clone()).collect()
    };
    assert_eq!(names(3), ["Block", "Lot"]);
    // `Gone` made nothing, and the tree cannot say when it was deleted: never shown.
    assert_eq!(names(4), ["Block"]);
    // The second lot starts: the first is there whole.
    assert_eq!(names(5), ["Block", "Lot"]);
    assert_eq!(names(9), ["Block", "Block"]);
}

#[test]
fn a_state_needs_the_tree_and_a_node_in_it() {
    let error = run(DOOR, lot(3.0, 4.0)).model_at_node(0).unwrap_err();
    assert_eq!(error.message, "the derivation kept no tree");
    assert_eq!(error.hints, ["derive with `DeriveOptions::keep_tree` set"]);
    let error = door(90.0).model_at_node(10).unwrap_err();
    assert_eq!(
        error.message,
        "there is no node 10: the derivation tree has 10 nodes (0 to 9)"
    );
}
