//! The skeleton's operations as the paper defines them, and its invariants under any sequence
//! of them (Lemmas 4.1–4.2, Corollary 4.3, Theorem 4.9).

use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use shapegram_kinematics::{Frame, KinematicError, Limits, Pose, Range, SectionId, Skeleton};

fn at(x: f64, y: f64, z: f64) -> Frame {
    Frame::from_translation(DVec3::new(x, y, z))
}

fn named(frames: impl IntoIterator<Item = Frame>) -> Vec<(Frame, String)> {
    frames
        .into_iter()
        .enumerate()
        .map(|(i, f)| (f, format!("s{i}")))
        .collect()
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

/// A point attached to `section`, moved from the rest pose into the current pose.
fn posed(skeleton: &Skeleton, section: SectionId, point: DVec3) -> DVec3 {
    skeleton.skinning()[section.index()].transform_point(point)
}

fn free_yaw() -> Limits {
    let mut limits = Limits::default();
    limits.rotation[1] = Range::new(-180.0, 180.0);
    limits
}

fn yaw(degrees: f64) -> Pose {
    Pose {
        rotation: DVec3::new(0.0, degrees, 0.0),
        translation: DVec3::ZERO,
    }
}

/// The rotating tower of Algorithm 1: a basement and five floors of 3 m, split sequentially
/// upwards, each floor's joint on the plane under it.
fn tower() -> (Skeleton, Vec<SectionId>) {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Building");
    let planes = (1..=5).map(|k| at(0.0, 0.5 + 3.0 * f64::from(k - 1), 0.0));
    let floors = skeleton.sequential(skeleton.root(), named(planes)).to_vec();
    (skeleton, floors)
}

#[test]
fn a_sequential_split_puts_the_joints_on_the_split_planes() {
    let (skeleton, floors) = tower();
    assert_eq!(floors.len(), 6);
    assert_eq!(floors[0], skeleton.root());
    for (k, pair) in floors.windows(2).enumerate() {
        assert_eq!(skeleton.section(pair[1]).parent(), Some(pair[0]));
        let joint = skeleton.joint(pair[1]);
        let expected = if k == 0 { 0.5 } else { 3.0 };
        assert!(
            close(joint.translation, DVec3::new(0.0, expected, 0.0)),
            "{joint:?}"
        );
    }
    assert!(skeleton.is_tree());
}

#[test]
fn turning_floor_k_moves_the_floors_above_and_not_those_below() {
    let (mut skeleton, floors) = tower();
    let k = 3;
    skeleton.set_limits(floors[k], free_yaw()).unwrap();
    assert!(skeleton.set_pose(floors[k], yaw(90.0)).unwrap().is_empty());
    // A corner of each floor, 2 m from the tower's axis along x, 1 m above the floor's plane.
    for (i, &floor) in floors.iter().enumerate() {
        let y = if i == 0 {
            0.25
        } else {
            1.5 + 3.0 * (i - 1) as f64
        };
        let corner = DVec3::new(2.0, y, 0.0);
        let moved = posed(&skeleton, floor, corner);
        if i < k {
            assert!(close(moved, corner), "floor {i} moved to {moved}");
        } else {
            // 90° about y takes +x to −z.
            assert!(
                close(moved, DVec3::new(0.0, y, -2.0)),
                "floor {i} at {moved}"
            );
        }
    }
}

#[test]
fn a_sequential_split_hands_the_children_to_the_last_part_without_moving_them() {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Arm");
    let hand = skeleton.add_child(skeleton.root(), at(0.0, 10.0, 0.0), "Hand");
    let parts = skeleton
        .sequential(
            skeleton.root(),
            named([at(0.0, 4.0, 0.0), at(0.0, 7.0, 0.0)]),
        )
        .to_vec();
    assert_eq!(skeleton.section(hand).parent(), Some(parts[2]));
    assert_eq!(skeleton.children(parts[2]).collect::<Vec<_>>(), [hand]);
    assert_eq!(
        skeleton.children(skeleton.root()).collect::<Vec<_>>(),
        [parts[1]]
    );
    assert!(close(
        skeleton.joint(hand).translation,
        DVec3::new(0.0, 3.0, 0.0)
    ));
    assert!(close(
        posed(&skeleton, hand, DVec3::new(1.0, 11.0, 0.0)),
        DVec3::new(1.0, 11.0, 0.0)
    ));
    assert!(skeleton.is_tree());
}

#[test]
fn a_parallel_split_forks_from_the_parent_and_refuses_the_root_and_sections_with_children() {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Body");
    assert_eq!(
        skeleton.parallel(skeleton.root(), named([at(0.0, 0.0, 0.0)])),
        Err(KinematicError::ParallelAtRoot)
    );
    let palm = skeleton.add_child(skeleton.root(), at(0.0, 1.0, 0.0), "Palm");
    let fingers = skeleton
        .parallel(
            palm,
            named((0..4).map(|i| at(f64::from(i) * 0.02, 1.1, 0.0))),
        )
        .unwrap()
        .to_vec();
    assert_eq!(fingers.len(), 4);
    assert!(
        fingers
            .iter()
            .all(|f| skeleton.section(*f).parent() == Some(skeleton.root()))
    );
    assert_eq!(
        skeleton.parallel(skeleton.root(), named([Frame::IDENTITY])),
        Err(KinematicError::ParallelAtRoot)
    );
    let wrist = skeleton.add_child(skeleton.root(), at(0.0, 0.9, 0.0), "Wrist");
    skeleton.add_child(wrist, at(0.0, 0.95, 0.0), "Thumb");
    assert_eq!(
        skeleton.parallel(wrist, named([Frame::IDENTITY])),
        Err(KinematicError::ParallelWithChildren)
    );
    assert_eq!(
        KinematicError::ParallelWithChildren.to_string(),
        "a parallel split needs a shape without kinematic children, and this shape has some: split sequentially"
    );
}

#[test]
fn components_hang_from_the_original_with_z_along_their_normals() {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Box");
    // The top face of a 2 m cube: centre (1, 2, 1), normal +y.
    let top = Frame::from_axes(
        DVec3::new(1.0, 2.0, 1.0),
        DMat3::from_cols(DVec3::X, DVec3::NEG_Z, DVec3::Y),
    );
    let faces = skeleton
        .components(skeleton.root(), vec![(top, "Top")])
        .to_vec();
    let joint = skeleton.joint(faces[0]);
    assert!(close(joint.transform_vector(DVec3::Z), DVec3::Y));
    assert!(close(joint.translation, DVec3::new(1.0, 2.0, 1.0)));
}

#[test]
fn placing_a_joint_moves_the_pivot_and_nothing_else() {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Door frame");
    let door = skeleton.add_child(skeleton.root(), at(0.5, 1.0, 0.0), "Door");
    let handle = skeleton.add_child(door, at(0.9, 1.0, 0.0), "Handle");
    // The hinge: the door's left edge.
    skeleton.place_joint(door, at(0.0, 1.0, 0.0));
    assert!(close(
        posed(&skeleton, handle, DVec3::new(0.9, 1.0, 0.0)),
        DVec3::new(0.9, 1.0, 0.0)
    ));
    skeleton.set_limits(door, free_yaw()).unwrap();
    skeleton.set_pose(door, yaw(90.0)).unwrap();
    // The handle swings about the hinge at x = 0: 0.9 m along +x becomes 0.9 m along −z.
    assert!(close(
        posed(&skeleton, handle, DVec3::new(0.9, 1.0, 0.0)),
        DVec3::new(0.0, 1.0, -0.9)
    ));
}

#[test]
fn poses_outside_the_limits_are_clamped_and_reported() {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Base");
    let arm = skeleton.add_child(skeleton.root(), Frame::IDENTITY, "Arm");
    let mut limits = Limits::default();
    limits.rotation[2] = Range::new(-45.0, 45.0);
    skeleton.set_limits(arm, limits).unwrap();
    let clamped = skeleton
        .set_pose(
            arm,
            Pose {
                rotation: DVec3::new(0.0, 0.0, 60.0),
                translation: DVec3::ZERO,
            },
        )
        .unwrap();
    assert_eq!(clamped.len(), 1);
    assert_eq!(skeleton.section(arm).pose().rotation.z, 45.0);
    assert!(
        skeleton
            .set_pose(
                arm,
                Pose {
                    rotation: DVec3::new(f64::NAN, 0.0, 0.0),
                    translation: DVec3::ZERO
                }
            )
            .is_err()
    );
    assert_eq!(
        skeleton.section(arm).pose().rotation.z,
        45.0,
        "a refused pose changes nothing"
    );
    let outside = Pose {
        rotation: DVec3::new(0.0, 0.0, -50.0),
        translation: DVec3::ZERO,
    };
    assert_eq!(
        skeleton.pose_within(arm, outside).unwrap_err().to_string(),
        "the rotation about z of -50° is outside the joint's limits (-45° to 45°)"
    );
    assert_eq!(skeleton.section(arm).pose().rotation.z, 45.0);
    assert_eq!(skeleton.find("Arm"), Some(arm));
    assert_eq!(skeleton.find("Leg"), None);
}

/// One rule application on a random section.
#[derive(Clone, Debug)]
enum Step {
    Components(usize, u8),
    Sequential(usize, u8),
    Parallel(usize, u8),
    Place(usize),
    Pose(usize, f64),
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        (any::<usize>(), 1..4u8).prop_map(|(s, n)| Step::Components(s, n)),
        (any::<usize>(), 1..4u8).prop_map(|(s, n)| Step::Sequential(s, n)),
        (any::<usize>(), 1..4u8).prop_map(|(s, n)| Step::Parallel(s, n)),
        any::<usize>().prop_map(Step::Place),
        (any::<usize>(), -90.0..90.0f64).prop_map(|(s, a)| Step::Pose(s, a)),
    ]
}

fn frames(seed: usize, n: u8) -> Vec<(Frame, String)> {
    (0..n)
        .map(|i| {
            let t = (seed % 97) as f64 + f64::from(i);
            let rotation = DQuat::from_rotation_x(t * 0.1) * DQuat::from_rotation_y(t * 0.2);
            (
                Frame {
                    rotation,
                    translation: DVec3::new(t, 2.0 * t, -t),
                },
                format!("p{i}"),
            )
        })
        .collect()
}

proptest! {
    #[test]
    fn any_derivation_keeps_one_rooted_tree_and_joints_fixed_after_birth(steps in prop::collection::vec(step(), 1..40)) {
        let mut skeleton = Skeleton::new(Frame::IDENTITY, "Root");
        let mut births: Vec<Frame> = vec![Frame::IDENTITY];
        for step in steps {
            let pick = |s: usize| SectionId((s % skeleton.len()) as u32);
            match step {
                Step::Components(s, n) => { skeleton.components(pick(s), frames(s, n)); }
                Step::Sequential(s, n) => { skeleton.sequential(pick(s), frames(s, n)); }
                Step::Parallel(s, n) => {
                    let id = pick(s);
                    let section = skeleton.section(id);
                    let allowed = section.parent().is_some() && !section.has_children();
                    prop_assert_eq!(skeleton.parallel(id, frames(s, n)).is_ok(), allowed);
                }
                Step::Place(s) => {
                    let id = pick(s);
                    skeleton.place_joint(id, frames(s, 1)[0].0);
                    births[id.index()] = skeleton.section(id).rest();
                }
                Step::Pose(s, a) => {
                    let id = pick(s);
                    skeleton.set_limits(id, free_yaw()).unwrap();
                    skeleton.set_pose(id, yaw(a)).unwrap();
                }
            }
            births.extend(skeleton.sections().skip(births.len()).map(|(_, s)| s.rest()));
            prop_assert!(skeleton.is_tree());
        }
        // Joints never change after birth (Theorem 4.9): only links do.
        for (id, section) in skeleton.sections() {
            prop_assert_eq!(section.rest(), births[id.index()]);
        }
        // In the rest pose nothing moves.
        let mut rest = skeleton.clone();
        let ids: Vec<SectionId> = rest.sections().map(|(id, _)| id).collect();
        for id in ids { rest.set_pose(id, Pose::default()).unwrap(); }
        let p = DVec3::new(1.0, 2.0, 3.0);
        for motion in rest.skinning() {
            prop_assert!(close(motion.transform_point(p), p));
        }
    }
}

proptest! {
    /// Theorem 4.4: rules applied only to a shape and what it derives leave the subtree linked
    /// to the rest of the skeleton exactly as the shape was: only by its parent (the shape's
    /// own section, or that section's parent for a fork) and, at one section only (Corollary
    /// 4.6), by its children.
    #[test]
    fn an_isolated_subtree_links_out_only_as_its_root_did(
        steps in prop::collection::vec(step(), 1..30),
        children in 0..3u8,
    ) {
        // P ── A ── children of A; A is the shape whose subtree derives.
        let mut skeleton = Skeleton::new(Frame::IDENTITY, "P");
        let a = skeleton.add_child(skeleton.root(), at(0.0, 1.0, 0.0), "A");
        let old: Vec<SectionId> = (0..children)
            .map(|i| skeleton.add_child(a, at(f64::from(i), 2.0, 0.0), format!("C{i}")))
            .collect();
        let first_new = skeleton.len();
        // The subtree's sections: A and every section made from here on.
        let subtree = |skeleton: &Skeleton| -> Vec<SectionId> {
            std::iter::once(a).chain((first_new..skeleton.len()).map(|i| SectionId(i as u32))).collect()
        };
        for step in steps {
            let ours = subtree(&skeleton);
            let pick = |s: usize| ours[s % ours.len()];
            match step {
                Step::Components(s, n) => { skeleton.components(pick(s), frames(s, n)); }
                Step::Sequential(s, n) => { skeleton.sequential(pick(s), frames(s, n)); }
                Step::Parallel(s, n) => { let _ = skeleton.parallel(pick(s), frames(s, n)); }
                Step::Place(s) => skeleton.place_joint(pick(s), frames(s, 1)[0].0),
                Step::Pose(s, angle) => {
                    skeleton.set_limits(pick(s), free_yaw()).unwrap();
                    skeleton.set_pose(pick(s), yaw(angle)).unwrap();
                }
            }
        }
        let ours = subtree(&skeleton);
        let root = skeleton.root();
        for &n in &ours {
            let parent = skeleton.section(n).parent().expect("only P is a root");
            prop_assert!(ours.contains(&parent) || parent == root, "{n:?} under {parent:?}");
            for child in skeleton.children(n) {
                prop_assert!(ours.contains(&child) || old.contains(&child));
            }
        }
        // A's children all hang from one section of the subtree.
        let holders: Vec<SectionId> = old
            .iter()
            .map(|&c| skeleton.section(c).parent().expect("a child has a parent"))
            .collect();
        prop_assert!(holders.iter().all(|h| ours.contains(h) && *h == holders[0]));
        prop_assert!(skeleton.is_tree());
    }
}

#[test]
fn folding_locked_sections_keeps_one_per_free_joint_and_every_pose() {
    let (mut skeleton, floors) = tower();
    // Floors 2 and 4 may turn; the others are locked. Each floor has two locked panes.
    for &k in &[2, 4] {
        skeleton.set_limits(floors[k], free_yaw()).unwrap();
        skeleton.set_pose(floors[k], yaw(30.0 * k as f64)).unwrap();
    }
    for &floor in &floors {
        for side in [-1.0, 1.0] {
            let y = skeleton.section(floor).rest().translation.y + 1.0;
            skeleton.add_child(floor, at(side, y, 2.0), "Pane");
        }
    }
    let (rig, map) = skeleton.without_locked();
    assert_eq!(rig.len(), 3, "the root and the two free floors");
    assert!(rig.is_tree());
    assert_eq!(
        rig.section(map[floors[4].index()]).parent(),
        Some(map[floors[2].index()])
    );
    // Every section moves as the section it was folded into, so posed geometry is unchanged.
    let (before, after) = (skeleton.skinning(), rig.skinning());
    let p = DVec3::new(1.0, 5.0, 2.0);
    for (id, _) in skeleton.sections() {
        let (a, b) = (before[id.index()], after[map[id.index()].index()]);
        assert!(close(a.transform_point(p), b.transform_point(p)), "{id:?}");
    }
    assert_eq!(rig.section(map[floors[4].index()]).pose(), yaw(120.0));
    // One section's motion, walking its chain only, is its skinning transformation.
    for (id, _) in skeleton.sections() {
        let one = skeleton.motion(id).unwrap();
        assert!(close(
            one.transform_point(p),
            before[id.index()].transform_point(p)
        ));
    }
    assert_eq!(skeleton.motion(SectionId(999)), None);
}
