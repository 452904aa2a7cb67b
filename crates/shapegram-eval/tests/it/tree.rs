//! What the derivation tree keeps for visual debugging: the rule applied to each shape, its
//! attribute values at birth, and where each leaf's faces went in the model.

use crate::common;

use common::{lot, try_run};
use shapegram_eval::{DeriveOptions, LeafFaces, Value};

/// A block split in three; the middle part sets `h` before its successor.
const BLOCKS: &str = "attr h = 6
Lot --> extrude(h) Mass
Mass --> split(x) { 5 : Red | ~1 : Blue | 5 : Red }
Red --> color(\"#ff0000\")
Blue --> set(h, 2) color(\"#0000ff\") Top
Top --> comp(f) { top : Lid | bottom : NIL }
";

fn tree_kept() -> DeriveOptions {
    DeriveOptions {
        keep_tree: true,
        ..DeriveOptions::default()
    }
}

#[test]
fn nodes_keep_their_rule_and_attribute_values() {
    let d = try_run(BLOCKS, lot(20.0, 30.0), &tree_kept()).unwrap();
    let nodes: Vec<(&str, Option<u32>, Vec<Value>)> = d
        .tree
        .iter()
        .map(|n| (&*n.name, n.rule, n.attrs.to_vec()))
        .collect();
    let (six, two) = (vec![Value::Number(6.0)], vec![Value::Number(2.0)]);
    assert_eq!(
        nodes,
        [
            ("Lot", Some(0), six.clone()),
            ("Mass", Some(1), six.clone()),
            // A split's part is named after the shape split; no rule rewrites it.
            ("Mass", None, six.clone()),
            ("Red", Some(2), six.clone()),
            ("Mass", None, six.clone()),
            ("Blue", Some(3), six.clone()),
            ("Mass", None, six.clone()),
            ("Red", Some(2), six.clone()),
            ("Top", Some(4), two.clone()),
            // The components of `comp` are named after the shape; the top one's successor Lid
            // has no rule, the bottom one (NIL) no successor.
            ("Top", None, two.clone()),
            ("Lid", None, two.clone()),
            ("Top", None, two),
        ]
    );
    // Unchanged values are one list, shared.
    assert!(std::sync::Arc::ptr_eq(&d.tree[0].attrs, &d.tree[7].attrs));
    assert!(std::sync::Arc::ptr_eq(&d.tree[8].attrs, &d.tree[9].attrs));
}

#[test]
fn the_model_says_where_each_leaf_went() {
    let d = try_run(BLOCKS, lot(20.0, 30.0), &tree_kept()).unwrap();
    let (model, faces) = d.to_model_with_faces();
    assert_eq!(model, d.to_model());
    // Parts by (symbol, colour): both red blocks in part 0 (6 faces each), the lid in part 1
    // (the bottom is NIL).
    let names: Vec<&str> = model.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["Red", "Lid"]);
    assert_eq!(
        faces,
        [
            LeafFaces {
                leaf: 0,
                part: 0,
                first: 0,
                count: 6
            },
            LeafFaces {
                leaf: 1,
                part: 1,
                first: 0,
                count: 1
            },
            LeafFaces {
                leaf: 2,
                part: 0,
                first: 6,
                count: 6
            },
        ]
    );
    let nodes: Vec<Option<u32>> = d.leaves.iter().map(|l| l.node()).collect();
    assert_eq!(nodes, [Some(3), Some(10), Some(7)]);
}

#[test]
fn without_the_tree_nothing_is_kept() {
    let d = try_run(BLOCKS, lot(20.0, 30.0), &DeriveOptions::default()).unwrap();
    assert!(d.tree.is_empty());
    assert!(d.leaves.iter().all(|l| l.node().is_none()));
}
