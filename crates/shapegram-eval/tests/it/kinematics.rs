//! Kinematic skeletons built while deriving (the Procedural Skeletons paper, §4.1): how
//! splits, components and the kinematic operations shape the skeleton, and what a pose does to
//! the model.

use crate::common;

use common::{lot, run, try_run};
use shapegram_eval::{Derivation, DeriveOptions};
use shapegram_geom::{DVec3, Model, kinematics::SectionId};
use shapegram_syntax::Span;

/// The rotating tower of Algorithm 1 in the main syntax: a basement and five floors of 3 m,
/// the joints on the tower's axis, each floor turned by `twist` against the one below.
const TOWER: &str = "attr twist = 0
@StartRule
Lot --> extrude(18.5) joint('0.5, 0, '0.5) split(y) { 3.5 : Basement | { ~3 : Floor }* }
Floor --> rotationLimits(y, -90, 90) rotateJoint(0, twist, 0) comp(f) { side : Facade | top : Slab. }
Facade --> split(x) { { ~2.5 : Pane. }* }
Basement --> Base.
";

/// Options that turn each floor of the tower by `twist` degrees.
fn twisted(twist: f64) -> DeriveOptions {
    DeriveOptions {
        attrs: vec![("twist".into(), shapegram_eval::Value::Number(twist))],
        ..DeriveOptions::default()
    }
}

fn tower(twist: f64) -> Derivation {
    try_run(TOWER, lot(20.0, 30.0), &twisted(twist)).unwrap()
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn the_floors_form_a_chain_with_joints_on_the_split_planes_and_the_axis() {
    let d = tower(0.0);
    assert_eq!(d.skeletons.len(), 1);
    let skeleton = &d.skeletons[0].1;
    assert!(skeleton.is_tree());
    // The chain: root (the lot, then the basement) and five floors, each the child of the one
    // below, joints at the centre of the footprint on the planes y = 3.5, 6.5, …
    let mut floor = skeleton.root();
    for k in 0..5 {
        let next = skeleton
            .children(floor)
            .find(|c| skeleton.section(*c).name().base() == "Floor")
            .unwrap_or_else(|| panic!("floor {k} has no successor"));
        let at = skeleton.section(next).rest().translation;
        assert!(
            close(at, DVec3::new(10.0, 3.5 + 3.0 * f64::from(k), 15.0)),
            "floor {k} at {at}"
        );
        floor = next;
    }
}

#[test]
fn turning_the_floors_turns_each_one_and_everything_above_it() {
    let d = tower(90.0);
    let model = d.to_model();
    let skeleton = &d.skeletons[0].1;
    let floors: Vec<SectionId> = {
        let mut chain = vec![skeleton.root()];
        while let Some(next) = skeleton
            .children(*chain.last().unwrap())
            .find(|c| skeleton.section(*c).name().base() == "Floor")
        {
            chain.push(next);
        }
        chain
    };
    assert_eq!(floors.len(), 6);
    // Floor k (k = 1…5) is turned by k · 90° about the vertical axis through (10, 15): odd
    // floors lie 30 m along x and 20 m along z, even ones as the lot does.
    for (k, &floor) in floors.iter().enumerate().skip(1) {
        let (min, max) = posed_bounds(&model, floor, skeleton);
        let size = max - min;
        let expected = if k % 2 == 1 {
            (30.0, 20.0)
        } else {
            (20.0, 30.0)
        };
        assert!(
            (size.x - expected.0).abs() < 1e-9 && (size.z - expected.1).abs() < 1e-9,
            "floor {k}: {size}"
        );
        assert!(close(
            (min + max) / 2.0 * DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(10.0, 0.0, 15.0)
        ));
    }
    // The basement does not move.
    let (min, max) = posed_bounds(&model, floors[0], skeleton);
    assert!(
        close(min, DVec3::ZERO) && close(max, DVec3::new(20.0, 3.5, 30.0)),
        "{min} {max}"
    );
}

/// The posed bounds of every part hanging from `section` or a section below it whose chain to
/// `section` passes no other floor (the floor's own facades and panes).
fn posed_bounds(
    model: &Model,
    section: SectionId,
    skeleton: &shapegram_geom::kinematics::Skeleton,
) -> (DVec3, DVec3) {
    let motions = skeleton.skinning();
    let owned = |mut s: SectionId| loop {
        if s == section {
            return true;
        }
        if skeleton.section(s).name().base() == "Floor" || s == skeleton.root() {
            return false;
        }
        match skeleton.section(s).parent() {
            Some(p) => s = p,
            None => return false,
        }
    };
    let mut min = DVec3::INFINITY;
    let mut max = DVec3::NEG_INFINITY;
    for part in &model.parts {
        let Some(bone) = part.bone else { continue };
        if !owned(bone.section) {
            continue;
        }
        let motion = motions[bone.section.index()];
        for &p in part.mesh.positions() {
            let q = motion.transform_point(p);
            min = min.min(q);
            max = max.max(q);
        }
    }
    (min, max)
}

#[test]
fn facade_splits_fork_from_the_floor_and_components_hang_from_their_shape() {
    let d = tower(0.0);
    let skeleton = &d.skeletons[0].1;
    let model = d.to_model();
    for part in model.parts.iter().filter(|p| p.name == "Glass") {
        let section = skeleton.section(part.bone.unwrap().section);
        // A pane's parent is its floor (a fork of the facade's parent), not the facade.
        let parent = skeleton.section(section.parent().unwrap());
        assert!(
            parent.name().base() == "Floor",
            "{} under {}",
            section.name(),
            parent.name()
        );
    }
    for part in model.parts.iter().filter(|p| p.name == "Slab") {
        let section = skeleton.section(part.bone.unwrap().section);
        assert!(section.name().base() == "Slab", "{}", section.name());
        // z along the slab's normal (up), joint at its centre.
        let rest = section.rest();
        assert!(close(rest.transform_vector(DVec3::Z), DVec3::Y));
        assert!(close(
            rest.translation * DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(10.0, 0.0, 15.0)
        ));
    }
}

#[test]
fn a_pose_outside_the_limits_is_an_error_at_the_operation() {
    let error = tower_error(120.0);
    assert_eq!(
        error.message,
        "the rotation about y of 120° is outside the joint's limits (-90° to 90°)"
    );
    let span = error.span.unwrap();
    assert_eq!(
        &TOWER[span.start as usize..span.end as usize],
        "rotateJoint(0, twist, 0)"
    );
}

fn tower_error(twist: f64) -> shapegram_eval::DeriveError {
    try_run(TOWER, lot(20.0, 30.0), &twisted(twist)).unwrap_err()
}

#[test]
fn a_parallel_split_of_the_root_is_an_error_with_its_span() {
    let text = "Lot --> extrude(3) split(x, parallel) { ~1 : A. }*";
    let error = try_run(text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    assert!(
        error
            .message
            .starts_with("a parallel split needs a shape with a kinematic parent")
    );
    let Span { start, end } = error.span.unwrap();
    assert!(text[start as usize..end as usize].starts_with("split(x, parallel)"));
}

#[test]
fn reversed_limits_are_an_error() {
    let text = "Lot --> rotationLimits(z, 10, -10) A.";
    let error = try_run(text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    assert_eq!(
        error.message,
        "the rotation limit about z runs from 10 to -10: the minimum must not exceed the maximum"
    );
}

#[test]
fn grammars_without_kinematic_operations_build_no_skeleton() {
    let d = run("Lot --> extrude(3) split(y) { ~1 : A. }*", lot(4.0, 4.0));
    assert!(d.skeletons.is_empty());
    assert!(d.to_model().parts.iter().all(|p| p.bone.is_none()));
}

#[test]
fn section_names_are_stable_and_unique_enough() {
    let a = tower(30.0);
    let b = tower(30.0);
    let names = |d: &Derivation| -> Vec<String> {
        d.skeletons[0]
            .1
            .sections()
            .map(|(_, s)| s.name().to_string())
            .collect()
    };
    assert_eq!(names(&a), names(&b));
    let mut unique = names(&a);
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), a.skeletons[0].1.len());
}

#[test]
fn the_twisting_tower_example_chains_its_floors_and_forks_its_facades() {
    let text = std::fs::read_to_string(common::examples().join("rotating_tower.cga")).unwrap();
    let d = run(&text, lot(20.0, 30.0));
    let skeleton = &d.skeletons[0].1;
    assert!(skeleton.is_tree());
    let model = d.to_model();
    // Every pane hangs from its storey's facade split (a fork from the storey).
    let panes: Vec<_> = model.parts.iter().filter(|p| p.name == "Glass").collect();
    assert!(!panes.is_empty());
    for pane in panes {
        let section = skeleton.section(pane.bone.unwrap().section);
        let parent = skeleton.section(section.parent().unwrap());
        assert!(
            parent.name().base() == "Storey",
            "{} under {}",
            section.name(),
            parent.name()
        );
    }
    // Twelve floors turned by 4° each: the top one by 48°.
    let floors: Vec<_> = skeleton
        .sections()
        .filter(|(_, s)| s.name().base() == "Floor")
        .map(|(id, _)| id)
        .collect();
    assert_eq!(floors.len(), 12);
    let posed = skeleton.posed();
    let top = floors
        .iter()
        .max_by(|a, b| {
            let y = |s: &SectionId| skeleton.section(*s).rest().translation.y;
            y(a).total_cmp(&y(b))
        })
        .unwrap();
    let x = posed[top.index()].transform_vector(DVec3::X);
    assert!(((-x.z).atan2(x.x).to_degrees() - 48.0).abs() < 1e-9);
}

/// Generated grammars (see `common::generated`).
mod generated {
    use proptest::prelude::*;

    use super::*;
    use common::generated::{body, grammar};

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// Whatever the grammar, the sections form one rooted tree (Lemmas 4.1–4.2, Corollary
        /// 4.3), every leaf hangs from one of them, and the pose moves leaves rigidly; the only
        /// error is a parallel split where the paper forbids one.
        #[test]
        fn any_grammar_builds_one_rooted_tree(bodies in prop::collection::vec(body(), 1..7)) {
            let text = format!("{}R_unused --> rotateJoint(0, 0, 0) Leaf.\n", grammar(&bodies));
            let options = DeriveOptions { max_shapes: 20_000, ..DeriveOptions::default() };
            match try_run(&text, lot(8.0, 6.0), &options) {
                Err(e) => prop_assert!(
                    e.message.starts_with("a parallel split needs"),
                    "{}\n{text}", e.message
                ),
                Ok(d) => {
                    prop_assert_eq!(d.skeletons.len(), 1);
                    let skeleton = &d.skeletons[0].1;
                    prop_assert!(skeleton.is_tree(), "{text}");
                    for leaf in &d.leaves {
                        prop_assert!((leaf.section() as usize) < skeleton.len());
                    }
                    for frame in skeleton.posed() {
                        prop_assert!(frame.is_finite());
                    }
                }
            }
        }
    }
}

#[test]
fn a_posed_part_keeps_its_pose_when_split_further() {
    // The sash turns on its hinge and is then split into glass and frame: both must turn.
    let text = "attr open = 90
Lot --> extrude(3) comp(f) { front : Window }
Window --> joint(0, 0, 0) rotationLimits(y, 0, 100) rotateJoint(0, open, 0)
           split(x) { 0.2 : Frame. | ~1 : Glass. | 0.2 : Frame. }";
    let d = run(text, lot(4.0, 4.0));
    let skeleton = &d.skeletons[0].1;
    let motions = skeleton.skinning();
    for leaf in &d.leaves {
        let motion = motions[leaf.section() as usize];
        let corner = leaf.scope.to_world(DVec3::new(leaf.scope.size.x, 0.0, 0.0));
        assert!(
            !close(motion.transform_point(corner), corner),
            "{} does not swing with the sash",
            d.name(leaf.name)
        );
    }
}

#[test]
fn limits_that_leave_out_the_rest_pose_start_the_joint_at_the_nearest_limit() {
    let text = "Lot --> extrude(3) rotationLimits(z, -160, -30) Stick.";
    let d = run(text, lot(4.0, 4.0));
    let root = d.skeletons[0].1.section(SectionId(0));
    assert_eq!(root.pose().rotation.z, -30.0);
    // A pose the grammar set is not moved by later limits: that is an error.
    let text =
        "Lot --> rotationLimits(z, -90, 90) rotateJoint(0, 0, 60) rotationLimits(z, -45, 45) A.";
    let error = try_run(text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    assert_eq!(
        error.message,
        "the joint's pose leaves the new limits: the rotation about z of 60° is outside the joint's limits (-45° to 45°)"
    );
}

#[test]
fn skeletons_are_the_same_whatever_the_thread_count() {
    let program = common::compile(TOWER);
    let lots = common::lots_in_a_row(12, 20.0, 30.0, 30.0);
    let options = twisted(20.0);
    let with = |threads| common::derive_on_threads(&program, &lots, &options, threads);
    let (one, four) = (with(1), with(4));
    assert_eq!(one.skeletons.len(), 12);
    assert_eq!(one.skeletons, four.skeletons);
    let sections = |d: &Derivation| {
        d.leaves
            .iter()
            .map(|l| (l.lot, l.section()))
            .collect::<Vec<_>>()
    };
    assert_eq!(sections(&one), sections(&four));
}

#[test]
fn any_node_of_the_derivation_tree_can_be_shown_posed() {
    let options = DeriveOptions {
        keep_tree: true,
        ..twisted(90.0)
    };
    let d = try_run(TOWER, lot(20.0, 30.0), &options).unwrap();
    // The nodes of the floors' sections (a shape is entered in the tree at each operation that
    // makes a new one, named after the rule it came from): one node per floor section, bottom
    // to top. Each turns by 90° more than the one below: the centre of its scope stays on the
    // axis, its +x side swings about it.
    let skeleton = &d.skeletons[0].1;
    let mut floors: Vec<usize> = (0..d.tree.len())
        .filter(|&n| skeleton.section(SectionId(d.tree[n].section)).name().base() == "Floor")
        .collect();
    floors.sort_by_key(|&n| d.tree[n].section);
    floors.dedup_by_key(|n| d.tree[*n].section);
    assert_eq!(floors.len(), 5);
    for (k, &node) in floors.iter().enumerate() {
        let motion = d.node_motion(node).unwrap();
        let scope = d.tree[node].scope;
        let centre = scope.center();
        assert!(close(motion.transform_point(centre), centre));
        let corner = scope.to_world(DVec3::new(scope.size.x, 0.0, scope.size.z * 0.5));
        let turned = motion.transform_point(corner) - centre;
        let expected = [DVec3::new(0.0, 0.0, -10.0), DVec3::new(-10.0, 0.0, 0.0)];
        let want = match (k + 1) % 4 {
            1 => expected[0],
            2 => expected[1],
            3 => -expected[0],
            _ => -expected[1],
        };
        let (got, want) = (turned * DVec3::new(1.0, 0.0, 1.0), want);
        assert!(close(got, want), "floor {k}: {got} instead of {want}");
    }
    assert_eq!(d.node_motion(d.tree.len()), None);
}

/// A door of a storey and a probe beside it: both hang from the storey's parent (a fork), so
/// each turns on its own joint.
const DOOR_AND_PROBE: &str = "attr open = 0
attr turn = 0
Lot --> extrude(3) split(y, sequential) { 0.1 : Floor. | ~1 : Storey }
Storey --> split(x, parallel) { 1 : Door | 1 : Probe | ~1 : Rest. }
Door --> joint('1, 0, '0.5) rotationLimits(y, -180, 180) rotateJoint(0, open, 0)
         label(\"door\") Slab.
Probe --> joint('0, 0, '0.5) rotationLimits(y, -180, 180) rotateJoint(0, turn, 0) Check
Check --> case overlaps(all, \"door\") : Hit.
          case touches(all, \"door\") : Beside.
          else : Clear.
";

/// The leaf that the probe became.
fn probe_result(open: f64, turn: f64) -> String {
    let options = DeriveOptions {
        attrs: vec![
            ("open".into(), shapegram_eval::Value::Number(open)),
            ("turn".into(), shapegram_eval::Value::Number(turn)),
        ],
        ..DeriveOptions::default()
    };
    let d = try_run(DOOR_AND_PROBE, lot(4.0, 2.0), &options).unwrap();
    let results: Vec<&str> = d
        .leaves
        .iter()
        .map(|l| d.name(l.name))
        .filter(|n| ["Hit", "Beside", "Clear"].contains(n))
        .collect();
    assert_eq!(results.len(), 1, "{results:?}");
    results[0].to_owned()
}

#[test]
fn occlusion_queries_see_occluders_where_the_pose_puts_them() {
    // At rest the door (x 0–1) only touches the probe (x 1–2); turned 180° about its joint on
    // its right edge it lies where the probe is; turned 90° it stands across the probe's half.
    assert_eq!(probe_result(0.0, 0.0), "Beside");
    assert_eq!(probe_result(180.0, 0.0), "Hit");
    assert_eq!(probe_result(-90.0, 0.0), "Hit");
}

#[test]
fn occlusion_queries_place_the_asking_shape_by_its_pose() {
    // The probe turned 180° about its joint on its left edge lies where the door is.
    assert_eq!(probe_result(0.0, 180.0), "Hit");
    // Turned by both, the two swap places and still meet along x = 1.
    assert_eq!(probe_result(180.0, 180.0), "Beside");
}

#[test]
fn snapping_splits_snap_to_lines_where_the_pose_puts_them() {
    // The marker's snap lines (x = 0 and 1 at rest) move with its joint by 2.5 m along x; the
    // wall splits in 1 m parts, of which the boundary nearest each line moves onto it.
    let text = "attr shift = 2.5
Lot --> extrude(3) split(y, sequential) { 0.1 : Floor. | ~1 : Storey }
Storey --> split(z, parallel) { 1 : Marker | ~1 : Wall }
Marker --> s(1, '1, '1) translationLimits(x, 0, 5) translateJoint(shift, 0, 0) snap(x) Post.
Wall --> split(x, snap) { { ~1 : Part. }* }
";
    let cuts = |shift: f64| {
        let options = DeriveOptions {
            attrs: vec![("shift".into(), shapegram_eval::Value::Number(shift))],
            ..DeriveOptions::default()
        };
        let d = try_run(text, lot(8.0, 3.0), &options).unwrap();
        let mut xs: Vec<f64> = d
            .leaves
            .iter()
            .filter(|l| d.name(l.name) == "Part")
            .map(|l| (l.scope.origin.x * 1e6).round() / 1e6)
            .collect();
        xs.sort_by(f64::total_cmp);
        xs
    };
    let at_rest = cuts(0.0);
    let shifted = cuts(2.5);
    assert!(at_rest.contains(&1.0), "{at_rest:?}");
    assert!(
        shifted.contains(&2.5) && shifted.contains(&3.5),
        "{shifted:?}"
    );
    assert!(!shifted.contains(&1.0), "{shifted:?}");
}

#[test]
fn posed_occlusion_is_the_same_whatever_the_thread_count() {
    let program = common::compile(DOOR_AND_PROBE);
    // Lots side by side, so that doors of one lot also meet the probes of the next.
    let lots = common::lots_in_a_row(9, 4.0, 2.0, 4.0);
    let options = DeriveOptions {
        attrs: vec![("open".into(), shapegram_eval::Value::Number(-90.0))],
        ..DeriveOptions::default()
    };
    let with = |threads| common::derive_on_threads(&program, &lots, &options, threads);
    let (one, four) = (with(1), with(4));
    assert_eq!(one.leaves, four.leaves);
    assert_eq!(one.skeletons, four.skeletons);
    // Skeletons come by lot, though the lots with waiting shapes finish in phase 2.
    let lots: Vec<u32> = one.skeletons.iter().map(|(lot, _)| *lot).collect();
    assert_eq!(lots, (0..9).collect::<Vec<_>>());
    assert_eq!(
        common::names(&one).iter().filter(|n| **n == "Hit").count(),
        9
    );
}

#[test]
fn a_joint_may_lie_outside_the_shape_but_must_be_a_number() {
    // A hinge 2 m beside the leaf: allowed, the leaf swings about it.
    let text = "Lot --> extrude(2) s(1, '1, 0.1) Leaf
Leaf --> joint(3, 0, 0) rotationLimits(y, -90, 90) rotateJoint(0, 90, 0) Panel.";
    let d = run(text, lot(4.0, 4.0));
    let skeleton = &d.skeletons[0].1;
    let section = shapegram_geom::kinematics::SectionId(d.leaves[0].section());
    let joint = skeleton.section(section).rest().translation;
    assert!(
        (joint.x - 3.0).abs() < 1e-12 && joint.y.abs() < 1e-12,
        "{joint}"
    );
    let motion = skeleton.motion(section).unwrap();
    // The leaf's origin corner, 3 m from the hinge, swings a quarter turn about it.
    let corner = motion.transform_point(d.leaves[0].scope.origin);
    assert!(
        (corner - DVec3::new(3.0, 0.0, 3.0)).length() < 1e-9,
        "{corner}"
    );
    // A position that is not a number is an error at the operation.
    let text = "Lot --> extrude(2) Leaf\nLeaf --> joint(0 / 0, 0, 0) Panel.";
    let error = try_run(text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    assert!(error.span.is_some(), "{}", error.message);
}
