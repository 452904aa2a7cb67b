//! The kinematic example grammars (`examples/excavator.cga`, `robot.cga`, `hinged_house.cga`,
//! `clock_tower.cga`): their skeletons have the shape each grammar means, and posing a joint
//! moves exactly the parts that hang below it, about the right axis, by the right amount.

use crate::common;

use std::collections::BTreeSet;

use common::{example, lot};
use shapegram_eval::{Derivation, DeriveError, DeriveOptions, Value, derive};
use shapegram_geom::DVec3;
use shapegram_geom::kinematics::{Frame, Limits, SectionId, Skeleton};

/// Derives `examples/<name>` on the default 20 × 30 lot with some attributes overridden.
fn try_derive(name: &str, attrs: &[(&str, f64)]) -> Result<Derivation, DeriveError> {
    let options = DeriveOptions {
        attrs: attrs
            .iter()
            .map(|(k, v)| ((*k).to_string(), Value::Number(*v)))
            .collect(),
        ..DeriveOptions::default()
    };
    derive(&example(name), &[lot(20.0, 30.0)], &options)
}

fn derived(name: &str, attrs: &[(&str, f64)]) -> Derivation {
    try_derive(name, attrs).unwrap_or_else(|e| panic!("{name}: {}", e.message))
}

fn skeleton(d: &Derivation) -> &Skeleton {
    assert_eq!(d.skeletons.len(), 1);
    &d.skeletons[0].1
}

/// A section's joint limits.
fn limits(skeleton: &Skeleton, id: SectionId) -> Limits {
    skeleton.section(id).limits()
}

/// A section's kinematic children, in the order they were linked.
fn children(skeleton: &Skeleton, id: SectionId) -> Vec<SectionId> {
    skeleton.children(id).collect()
}

/// The sections whose joints may move.
fn free_sections(skeleton: &Skeleton) -> Vec<SectionId> {
    skeleton
        .sections()
        .map(|(id, _)| id)
        .filter(|id| limits(skeleton, *id).is_free())
        .collect()
}

/// The sections made by the rule `rule` (their names are the rule and a hash).
fn named(skeleton: &Skeleton, rule: &str) -> Vec<SectionId> {
    let prefix = format!("{rule}_");
    skeleton
        .sections()
        .filter(|(_, s)| s.name().to_string().starts_with(&prefix))
        .map(|(id, _)| id)
        .collect()
}

/// The one section made by `rule`.
fn one(skeleton: &Skeleton, rule: &str) -> SectionId {
    let found = named(skeleton, rule);
    assert_eq!(found.len(), 1, "sections of {rule}");
    found[0]
}

/// Picks the one section made by `rule`.
fn section_of(rule: &'static str) -> impl Fn(&Skeleton) -> SectionId {
    move |s| one(s, rule)
}

/// The rule that made a section: its name without the hash.
fn rule_of(skeleton: &Skeleton, id: SectionId) -> String {
    let mut name = skeleton.section(id).name().to_string();
    name.truncate(name.rfind('_').expect("names end in a hash"));
    name
}

fn parent(skeleton: &Skeleton, id: SectionId) -> SectionId {
    skeleton.section(id).parent().expect("not the root")
}

/// `section` and every section below it.
fn subtree(skeleton: &Skeleton, section: SectionId) -> BTreeSet<SectionId> {
    let mut all = BTreeSet::new();
    let mut stack = vec![section];
    while let Some(s) = stack.pop() {
        all.insert(s);
        stack.extend(children(skeleton, s));
    }
    all
}

/// A leaf with its vertices in the rest pose and in the current pose.
struct Posed {
    name: String,
    section: SectionId,
    rest: Vec<DVec3>,
    posed: Vec<DVec3>,
}

/// Every leaf with geometry, in leaf order, moved by its section's skinning transform.
fn posed_leaves(d: &Derivation) -> Vec<Posed> {
    let motions = skeleton(d).skinning();
    d.leaves
        .iter()
        .filter_map(|leaf| {
            let mesh = leaf.world_mesh()?;
            let section = SectionId(leaf.section());
            let motion = motions[section.index()];
            let rest = mesh.positions().to_vec();
            let posed = rest.iter().map(|p| motion.transform_point(*p)).collect();
            Some(Posed {
                name: d.name(leaf.name).to_string(),
                section,
                rest,
                posed,
            })
        })
        .collect()
}

/// The indices of the leaves that are somewhere else in `b` than in `a` (the same grammar under
/// two poses, so the same leaves in the same order).
fn moved(a: &[Posed], b: &[Posed]) -> BTreeSet<usize> {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .enumerate()
        .filter(|(_, (a, b))| {
            assert_eq!(a.name, b.name);
            assert_eq!(a.rest.len(), b.rest.len());
            a.posed
                .iter()
                .zip(&b.posed)
                .any(|(p, q)| (*p - *q).length() > 1e-9)
        })
        .map(|(i, _)| i)
        .collect()
}

/// The indices of the leaves hanging from a section in `sections`.
fn hanging_from(leaves: &[Posed], sections: &BTreeSet<SectionId>) -> BTreeSet<usize> {
    leaves
        .iter()
        .enumerate()
        .filter(|(_, l)| sections.contains(&l.section))
        .map(|(i, _)| i)
        .collect()
}

/// Posing `attr` differently moves exactly the leaves below the section `section` picks;
/// returns how many.
fn moves_exactly_below(
    name: &str,
    attr: (&str, f64, f64),
    section: impl Fn(&Skeleton) -> SectionId,
) -> usize {
    let a = derived(name, &[(attr.0, attr.1)]);
    let b = derived(name, &[(attr.0, attr.2)]);
    let s = skeleton(&a);
    let below = subtree(s, section(s));
    let (la, lb) = (posed_leaves(&a), posed_leaves(&b));
    let moved = moved(&la, &lb);
    assert_eq!(
        moved,
        hanging_from(&la, &below),
        "{name}: {} moves exactly the parts below its joint",
        attr.0
    );
    moved.len()
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

fn assert_close(a: DVec3, b: DVec3, what: &str) {
    assert!(close(a, b), "{what}: {a} is not {b}");
}

/// A point of a section's rest frame, in the current pose.
fn posed_joint(skeleton: &Skeleton, id: SectionId) -> DVec3 {
    skeleton.posed()[id.index()].translation
}

/// `p` turned by `degrees` about the vertical line through `axis`.
fn turned_about_y(p: DVec3, axis: DVec3, degrees: f64) -> DVec3 {
    let turn = Frame::from_rotation(shapegram_geom::DQuat::from_rotation_y(degrees.to_radians()));
    axis + turn.transform_vector(p - axis)
}

// ---- Excavator -------------------------------------------------------------------------------------

/// The machine's turning axis: the lot's centre; the machine faces −z (the lot's first edge).
const AXIS: DVec3 = DVec3::new(10.0, 0.0, 15.0);

#[test]
fn excavator_is_one_chain_from_the_undercarriage_to_the_bucket() {
    let d = derived("excavator.cga", &[]);
    assert_eq!(d.leaves.len(), 67);
    let s = skeleton(&d);
    assert!(s.is_tree());
    assert_eq!(s.len(), 35);
    // Four free joints: the cab's turn and the three hinges of the arm, in one chain hanging
    // from the root (the undercarriage).
    let free: Vec<String> = free_sections(s).iter().map(|id| rule_of(s, *id)).collect();
    assert_eq!(free, ["Upper", "Boom", "Stick", "Bucket"]);
    let [upper, boom, stick, bucket] = ["Upper", "Boom", "Stick", "Bucket"].map(|r| one(s, r));
    assert_eq!(parent(s, upper), s.root());
    assert_eq!(parent(s, boom), upper);
    assert_eq!(parent(s, stick), boom);
    assert_eq!(parent(s, bucket), stick);
    // Limits: a full circle for the cab, realistic ranges about the axis across the arm.
    let range = |id: SectionId, axis: usize| {
        let r = limits(s, id).rotation[axis];
        (r.min, r.max)
    };
    assert_eq!(range(upper, 1), (-180.0, 180.0));
    assert_eq!(range(boom, 2), (-40.0, 60.0));
    assert_eq!(range(stick, 2), (-155.0, 0.0));
    assert_eq!(range(bucket, 2), (-160.0, 40.0));
    for id in [upper, boom, stick, bucket] {
        let l = limits(s, id);
        let free_axes = l.rotation.iter().chain(&l.translation);
        assert_eq!(
            free_axes.filter(|r| r.is_free()).count(),
            1,
            "{}",
            s.section(id).name()
        );
    }
    // The rest pose: the turning axis at the slewing ring's top (0.95 m), the arm stretched out
    // ahead at 1.95 m: boom foot 1.1 m ahead of the axis, stick pin 5.7 m further, bucket pin
    // 2.9 m further.
    let at = |id: SectionId| s.section(id).rest().translation;
    assert_close(at(upper), DVec3::new(10.0, 0.95, 15.0), "turning axis");
    assert_close(at(boom), DVec3::new(10.0, 1.95, 13.9), "boom foot");
    assert_close(at(stick), DVec3::new(10.0, 1.95, 8.2), "stick pin");
    assert_close(at(bucket), DVec3::new(10.0, 1.95, 5.3), "bucket pin");
    // The hinges turn about the machine's axis across the arm (world x), the cab about y.
    for id in [boom, stick, bucket] {
        assert_close(
            s.section(id).rest().transform_vector(DVec3::Z),
            DVec3::X,
            "hinge axis",
        );
    }
    assert_close(
        s.section(upper).rest().transform_vector(DVec3::Y),
        DVec3::Y,
        "turning axis",
    );
}

#[test]
fn excavator_hinges_lift_the_arm_about_its_pins() {
    // The boom raised by 60° (its limit), the rest of the arm straight on: stick and bucket
    // pins on the line rising at 60° from the boom foot, ahead of the machine (−z).
    let (sin, cos) = 60f64.to_radians().sin_cos();
    let rest = [("cabTurn", 0.0), ("bucketAngle", 0.0)];
    let d = derived(
        "excavator.cga",
        &[rest[0], rest[1], ("boomAngle", 60.0), ("stickAngle", 0.0)],
    );
    let s = skeleton(&d);
    let foot = DVec3::new(10.0, 1.95, 13.9);
    assert_close(
        posed_joint(s, one(s, "Stick")),
        foot + 5.7 * DVec3::new(0.0, sin, -cos),
        "stick pin",
    );
    assert_close(
        posed_joint(s, one(s, "Bucket")),
        foot + 8.6 * DVec3::new(0.0, sin, -cos),
        "bucket pin",
    );
    // The stick folded in by 60° from there runs level, straight ahead.
    let d = derived(
        "excavator.cga",
        &[rest[0], rest[1], ("boomAngle", 60.0), ("stickAngle", -60.0)],
    );
    let s = skeleton(&d);
    let stick = foot + 5.7 * DVec3::new(0.0, sin, -cos);
    assert_close(posed_joint(s, one(s, "Stick")), stick, "stick pin");
    assert_close(
        posed_joint(s, one(s, "Bucket")),
        stick + DVec3::new(0.0, 0.0, -2.9),
        "bucket pin",
    );
}

#[test]
fn excavator_turning_the_cab_moves_the_upper_structure_and_arm_but_not_the_tracks() {
    let a = derived("excavator.cga", &[("cabTurn", 0.0)]);
    let b = derived("excavator.cga", &[("cabTurn", 90.0)]);
    let (la, lb) = (posed_leaves(&a), posed_leaves(&b));
    let s = skeleton(&a);
    let upper = subtree(s, one(s, "Upper"));
    let moved = moved(&la, &lb);
    assert_eq!(moved, hanging_from(&la, &upper));
    assert_eq!(moved.len(), 49);
    // Tracks, car body and slewing ring stay; the house, cab and the whole arm turn.
    let names = |set: &BTreeSet<usize>| -> BTreeSet<&str> {
        set.iter().map(|&i| la[i].name.as_str()).collect()
    };
    let stayed: BTreeSet<usize> = (0..la.len()).filter(|i| !moved.contains(i)).collect();
    assert_eq!(
        names(&stayed),
        BTreeSet::from([
            "CarBody",
            "Drum",
            "Roller",
            "SlewingRing",
            "TrackBelt",
            "TrackFrame"
        ])
    );
    for part in [
        "Deck", "CabPost", "CabGlass", "Roof", "Member", "Ram", "Pin", "Tooth",
    ] {
        assert!(names(&moved).contains(part), "{part} turns with the cab");
    }
    // A quarter turn to the left about the vertical axis through the lot's centre: the bucket
    // pin turns with it, exactly.
    let bucket = |d: &Derivation| {
        let s = skeleton(d);
        posed_joint(s, one(s, "Bucket"))
    };
    assert_close(
        bucket(&b),
        turned_about_y(bucket(&a), AXIS, 90.0),
        "bucket pin turned",
    );
    // The arm now reaches out towards −x, 7 m from the axis.
    assert!((bucket(&b).x - (10.0 - 7.0)).abs() < 0.01, "{}", bucket(&b));
}

#[test]
fn excavator_each_hinge_moves_only_what_comes_after_it() {
    // Leaves below each joint: the bucket's 8 (shell, sides, teeth), the stick's 4 more, the
    // boom's 7 more.
    assert_eq!(
        moves_exactly_below(
            "excavator.cga",
            ("boomAngle", 35.0, -20.0),
            section_of("Boom")
        ),
        19
    );
    assert_eq!(
        moves_exactly_below(
            "excavator.cga",
            ("stickAngle", -100.0, -40.0),
            section_of("Stick")
        ),
        12
    );
    assert_eq!(
        moves_exactly_below(
            "excavator.cga",
            ("bucketAngle", -75.0, 30.0),
            section_of("Bucket")
        ),
        8
    );
}

#[test]
fn excavator_poses_outside_the_limits_are_errors() {
    let error = try_derive("excavator.cga", &[("boomAngle", 70.0)]).unwrap_err();
    assert_eq!(
        error.message,
        "the rotation about z of 70° is outside the joint's limits (-40° to 60°)"
    );
    let error = try_derive("excavator.cga", &[("stickAngle", 10.0)]).unwrap_err();
    assert_eq!(
        error.message,
        "the rotation about z of 10° is outside the joint's limits (-155° to 0°)"
    );
}

// ---- Robot -------------------------------------------------------------------------------------------

#[test]
fn robot_has_eighteen_free_joints_in_forks_and_chains() {
    let d = derived("robot.cga", &[]);
    assert_eq!(d.leaves.len(), 43);
    let s = skeleton(&d);
    assert!(s.is_tree());
    assert_eq!(s.len(), 29);
    let free = free_sections(s);
    assert_eq!(free.len(), 18);
    let mut by_rule: Vec<String> = free.iter().map(|id| rule_of(s, *id)).collect();
    by_rule.sort_unstable();
    assert_eq!(
        by_rule,
        [
            "Arm",
            "Arm",
            "Finger",
            "Finger",
            "Finger",
            "Finger",
            "Foot",
            "Foot",
            "ForeArm",
            "ForeArm",
            "Hand",
            "Hand",
            "Leg",
            "Leg",
            "Neck",
            "Shin",
            "Shin",
            "UpperBody"
        ]
    );
    // Forks: both legs and the upper body hang from the root (the plinth, with the pelvis);
    // both arms and the neck from the waist; the two jaws of a gripper from the hand.
    // Chains: hip → knee → ankle, shoulder → elbow → wrist.
    let waist = one(s, "UpperBody");
    assert_eq!(parent(s, waist), s.root());
    assert_eq!(parent(s, one(s, "Neck")), waist);
    for thigh in named(s, "Leg") {
        assert_eq!(parent(s, thigh), s.root());
        let shin = children(s, thigh)[0];
        assert_eq!(rule_of(s, shin), "Shin");
        assert_eq!(children(s, thigh), [shin]);
        let foot = children(s, shin);
        assert_eq!(foot.len(), 1);
        assert_eq!(rule_of(s, foot[0]), "Foot");
    }
    for arm in named(s, "Arm") {
        assert_eq!(parent(s, arm), waist);
        let chain: Vec<String> = subtree(s, arm)
            .iter()
            .filter(|id| limits(s, **id).is_free())
            .map(|id| rule_of(s, *id))
            .collect();
        assert_eq!(chain, ["Arm", "ForeArm", "Hand", "Finger", "Finger"]);
    }
    for finger in named(s, "Finger") {
        assert_eq!(rule_of(s, parent(s, finger)), "Hand");
    }
    // The hips: 0.28 × shoulderWidth either side of the middle, at half the height above the
    // 0.12 m plinth; the shoulders at the arms' slots, half a slot below the torso's top.
    let mut hips: Vec<DVec3> = named(s, "Leg")
        .iter()
        .map(|id| s.section(*id).rest().translation)
        .collect();
    hips.sort_by(|a, b| a.x.total_cmp(&b.x));
    assert_close(
        hips[0],
        DVec3::new(10.0 - 0.28 * 0.62, 0.12 + 1.2, 15.0),
        "left hip",
    );
    assert_close(
        hips[1],
        DVec3::new(10.0 + 0.28 * 0.62, 0.12 + 1.2, 15.0),
        "right hip",
    );
    let arm_slot = 1.3 * 0.16;
    let shoulder = DVec3::new(
        10.0 + 0.62 / 2.0 + arm_slot / 2.0,
        0.12 + 0.815 * 2.4 - arm_slot / 2.0,
        15.0,
    );
    assert_close(right_of(s, "Arm"), shoulder, "right shoulder");
}

/// The rest position of the joint of `rule` on the robot's right (+x).
fn right_of(s: &Skeleton, rule: &str) -> DVec3 {
    named(s, rule)
        .iter()
        .map(|id| s.section(*id).rest().translation)
        .max_by(|a, b| a.x.total_cmp(&b.x))
        .unwrap()
}

/// The section of `rule` on the robot's right.
fn right_section(s: &Skeleton, rule: &str) -> SectionId {
    *named(s, rule)
        .iter()
        .max_by(|a, b| {
            let x = |id: &SectionId| s.section(*id).rest().translation.x;
            x(a).total_cmp(&x(b))
        })
        .unwrap()
}

#[test]
fn robot_waves_with_its_forearm_upright() {
    // The default pose: the right upper arm out level and turned outwards, so that the elbow's
    // 100° lift the forearm: elbow straight out to the right of the shoulder, the wrist above
    // the elbow, leaning 10° back towards the head.
    let d = derived("robot.cga", &[]);
    let s = skeleton(&d);
    let shoulder = right_of(s, "Arm");
    let elbow = posed_joint(s, right_section(s, "ForeArm"));
    let wrist = posed_joint(s, right_section(s, "Hand"));
    let (upper_arm, fore_arm) = (0.18 * 2.4, 0.16 * 2.4);
    assert_close(elbow, shoulder + DVec3::new(upper_arm, 0.0, 0.0), "elbow");
    let lean = 100f64.to_radians();
    assert_close(
        wrist,
        elbow + fore_arm * DVec3::new(lean.cos(), lean.sin(), 0.0),
        "wrist",
    );
    // The waving hand is raised above the collar, the other hangs below the waist.
    let posed = posed_leaves(&d);
    let palms: Vec<f64> = posed
        .iter()
        .filter(|l| l.name == "Palm")
        .map(|l| l.posed.iter().map(|p| p.y).fold(f64::INFINITY, f64::min))
        .collect();
    let collar = posed
        .iter()
        .find(|l| l.name == "Collar")
        .map(|l| {
            l.posed
                .iter()
                .map(|p| p.y)
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .unwrap();
    assert_eq!(palms.len(), 2);
    assert!(
        palms[0] < 0.12 + 0.57 * 2.4 && palms[1] > collar,
        "{palms:?} {collar}"
    );
}

#[test]
fn robot_each_joint_moves_only_the_limb_below_it() {
    // Right elbow: forearm, elbow and wrist balls, palm, two jaws.
    let n = moves_exactly_below("robot.cga", ("rightElbow", 100.0, 40.0), |s| {
        right_section(s, "ForeArm")
    });
    assert_eq!(n, 6);
    // The waist carries the torso, both arms and the head: everything but legs, pelvis, plinth.
    let n = moves_exactly_below(
        "robot.cga",
        ("waistTurn", 0.0, 30.0),
        section_of("UpperBody"),
    );
    assert_eq!(n, 27);
    // The neck: neck, helmet, visor, two eyes, antenna and its tip.
    let n = moves_exactly_below("robot.cga", ("neckTurn", 20.0, -45.0), section_of("Neck"));
    assert_eq!(n, 7);
    // A left knee: the shin, its guard, the knee and ankle balls and the boot; nothing of the
    // right leg.
    let a = derived("robot.cga", &[("leftKnee", 0.0)]);
    let b = derived("robot.cga", &[("leftKnee", 60.0)]);
    let s = skeleton(&a);
    let left_shin = *named(s, "Shin")
        .iter()
        .min_by(|x, y| {
            let x_of = |id: &SectionId| s.section(*id).rest().translation.x;
            x_of(x).total_cmp(&x_of(y))
        })
        .unwrap();
    let (la, lb) = (posed_leaves(&a), posed_leaves(&b));
    let moved = moved(&la, &lb);
    assert_eq!(moved, hanging_from(&la, &subtree(s, left_shin)));
    let names: Vec<&str> = moved.iter().map(|&i| la[i].name.as_str()).collect();
    assert_eq!(
        names,
        ["JointBall", "Limb", "ShinGuard", "JointBall", "Boot"]
    );
    // The knee bends backwards: the ankle goes back (+z) and up. (Both derivations have the
    // same sections: only the pose differs.)
    let foot = children(s, left_shin)[0];
    assert_eq!(rule_of(s, foot), "Foot");
    let (rest, bent) = (
        posed_joint(skeleton(&a), foot),
        posed_joint(skeleton(&b), foot),
    );
    let shin = 0.225 * 2.4;
    let knee = rest + DVec3::new(0.0, shin, 0.0);
    let angle = 60f64.to_radians();
    assert_close(
        bent,
        knee + shin * DVec3::new(0.0, -angle.cos(), angle.sin()),
        "bent ankle",
    );
}

#[test]
fn robot_physique_comes_from_attributes() {
    // A taller, broader, stockier robot: joints move with the proportions.
    let d = derived(
        "robot.cga",
        &[
            ("height", 3.0),
            ("shoulderWidth", 0.9),
            ("limbThickness", 0.24),
        ],
    );
    let s = skeleton(&d);
    assert_eq!(free_sections(s).len(), 18);
    let arm_slot = 1.3 * 0.24;
    assert_close(
        right_of(s, "Arm"),
        DVec3::new(
            10.0 + 0.45 + arm_slot / 2.0,
            0.12 + 0.815 * 3.0 - arm_slot / 2.0,
            15.0,
        ),
        "right shoulder",
    );
    assert_close(
        right_of(s, "Leg"),
        DVec3::new(10.0 + 0.28 * 0.9, 0.12 + 1.5, 15.0),
        "right hip",
    );
    // Standing straight (head level), the helmet's top is at the height above the plinth.
    let d = derived(
        "robot.cga",
        &[("height", 3.0), ("neckBend", 0.0), ("neckTurn", 0.0)],
    );
    let top = posed_leaves(&d)
        .iter()
        .filter(|l| l.name == "Helmet")
        .flat_map(|l| l.posed.iter().map(|p| p.y))
        .fold(f64::NEG_INFINITY, f64::max);
    assert!((top - (0.12 + 3.0)).abs() < 1e-9, "{top}");
}

// ---- Hinged house --------------------------------------------------------------------------------------

#[test]
fn hinged_house_has_a_free_joint_per_door_and_window() {
    let d = derived("hinged_house.cga", &[]);
    assert_eq!(d.leaves.len(), 450);
    let s = skeleton(&d);
    assert!(s.is_tree());
    // 28 windows (front 4 + 4: two on each side of the door; sides 2 × 2 × 3, back 2 × 4) and
    // the front door, each free to turn about its y axis only, from 0° to 100°.
    let free = free_sections(s);
    assert_eq!(free.len(), 29);
    assert_eq!(named(s, "Sash").len(), 28);
    assert_eq!(named(s, "Door").len(), 1);
    for id in free {
        let section = s.section(id);
        assert!(
            matches!(rule_of(s, id).as_str(), "Sash" | "Door"),
            "{}",
            section.name()
        );
        let limits = limits(s, id);
        assert_eq!(
            (limits.rotation[1].min, limits.rotation[1].max),
            (0.0, 100.0)
        );
        assert!(!limits.rotation[0].is_free() && !limits.rotation[2].is_free());
        assert!(limits.translation.iter().all(|r| !r.is_free()));
        // Forks: every door and sash hangs from the house (the root), and its joint's y is up.
        assert_eq!(parent(s, id), s.root());
        assert_close(
            section.rest().transform_vector(DVec3::Y),
            DVec3::Y,
            "hinge axis",
        );
    }
}

#[test]
fn hinged_house_door_swings_inwards_about_its_hinge_edge() {
    let shut = derived("hinged_house.cga", &[("doorAngle", 0.0)]);
    let open = derived("hinged_house.cga", &[("doorAngle", 65.0)]);
    let (a, b) = (posed_leaves(&shut), posed_leaves(&open));
    // Only the door's own parts move.
    let moved = moved(&a, &b);
    let names: Vec<&str> = moved.iter().map(|&i| a[i].name.as_str()).collect();
    assert_eq!(names, ["DoorLeaf", "DoorPanel", "DoorLight", "Handle"]);
    let s = skeleton(&shut);
    assert_eq!(
        moved,
        hanging_from(&a, &subtree(s, one(s, "Door"))),
        "the door's section and nothing else"
    );
    // The leaf: 1.1 m wide, in the front facade (z = 19.5, facing +z) 0.15 m behind its face.
    // Its joint is on the hinge edge, x = 0 of its scope: the leaf's inner left edge.
    let leaf = a.iter().position(|l| l.name == "DoorLeaf").unwrap();
    let hinge = s.section(one(s, "Door")).rest().translation;
    let (x0, x1) = a[leaf]
        .rest
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.x), hi.max(p.x))
        });
    assert!((x1 - x0 - 1.1).abs() < 1e-9);
    assert_close(hinge, DVec3::new(x0, 0.0, 19.5 - 0.15), "hinge");
    let angle = 65f64.to_radians();
    let mut on_hinge = 0;
    let mut free_edge = 0;
    for (p, q) in a[leaf].rest.iter().zip(&b[leaf].posed) {
        // Every vertex turns by 65° about the vertical line through the hinge: it keeps its
        // height and its distance r from the line and moves by 2 r sin(θ / 2).
        let r = DVec3::new(p.x - hinge.x, 0.0, p.z - hinge.z).length();
        assert!((q.y - p.y).abs() < 1e-9);
        assert!((DVec3::new(q.x - hinge.x, 0.0, q.z - hinge.z).length() - r).abs() < 1e-9);
        assert!(((*q - *p).length() - 2.0 * r * (angle / 2.0).sin()).abs() < 1e-9);
        if close(DVec3::new(p.x, 0.0, p.z), DVec3::new(hinge.x, 0.0, hinge.z)) {
            // Corners on the hinge stay put.
            assert_close(*q, *p, "hinge corner");
            on_hinge += 1;
        } else if (p.x - x1).abs() < 1e-9 && (p.z - hinge.z).abs() < 1e-9 {
            // The free edge swings into the house: 1.1 m from the hinge at 65° from the facade.
            assert_close(
                *q,
                DVec3::new(
                    hinge.x + 1.1 * angle.cos(),
                    p.y,
                    hinge.z - 1.1 * angle.sin(),
                ),
                "free edge",
            );
            assert!(((*q - *p).length() - 2.2 * (angle / 2.0).sin()).abs() < 1e-9);
            free_edge += 1;
        }
    }
    assert!(on_hinge >= 2 && free_edge >= 2, "{on_hinge} {free_edge}");
}

#[test]
fn hinged_house_windows_swing_alone() {
    let shut = derived("hinged_house.cga", &[("windowAngle", 0.0)]);
    let open = derived("hinged_house.cga", &[("windowAngle", 90.0)]);
    let (a, b) = (posed_leaves(&shut), posed_leaves(&open));
    let moved = moved(&a, &b);
    // Five bars and a pane per sash, 28 sashes: walls, frames and sills stay.
    assert_eq!(moved.len(), 28 * 6);
    assert!(
        moved
            .iter()
            .all(|&i| matches!(a[i].name.as_str(), "SashBar" | "Pane"))
    );
    let s = skeleton(&shut);
    let sashes: BTreeSet<SectionId> = named(s, "Sash").into_iter().collect();
    assert_eq!(moved, hanging_from(&a, &sashes));
    // Square open, every pane stands out of its wall's plane by its width (1.04 m: the window
    // less its frame) on the inside: its extent across the facade is its thickness.
    for &i in &moved {
        if a[i].name != "Pane" {
            continue;
        }
        let extent = |points: &[DVec3]| {
            let lo = points.iter().fold(DVec3::INFINITY, |m, p| m.min(*p));
            let hi = points.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p));
            hi - lo
        };
        let (before, after) = (extent(&a[i].rest), extent(&b[i].posed));
        let across = |e: DVec3| e.x.max(e.z);
        let along = |e: DVec3| e.x.min(e.z);
        assert!((across(before) - 1.04).abs() < 1e-9 && along(before) < 1e-9);
        assert!((across(after) - 1.04).abs() < 1e-9 && along(after) < 1e-9);
    }
}

#[test]
fn hinged_house_door_past_its_stop_is_an_error() {
    let error = try_derive("hinged_house.cga", &[("doorAngle", 120.0)]).unwrap_err();
    assert_eq!(
        error.message,
        "the rotation about y of 120° is outside the joint's limits (0° to 100°)"
    );
}

// ---- Clock tower -------------------------------------------------------------------------------------------

/// Per clock: its hour hand's and minute hand's sections.
fn clocks(s: &Skeleton) -> Vec<(SectionId, SectionId)> {
    let hours = named(s, "HourHand");
    let minutes = named(s, "MinuteHand");
    assert_eq!((hours.len(), minutes.len()), (4, 4));
    // The hands of a clock share the line of their joints (the clock's axis).
    hours
        .into_iter()
        .map(|h| {
            let at = s.section(h).rest();
            let normal = at.transform_vector(DVec3::Z);
            let m = *minutes
                .iter()
                .find(|m| {
                    let d = s.section(**m).rest().translation - at.translation;
                    d.cross(normal).length() < 1e-9 && d.length() < 0.5
                })
                .expect("a minute hand on the hour hand's axis");
            (h, m)
        })
        .collect()
}

/// A hand's angle, clockwise from twelve as seen from outside, in degrees (0 to 360).
fn hand_angle(s: &Skeleton, hand: SectionId) -> f64 {
    let rest = s.section(hand).rest();
    let (right, up) = (
        rest.transform_vector(DVec3::X),
        rest.transform_vector(DVec3::Y),
    );
    let points = s.skinning()[hand.index()].transform_vector(up);
    points
        .dot(right)
        .atan2(points.dot(up))
        .to_degrees()
        .rem_euclid(360.0)
}

/// Whether two angles in degrees are the same direction, to 1e-9°.
fn same_angle(a: f64, b: f64) -> bool {
    let d = (a - b + 180.0).rem_euclid(360.0) - 180.0;
    d.abs() < 1e-9
}

#[test]
fn clock_tower_hands_hinge_at_each_clock_centre() {
    let d = derived("clock_tower.cga", &[]);
    assert_eq!(d.leaves.len(), 203);
    let s = skeleton(&d);
    assert!(s.is_tree());
    let free = free_sections(s);
    assert_eq!(free.len(), 8);
    let pairs = clocks(s);
    let mut normals = Vec::new();
    for (h, m) in pairs {
        for (hand, offset) in [(h, 0.12 + 0.025), (m, 0.12 + 0.075)] {
            let section = s.section(hand);
            assert!(free.contains(&hand));
            let r = limits(s, hand).rotation[2];
            assert_eq!((r.min, r.max), (-360.0, 360.0));
            // The joint: on the clock's centre line (the clock storey is 6.6 m wide, 16 to
            // 21 m up), in front of the dial by the thickness of the hands before it.
            let normal = section.rest().transform_vector(DVec3::Z);
            let centre = DVec3::new(10.0, 18.5, 15.0) + 3.3 * normal;
            assert_close(
                section.rest().translation,
                centre + offset * normal,
                "hand joint",
            );
            normals.push(normal);
        }
        // Dial and hands are forks from the clock storey: siblings, so the minute hand does
        // not turn with the hour hand.
        assert_eq!(parent(s, h), parent(s, m));
        assert_eq!(rule_of(s, parent(s, h)), "ClockStorey");
    }
    // Four faces, each facing out horizontally.
    for n in &normals {
        assert!(n.y.abs() < 1e-9 && (n.length() - 1.0).abs() < 1e-9);
    }
    let distinct: BTreeSet<(i64, i64)> = normals
        .iter()
        .map(|n| (n.x.round() as i64, n.z.round() as i64))
        .collect();
    assert_eq!(distinct.len(), 4);
}

#[test]
fn clock_tower_hands_show_the_time() {
    for (hours, minutes, hour_hand, minute_hand) in [
        (3.0, 0.0, 90.0, 0.0),
        (6.0, 30.0, 195.0, 180.0),
        (10.0, 10.0, 305.0, 60.0),
        (15.0, 45.0, 112.5, 270.0),
    ] {
        let d = derived("clock_tower.cga", &[("hours", hours), ("minutes", minutes)]);
        let s = skeleton(&d);
        for (h, m) in clocks(s) {
            let (ah, am) = (hand_angle(s, h), hand_angle(s, m));
            assert!(
                same_angle(ah, hour_hand) && same_angle(am, minute_hand),
                "{hours}:{minutes}: {ah} {am}"
            );
        }
    }
    // At 3:00 the hour hand's tip is 0.3 × 3.4 m right of the centre of its clock, seen from
    // outside, and the minute hand's 0.43 × 3.4 m above it.
    let d = derived("clock_tower.cga", &[("hours", 3.0), ("minutes", 0.0)]);
    let s = skeleton(&d);
    let posed = posed_leaves(&d);
    for (h, m) in clocks(s) {
        let rest = s.section(h).rest();
        let centre = rest.translation;
        let (right, up) = (
            rest.transform_vector(DVec3::X),
            rest.transform_vector(DVec3::Y),
        );
        let reach = |hand: SectionId, along: DVec3| {
            posed
                .iter()
                .filter(|l| l.section == hand)
                .flat_map(|l| l.posed.iter().map(|p| (*p - centre).dot(along)))
                .fold(f64::NEG_INFINITY, f64::max)
        };
        assert!((reach(h, right) - 0.3 * 3.4).abs() < 1e-9);
        assert!((reach(h, up) - 0.09 * 3.4 / 2.0).abs() < 1e-9);
        assert!((reach(m, up) - 0.43 * 3.4).abs() < 1e-9);
        assert!((reach(m, right) - 0.05 * 3.4 / 2.0).abs() < 1e-9);
    }
}

#[test]
fn clock_tower_setting_the_time_moves_only_the_hands() {
    let a = derived("clock_tower.cga", &[("hours", 3.0), ("minutes", 0.0)]);
    let b = derived("clock_tower.cga", &[("hours", 6.0), ("minutes", 30.0)]);
    let (la, lb) = (posed_leaves(&a), posed_leaves(&b));
    let moved = moved(&la, &lb);
    let s = skeleton(&a);
    let hands: BTreeSet<SectionId> = clocks(s).into_iter().flat_map(|(h, m)| [h, m]).collect();
    assert_eq!(moved, hanging_from(&la, &hands));
    assert_eq!(moved.len(), 8);
    assert!(moved.iter().all(|&i| la[i].name == "Hand"));
}
