//! Named poses: a skeleton keeps the poses of the same skeleton derived again with other
//! attribute values, and keeps them when locked sections are folded away.

use glam::DVec3;
use shapegram_kinematics::{Frame, Limits, Pose, Range, SectionId, Skeleton};

fn at(x: f64, y: f64, z: f64) -> Frame {
    Frame::from_translation(DVec3::new(x, y, z))
}

fn yaw(degrees: f64) -> Pose {
    Pose {
        rotation: DVec3::new(0.0, degrees, 0.0),
        translation: DVec3::ZERO,
    }
}

fn door_limits() -> Limits {
    let mut limits = Limits::default();
    limits.rotation[1] = Range::new(0.0, 100.0);
    limits
}

/// A house with a locked wall and a door on it (free about y), a locked handle on the door,
/// and a window on the wall (free about y); the door and the window opened by the given angles.
fn house(door: f64, window: f64) -> (Skeleton, [SectionId; 4]) {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "House");
    let wall = skeleton.add_child(skeleton.root(), at(0.0, 0.0, 5.0), "Wall");
    let door_id = skeleton.add_child(wall, at(1.0, 0.0, 5.0), "Door");
    let handle = skeleton.add_child(door_id, at(1.9, 1.0, 5.1), "Handle");
    let window_id = skeleton.add_child(wall, at(4.0, 1.0, 5.0), "Window");
    for (id, angle) in [(door_id, door), (window_id, window)] {
        skeleton.set_limits(id, door_limits()).unwrap();
        skeleton.set_pose(id, yaw(angle)).unwrap();
    }
    (skeleton, [wall, door_id, handle, window_id])
}

#[test]
fn named_poses_record_every_sections_pose_in_order() {
    let (mut skeleton, [wall, door, handle, window]) = house(65.0, 35.0);
    assert!(skeleton.named_poses().is_empty());
    skeleton
        .add_named_pose("open", &house(95.0, 80.0).0)
        .unwrap();
    skeleton
        .add_named_pose("closed", &house(0.0, 0.0).0)
        .unwrap();
    let names: Vec<&str> = skeleton
        .named_poses()
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(names, ["open", "closed"]);
    let open = skeleton.named_pose("open").unwrap();
    assert_eq!(open.poses.len(), skeleton.len());
    assert_eq!(open.pose(door), yaw(95.0));
    assert_eq!(open.pose(window), yaw(80.0));
    assert_eq!(open.pose(wall), Pose::default());
    assert_eq!(open.pose(handle), Pose::default());
    // The current pose is untouched.
    assert_eq!(skeleton.section(door).pose(), yaw(65.0));
    // The local transformation in a named pose is the one the skeleton would have posed so.
    let opened = house(95.0, 80.0).0;
    for (id, _) in skeleton.sections() {
        let a = skeleton.local_in(id, &open.pose(id));
        let b = opened.local(id);
        assert!((a.translation - b.translation).length() < 1e-12, "{id:?}");
        assert!(a.rotation.abs_diff_eq(b.rotation, 1e-12), "{id:?}");
    }
    // Adding a pose of the same name again replaces it, in place.
    skeleton
        .add_named_pose("open", &house(20.0, 10.0).0)
        .unwrap();
    assert_eq!(skeleton.named_poses().len(), 2);
    assert_eq!(skeleton.named_poses()[0].pose(door), yaw(20.0));
}

#[test]
fn a_named_pose_must_have_the_same_structure() {
    let (mut skeleton, _) = house(65.0, 35.0);
    let (mut bigger, [wall, ..]) = house(95.0, 80.0);
    bigger.add_child(wall, at(8.0, 1.0, 5.0), "Window");
    let error = skeleton.add_named_pose("open", &bigger).unwrap_err();
    assert!(error.contains("6 sections instead of 5"), "{error}");

    let mut renamed = Skeleton::new(Frame::IDENTITY, "House");
    let wall = renamed.add_child(renamed.root(), at(0.0, 0.0, 5.0), "Wall");
    renamed.add_child(wall, at(1.0, 0.0, 5.0), "Gate");
    renamed.add_child(wall, at(1.9, 1.0, 5.1), "Handle");
    renamed.add_child(wall, at(4.0, 1.0, 5.0), "Window");
    let error = skeleton.add_named_pose("open", &renamed).unwrap_err();
    assert!(
        error.contains("section 2") && error.contains("Gate"),
        "{error}"
    );
    assert!(
        skeleton.named_poses().is_empty(),
        "a refused pose is not kept"
    );
}

#[test]
fn without_locked_keeps_the_named_poses_of_the_kept_sections() {
    let (mut skeleton, [_, door, handle, window]) = house(65.0, 35.0);
    skeleton
        .add_named_pose("open", &house(95.0, 80.0).0)
        .unwrap();
    skeleton
        .add_named_pose("ajar", &house(20.0, 0.0).0)
        .unwrap();
    let (rig, map) = skeleton.without_locked();
    assert_eq!(rig.len(), 3, "the root, the door and the window");
    assert_eq!(map[handle.index()], map[door.index()]);
    let names: Vec<&str> = rig.named_poses().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["open", "ajar"]);
    for named in rig.named_poses() {
        assert_eq!(named.poses.len(), rig.len());
        assert_eq!(named.pose(rig.root()), Pose::default());
    }
    let open = rig.named_pose("open").unwrap();
    assert_eq!(open.pose(map[door.index()]), yaw(95.0));
    assert_eq!(open.pose(map[window.index()]), yaw(80.0));
    let ajar = rig.named_pose("ajar").unwrap();
    assert_eq!(ajar.pose(map[door.index()]), yaw(20.0));
    assert_eq!(ajar.pose(map[window.index()]), yaw(0.0));
    // Posed by a named pose, the rig puts the door where the full skeleton does.
    let full = house(95.0, 80.0).0;
    let (mut folded, _) = full.without_locked();
    for (id, _) in rig.sections() {
        folded.set_pose(id, open.pose(id)).unwrap();
    }
    let p = DVec3::new(1.5, 1.0, 5.0);
    let a = full.skinning()[handle.index()].transform_point(p);
    let b = folded.skinning()[map[handle.index()].index()].transform_point(p);
    assert!((a - b).length() < 1e-9);
}
