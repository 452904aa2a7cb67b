//! Kinematic skeletons in GLB as glTF skins, read back with the `gltf` crate; OBJ and STL in the
//! current pose.

use std::collections::BTreeMap;
use std::io;

use gltf::Gltf;
use gltf::accessor::DataType;
use gltf::mesh::Semantic;
use serde_json::{Value, json};
use shapegram_export::{
    ExportOptions, FlatNormals, GlbEncoding, Instancing, save, write_glb, write_glb_to, write_obj,
    write_stl,
};
use shapegram_geom::kinematics::{Frame, Limits, Pose, Range, SectionId, Skeleton};
use shapegram_geom::primitives::{cuboid, cylinder};
use shapegram_geom::{Bone, Color, DAffine3, DQuat, DVec3, Lines, Mesh, Model, Part};

const GROUPED: ExportOptions = ExportOptions {
    group_by_part: true,
    encoding: GlbEncoding::Float,
    instancing: Instancing::Auto,
    flat_normals: FlatNormals::Computed,
};
const MERGED: ExportOptions = ExportOptions {
    group_by_part: false,
    encoding: GlbEncoding::Float,
    instancing: Instancing::Auto,
    flat_normals: FlatNormals::Computed,
};

const STONE: Color = Color::rgb(0.6, 0.6, 0.55);
const GLASS: Color = Color::rgb(0.3, 0.5, 0.8);
const WOOD: Color = Color::rgb(0.5, 0.3, 0.1);

fn at(x: f64, y: f64, z: f64) -> Frame {
    Frame::from_translation(DVec3::new(x, y, z))
}

fn part(name: &str, color: Color, mesh: Mesh, bone: Option<Bone>) -> Part {
    Part {
        texture: None,
        uvs: Vec::new(),
        name: name.to_owned(),
        color,
        mesh,
        normals: Vec::new(),
        bone,
        metadata: None,
        material: None,
        surface: None,
        instance: None,
    }
}

fn bone(skeleton: u32, section: SectionId) -> Option<Bone> {
    Some(Bone { skeleton, section })
}

/// Floor `k` of the tower: a box 2.5 m high on the plane y = 3k, so that a vertex's floor is
/// `floor(y / 3)` in the rest pose.
fn floor_box(k: usize) -> Mesh {
    cuboid(DVec3::new(4.0, 2.5, 4.0)).transformed(&DAffine3::from_translation(DVec3::new(
        0.0,
        3.0 * k as f64,
        0.0,
    )))
}

/// A three-floor tower split sequentially upwards (joints on the planes y = 3 and y = 6), the
/// middle floor free to turn about y and slide along x, turned by 30° and moved 0.25 m. Names
/// that need sanitising, two of them equal once sanitised.
fn tower() -> (Skeleton, Vec<SectionId>) {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Tower");
    let floors = skeleton
        .sequential(
            skeleton.root(),
            [
                (at(0.0, 3.0, 0.0), "floor:1/Étage".to_owned()),
                (at(0.0, 6.0, 0.0), "floor_1__tage".to_owned()),
            ],
        )
        .to_vec();
    let mut limits = Limits::default();
    limits.rotation[1] = Range::new(-90.0, 90.0);
    limits.translation[0] = Range::new(0.0, 0.5);
    skeleton.set_limits(floors[1], limits).unwrap();
    let pose = Pose {
        rotation: DVec3::new(0.0, 30.0, 0.0),
        translation: DVec3::new(0.25, 0.0, 0.0),
    };
    assert!(skeleton.set_pose(floors[1], pose).unwrap().is_empty());
    (skeleton, floors)
}

/// A fork at x = 10: a root, a trunk and two branches (a parallel split of the trunk, so all
/// three are children of the root), the branches tilted ±45° about z at rest, one of them bent
/// by 20° more.
fn fork() -> (Skeleton, Vec<SectionId>) {
    let mut skeleton = Skeleton::new(at(10.0, 0.0, 0.0), "Tree");
    let chain = skeleton
        .sequential(skeleton.root(), [(at(10.0, 1.0, 0.0), "trunk".to_owned())])
        .to_vec();
    let tilted = |degrees: f64| Frame {
        rotation: DQuat::from_rotation_z(degrees.to_radians()),
        translation: DVec3::new(10.0, 1.0, 0.5),
    };
    let branches = skeleton
        .parallel(
            chain[1],
            [
                (tilted(45.0), "branch".to_owned()),
                (tilted(-45.0), "branch".to_owned()),
            ],
        )
        .unwrap()
        .to_vec();
    let mut limits = Limits::default();
    limits.rotation[2] = Range::new(-45.0, 45.0);
    skeleton.set_limits(branches[0], limits).unwrap();
    let bend = Pose {
        rotation: DVec3::new(0.0, 0.0, 20.0),
        translation: DVec3::ZERO,
    };
    skeleton.set_pose(branches[0], bend).unwrap();
    let mut sections = chain;
    sections.extend(branches);
    (skeleton, sections)
}

/// A branch along its frame's y axis, in model space at rest.
fn branch_mesh(frame: &Frame) -> Mesh {
    cylinder(DVec3::new(0.2, 1.5, 0.2), 8).transformed(&frame.to_affine())
}

/// The tower (skeleton 0), the fork (skeleton 1), an unbound lot in the tower's stone colour and
/// a line set.
fn scene() -> Model {
    let (tower, floors) = tower();
    let (tree, sections) = fork();
    let mut parts: Vec<Part> = floors
        .iter()
        .enumerate()
        .map(|(k, &s)| part(&format!("floor {k}"), STONE, floor_box(k), bone(0, s)))
        .collect();
    // Windows in another material on the middle floor: a second primitive in the same skin.
    parts.push(part(
        "window",
        GLASS,
        cuboid(DVec3::new(1.0, 1.0, 0.1))
            .transformed(&DAffine3::from_translation(DVec3::new(1.0, 4.0, 4.0))),
        bone(0, floors[1]),
    ));
    parts.push(part(
        "lot",
        STONE,
        cuboid(DVec3::new(20.0, 0.1, 20.0))
            .transformed(&DAffine3::from_translation(DVec3::new(-5.0, -0.2, -5.0))),
        None,
    ));
    parts.push(part(
        "tree trunk",
        WOOD,
        cylinder(DVec3::new(0.4, 1.0, 0.4), 8)
            .transformed(&DAffine3::from_translation(DVec3::new(10.0, 0.0, 0.0))),
        bone(1, sections[1]),
    ));
    for (i, &s) in sections[2..].iter().enumerate() {
        let mesh = branch_mesh(&tree.section(s).rest());
        parts.push(part(&format!("branch {i}"), WOOD, mesh, bone(1, s)));
    }
    Model {
        parts,
        lines: vec![Lines {
            name: "path".to_owned(),
            color: STONE,
            points: vec![DVec3::new(-5.0, 0.0, -5.0), DVec3::new(15.0, 0.0, 15.0)],
            segments: vec![[0, 1]],
        }],
        skeletons: vec![tower, tree],
    }
}

/// A fan of `n` sections, all children of the root, each with a small box bound to it.
fn fan(n: usize) -> Model {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Fan");
    let frames = (1..n).map(|i| (at(i as f64, 0.0, 0.0), "w".repeat(100)));
    let sections = skeleton.components(skeleton.root(), frames).to_vec();
    let parts = sections
        .iter()
        .enumerate()
        .map(|(i, &s)| {
            let mesh = cuboid(DVec3::splat(0.5)).transformed(&DAffine3::from_translation(
                DVec3::new(i as f64 + 1.0, 0.0, 0.0),
            ));
            part(&format!("leaf {i}"), STONE, mesh, bone(0, s))
        })
        .collect();
    Model {
        parts,
        lines: Vec::new(),
        skeletons: vec![skeleton],
    }
}

/// A vertex's JOINTS_0 and WEIGHTS_0.
type Influence = ([u16; 4], [f32; 4]);

/// A written GLB parsed by the `gltf` crate, with the raw JSON beside it.
struct Read {
    gltf: Gltf,
    json: Value,
}

impl Read {
    fn new(bytes: &[u8]) -> Self {
        let gltf = Gltf::from_slice(bytes).expect("the file parses");
        let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        Self { gltf, json }
    }

    fn blob(&self) -> &[u8] {
        self.gltf.blob.as_deref().unwrap_or_default()
    }

    fn node(&self, name: &str) -> gltf::Node<'_> {
        let mut found = self.gltf.nodes().filter(|n| n.name() == Some(name));
        let node = found.next().unwrap_or_else(|| panic!("no node {name}"));
        assert!(found.next().is_none(), "two nodes {name}");
        node
    }

    /// Parent node index by node index.
    fn parents(&self) -> BTreeMap<usize, usize> {
        self.gltf
            .nodes()
            .flat_map(|n| n.children().map(move |c| (c.index(), n.index())))
            .collect()
    }

    /// A node's transformation in the scene, through all its ancestors.
    fn world(&self, node: usize) -> DAffine3 {
        let parents = self.parents();
        let nodes: Vec<_> = self.gltf.nodes().collect();
        let mut world = DAffine3::IDENTITY;
        let mut at = Some(node);
        while let Some(n) = at {
            let (t, r, s) = nodes[n].transform().decomposed();
            assert_eq!(s, [1.0; 3], "joints are never scaled");
            let local = DAffine3::from_rotation_translation(
                DQuat::from_array(r.map(f64::from)),
                DVec3::from_array(t.map(f64::from)),
            );
            world = local * world;
            at = parents.get(&n).copied();
        }
        world
    }

    /// The inverse bind matrices of a skin, as affine maps, after checking that the last row
    /// of each is exactly 0, 0, 0, 1.
    fn inverse_bind_matrices(&self, skin: &gltf::Skin<'_>) -> Vec<DAffine3> {
        let reader = skin.reader(|_| Some(self.blob()));
        reader
            .read_inverse_bind_matrices()
            .expect("the skin has inverse bind matrices")
            .map(|columns| {
                assert_eq!(columns.map(|c| c[3]), [0.0, 0.0, 0.0, 1.0]);
                let mut cols = [0.0; 12];
                for (c, column) in columns.iter().enumerate() {
                    for r in 0..3 {
                        cols[3 * c + r] = f64::from(column[r]);
                    }
                }
                DAffine3::from_cols_array(&cols)
            })
            .collect()
    }

    /// Every vertex of every primitive of a node's mesh: position, JOINTS_0 and WEIGHTS_0
    /// (`None` for a primitive without them).
    fn vertices(&self, node: &gltf::Node<'_>) -> Vec<(DVec3, Option<Influence>)> {
        let mesh = node.mesh().expect("a mesh node");
        let mut out = Vec::new();
        for primitive in mesh.primitives() {
            let reader = primitive.reader(|_| Some(self.blob()));
            let positions: Vec<DVec3> = reader
                .read_positions()
                .unwrap()
                .map(|p| DVec3::from_array(p.map(f64::from)))
                .collect();
            let joints = reader
                .read_joints(0)
                .map(|j| j.into_u16().collect::<Vec<_>>());
            let weights = reader
                .read_weights(0)
                .map(|w| w.into_f32().collect::<Vec<_>>());
            assert_eq!(
                joints.is_some(),
                weights.is_some(),
                "JOINTS_0 with WEIGHTS_0"
            );
            for (v, p) in positions.into_iter().enumerate() {
                let influence = joints
                    .as_ref()
                    .zip(weights.as_ref())
                    .map(|(j, w)| (j[v], w[v]));
                out.push((p, influence));
            }
        }
        out
    }
}

fn close(a: DVec3, b: DVec3, tolerance: f64) -> bool {
    (a - b).abs().max_element() <= tolerance
}

#[test]
fn each_skeleton_becomes_a_skin_under_an_armature_with_its_sections_in_order() {
    let model = scene();
    for options in [MERGED, GROUPED] {
        let read = Read::new(&write_glb(&model, &options));
        let skins: Vec<_> = read.gltf.skins().collect();
        assert_eq!(skins.len(), 2);
        let parents = read.parents();
        let root = read.node("shapegram");
        // Skinned mesh nodes are scene roots (the validator warns about a parent, whose
        // transformation skinning ignores); unskinned ones hang from "shapegram".
        let scene: Vec<usize> = read
            .gltf
            .default_scene()
            .unwrap()
            .nodes()
            .map(|n| n.index())
            .collect();
        let mut skinned = Vec::new();
        for node in read.gltf.nodes().filter(|n| n.mesh().is_some()) {
            if node.skin().is_some() {
                assert_eq!(parents.get(&node.index()), None);
                skinned.push(node.index());
            } else {
                assert_eq!(parents.get(&node.index()), Some(&root.index()));
            }
        }
        assert_eq!(scene[0], root.index());
        assert_eq!(scene[1..], skinned);
        for (k, (skin, skeleton)) in skins.iter().zip(&model.skeletons).enumerate() {
            let armature = read.node(["Armature", "Armature.001"][k]);
            assert_eq!(skin.name(), armature.name());
            assert_eq!(skin.skeleton().map(|n| n.index()), Some(armature.index()));
            assert_eq!(parents.get(&armature.index()), Some(&root.index()));
            assert!(armature.mesh().is_none() && armature.skin().is_none());
            let joints: Vec<usize> = skin.joints().map(|n| n.index()).collect();
            let order = skeleton.order();
            assert_eq!(joints.len(), skeleton.len());
            for (j, &id) in order.iter().enumerate() {
                let expected_parent = match skeleton.section(id).parent() {
                    Some(p) => joints[order.iter().position(|&o| o == p).unwrap()],
                    None => armature.index(),
                };
                assert_eq!(parents.get(&joints[j]), Some(&expected_parent), "joint {j}");
                // Nothing but joints under joints: no mesh hangs from the skeleton.
                let node = read.gltf.nodes().nth(joints[j]).unwrap();
                assert!(node.mesh().is_none() && node.skin().is_none());
                assert!(node.children().all(|c| joints.contains(&c.index())));
            }
        }
    }
}

#[test]
fn joint_nodes_carry_the_posed_local_transform_and_nothing_else() {
    let model = scene();
    let read = Read::new(&write_glb(&model, &MERGED));
    for (skin, skeleton) in read.gltf.skins().zip(&model.skeletons) {
        for (node, id) in skin.joints().zip(skeleton.order()) {
            let local = skeleton.local(id);
            let (t, r, s) = node.transform().decomposed();
            assert_eq!(
                t,
                local.translation.as_vec3().to_array(),
                "{:?}",
                node.name()
            );
            let q = local.rotation.as_quat().to_array();
            // q and −q are the same rotation.
            assert!(r == q || r == q.map(|x| -x), "{r:?} vs {q:?}");
            assert_eq!(s, [1.0; 3]);
            let raw = &read.json["nodes"][node.index()];
            assert!(raw.get("scale").is_none() && raw.get("matrix").is_none());
            // Identity parts are left out.
            assert_eq!(raw.get("translation").is_some(), t != [0.0; 3]);
            assert_eq!(raw.get("rotation").is_some(), r != [0.0, 0.0, 0.0, 1.0]);
        }
    }
    // The tower's root joint sits at the origin unturned: a node with neither.
    let root = &read.json["nodes"][read.node("Tower").index()];
    assert!(root.get("translation").is_none() && root.get("rotation").is_none());
}

#[test]
fn inverse_bind_matrices_undo_the_rest_frames_in_a_view_of_their_own() {
    let model = scene();
    let read = Read::new(&write_glb(&model, &MERGED));
    for (skin, skeleton) in read.gltf.skins().zip(&model.skeletons) {
        let matrices = read.inverse_bind_matrices(&skin);
        assert_eq!(matrices.len(), skeleton.len());
        for (ibm, id) in matrices.iter().zip(skeleton.order()) {
            let product = *ibm * skeleton.section(id).rest().to_affine();
            assert!(
                product.abs_diff_eq(DAffine3::IDENTITY, 1e-6),
                "{:?}: {product:?}",
                skeleton.section(id).name()
            );
        }
        let accessor = skin.inverse_bind_matrices().unwrap();
        assert_eq!(accessor.data_type(), DataType::F32);
        assert_eq!(accessor.dimensions(), gltf::accessor::Dimensions::Mat4);
        let view = accessor.view().unwrap();
        assert_eq!(view.stride(), None);
        assert_eq!(view.target(), None);
        assert_eq!(view.offset() % 4, 0);
        assert_eq!(view.length(), 64 * skeleton.len());
    }
    // Each accessor has a view of its own (so no view is used for two kinds of data).
    let views: Vec<_> = read
        .gltf
        .accessors()
        .map(|a| a.view().unwrap().index())
        .collect();
    let distinct: std::collections::BTreeSet<_> = views.iter().collect();
    assert_eq!(views.len(), distinct.len());
}

#[test]
fn every_skinned_vertex_follows_its_parts_joint_with_full_weight() {
    let model = scene();
    let (tower, floors) = tower();
    let tower_joint =
        |section: SectionId| tower.order().iter().position(|&s| s == section).unwrap() as u16;
    // Merged: a vertex's floor is known from its height; the window is on floor 1.
    let read = Read::new(&write_glb(&model, &MERGED));
    let skinned = read.node("skinned");
    assert_eq!(skinned.skin().unwrap().index(), 0);
    let vertices = read.vertices(&skinned);
    assert!(!vertices.is_empty());
    for (p, influence) in vertices {
        let (joints, weights) = influence.expect("every primitive of a skinned mesh is skinned");
        let floor = (p.y / 3.0).floor() as usize;
        assert_eq!(joints, [tower_joint(floors[floor]), 0, 0, 0], "{p}");
        assert_eq!(weights, [1.0, 0.0, 0.0, 0.0]);
    }
    // Grouped: each part's node, skinned by its skeleton, names its section's joint.
    let read = Read::new(&write_glb(&model, &GROUPED));
    for part in &model.parts {
        let node = read.node(&part.name);
        let raw = &read.json["nodes"][node.index()];
        assert!(raw.get("translation").is_none() && raw.get("rotation").is_none());
        let Some(bone) = part.bone else {
            assert!(node.skin().is_none());
            assert!(read.vertices(&node).iter().all(|(_, i)| i.is_none()));
            continue;
        };
        assert_eq!(node.skin().unwrap().index(), bone.skeleton as usize);
        let skeleton = &model.skeletons[bone.skeleton as usize];
        let joint = skeleton
            .order()
            .iter()
            .position(|&s| s == bone.section)
            .unwrap() as u16;
        let vertices = read.vertices(&node);
        assert!(!vertices.is_empty());
        for (_, influence) in vertices {
            assert_eq!(influence, Some(([joint, 0, 0, 0], [1.0, 0.0, 0.0, 0.0])));
        }
    }
}

#[test]
fn joints_and_weights_are_u8_vec4_in_aligned_vertex_views_and_u16_beyond_256_joints() {
    for (model, sections, component) in [
        (scene(), 3, DataType::U8),
        (fan(256), 256, DataType::U8),
        (fan(257), 257, DataType::U16),
        (fan(300), 300, DataType::U16),
    ] {
        assert_eq!(model.skeletons[0].len(), sections);
        let bytes = write_glb(&model, &MERGED);
        let read = Read::new(&bytes);
        let skinned = read.node("skinned");
        for primitive in skinned.mesh().unwrap().primitives() {
            let joints = primitive.get(&Semantic::Joints(0)).unwrap();
            let weights = primitive.get(&Semantic::Weights(0)).unwrap();
            assert_eq!(joints.data_type(), component);
            assert_eq!(weights.data_type(), DataType::U8);
            assert!(weights.normalized());
            assert!(!joints.normalized());
            for accessor in [joints, weights] {
                assert_eq!(accessor.dimensions(), gltf::accessor::Dimensions::Vec4);
                let view = accessor.view().unwrap();
                assert_eq!(view.target(), Some(gltf::buffer::Target::ArrayBuffer));
                assert_eq!(view.offset() % 4, 0);
                assert_eq!(view.stride(), None);
            }
        }
    }
    // The fan's leaves are joints 1..n in link order: the last leaf names joint 299.
    let model = fan(300);
    let read = Read::new(&write_glb(&model, &GROUPED));
    let last = read.vertices(&read.node("leaf 298"));
    assert!(last.iter().all(|(_, i)| i.unwrap().0 == [299, 0, 0, 0]));
}

#[test]
fn a_viewer_skinning_the_file_sees_the_posed_model() {
    let model = scene();
    let posed = model.posed();
    let read = Read::new(&write_glb(&model, &GROUPED));
    let mut moved = 0;
    for (part, posed_part) in model.parts.iter().zip(&posed.parts) {
        let node = read.node(&part.name);
        let Some(skin) = node.skin() else { continue };
        let matrices = read.inverse_bind_matrices(&skin);
        let joints: Vec<usize> = skin.joints().map(|n| n.index()).collect();
        // What glTF's skinning does to each vertex: joint world transform × IBM.
        let skinned: Vec<DVec3> = read
            .vertices(&node)
            .into_iter()
            .map(|(p, influence)| {
                let j = usize::from(influence.unwrap().0[0]);
                (read.world(joints[j]) * matrices[j]).transform_point3(p)
            })
            .collect();
        let expected = posed_part.mesh.positions();
        let near = |p: &DVec3, set: &[DVec3]| set.iter().any(|q| close(*p, *q, 1e-5));
        assert!(skinned.iter().all(|p| near(p, expected)), "{}", part.name);
        assert!(expected.iter().all(|p| near(p, &skinned)), "{}", part.name);
        if posed_part.mesh != part.mesh {
            moved += 1;
        }
    }
    // Floors 1 and 2, the window and the bent branch moved.
    assert_eq!(moved, 4);
}

#[test]
fn joint_names_are_sanitised_ascii_unique_and_short() {
    let read = Read::new(&write_glb(&scene(), &MERGED));
    let names = |skin: usize| -> Vec<String> {
        let skin = read.gltf.skins().nth(skin).unwrap();
        skin.joints()
            .map(|n| n.name().unwrap().to_owned())
            .collect()
    };
    assert_eq!(
        names(0),
        ["Tower", "floor_1__tage", "floor_1__tage_2"].map(String::from)
    );
    assert_eq!(
        names(1),
        ["Tree", "trunk", "branch", "branch_2"].map(String::from)
    );
    let read = Read::new(&write_glb(&fan(300), &MERGED));
    let skin = read.gltf.skins().next().unwrap();
    let names: Vec<&str> = skin.joints().map(|n| n.name().unwrap()).collect();
    assert_eq!(names[1], "w".repeat(63));
    assert_eq!(names[2], format!("{}_2", "w".repeat(61)));
    assert_eq!(names[299], format!("{}_299", "w".repeat(59)));
    let mut unique = names.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), names.len());
    for name in names {
        assert!(name.len() <= 63 && !name.is_empty(), "{name}");
        assert!(
            name.bytes()
                .all(|b| b.is_ascii_alphanumeric() || b"_-.".contains(&b)),
            "{name}"
        );
    }
}

#[test]
fn joint_extras_hold_the_section_rest_limits_and_pose() {
    let model = scene();
    let read = Read::new(&write_glb(&model, &MERGED));
    let extras = |name: &str| -> Value {
        let raw = read.node(name).extras().as_ref().expect("joint extras");
        serde_json::from_str(raw.get()).unwrap()
    };
    assert_eq!(
        extras("floor_1__tage"),
        json!({"shapegram": {"joint": {
            "section": "floor:1/Étage",
            "rest_translation_m": [0.0, 3.0, 0.0],
            "rest_rotation_xyzw": [0.0, 0.0, 0.0, 1.0],
            "rotation_limits_deg": [[0.0, 0.0], [-90.0, 90.0], [0.0, 0.0]],
            "translation_limits_m": [[0.0, 0.5], [0.0, 0.0], [0.0, 0.0]],
            "pose_rotation_deg": [0.0, 30.0, 0.0],
            "pose_translation_m": [0.25, 0.0, 0.0],
        }}})
    );
    // A locked joint in the rest pose still says so.
    assert_eq!(
        extras("Tower")["shapegram"]["joint"]["rotation_limits_deg"],
        json!([[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    );
    // The branch's rest rotation relative to the root, printed exactly as the skeleton holds
    // it (compared as text: serde_json's default parser may miss the last bit).
    let (tree, sections) = fork();
    let rest = tree.joint(sections[2]).rotation.to_array();
    let raw = read.node("branch").extras().as_ref().unwrap().get();
    let printed = serde_json::to_string(&rest).unwrap();
    assert!(
        raw.contains(&format!("\"rest_rotation_xyzw\":{printed}")),
        "{raw}"
    );
    let branch = extras("branch");
    let joint = &branch["shapegram"]["joint"];
    assert_eq!(joint["pose_rotation_deg"], json!([0.0, 0.0, 20.0]));
    assert_eq!(
        joint["rotation_limits_deg"][2],
        json!([-45.0, 45.0]),
        "{branch}"
    );
    // Only joints carry extras, and nothing is required of readers.
    let joints: usize = model.skeletons.iter().map(Skeleton::len).sum();
    let with_extras = read.gltf.nodes().filter(|n| n.extras().is_some()).count();
    assert_eq!(with_extras, joints);
    assert!(read.json.get("extensionsRequired").is_none());
    assert!(read.json.get("extensionsUsed").is_none());
}

#[test]
fn merged_skinned_parts_share_no_primitive_with_other_skins_or_unskinned_parts() {
    let model = scene();
    let read = Read::new(&write_glb(&model, &MERGED));
    let mesh_nodes: Vec<_> = read.gltf.nodes().filter(|n| n.mesh().is_some()).collect();
    let summary: Vec<(&str, Option<usize>, usize)> = mesh_nodes
        .iter()
        .map(|n| {
            let primitives = n.mesh().unwrap().primitives().len();
            (n.name().unwrap(), n.skin().map(|s| s.index()), primitives)
        })
        .collect();
    // The lot and the path: stone triangles and stone lines; the tower: stone and glass; the
    // tree: wood.
    assert_eq!(
        summary,
        [
            ("skinned", Some(0), 2),
            ("model", None, 2),
            ("skinned.001", Some(1), 1),
        ]
    );
    for node in &mesh_nodes {
        let skinned = node.skin().is_some();
        for primitive in node.mesh().unwrap().primitives() {
            assert_eq!(primitive.get(&Semantic::Joints(0)).is_some(), skinned);
            assert_eq!(primitive.get(&Semantic::Weights(0)).is_some(), skinned);
        }
    }
    // Vertices stay in the rest pose: the skinned meshes' bounds are the rest parts' bounds.
    let tower_rest = model.parts[..4]
        .iter()
        .filter_map(|p| p.mesh.bounds())
        .reduce(shapegram_geom::Aabb::union)
        .unwrap();
    let positions: Vec<DVec3> = read
        .vertices(&read.node("skinned"))
        .into_iter()
        .map(|(p, _)| p)
        .collect();
    let bounds = shapegram_geom::Aabb::from_points(positions).unwrap();
    assert!(close(bounds.min, tower_rest.min, 1e-6) && close(bounds.max, tower_rest.max, 1e-6));
}

#[test]
fn obj_and_stl_write_the_posed_model() {
    let model = scene();
    let posed = model.posed();
    assert_eq!(write_stl(&model), write_stl(&posed));
    assert_eq!(
        write_obj(&model, &GROUPED, "m.mtl"),
        write_obj(&posed, &GROUPED, "m.mtl")
    );
    // The pose shows: the rest pose writes other files.
    let mut rest = model.clone();
    rest.skeletons.clear();
    for part in &mut rest.parts {
        part.bone = None;
    }
    assert_ne!(write_stl(&model), write_stl(&rest));
    // `save` goes through the same writers.
    let dir = std::env::temp_dir().join(format!("shapegram-export-{}-skins", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    save(&model, &dir.join("posed.stl"), &MERGED).unwrap();
    assert_eq!(
        std::fs::read(dir.join("posed.stl")).unwrap(),
        write_stl(&posed)
    );
    save(&model, &dir.join("posed.obj"), &MERGED).unwrap();
    let (obj, _) = write_obj(&posed, &MERGED, "posed.mtl");
    assert_eq!(std::fs::read_to_string(dir.join("posed.obj")).unwrap(), obj);
}

#[test]
fn models_without_bound_parts_are_written_as_before() {
    let mut model = scene();
    for part in &mut model.parts {
        part.bone = None;
    }
    let mut bare = model.clone();
    bare.skeletons.clear();
    for options in [MERGED, GROUPED] {
        let bytes = write_glb(&model, &options);
        assert_eq!(bytes, write_glb(&bare, &options));
        let read = Read::new(&bytes);
        assert_eq!(read.gltf.skins().len(), 0);
        let text = serde_json::to_string(&read.json).unwrap();
        for absent in ["JOINTS_0", "WEIGHTS_0", "extras", "skins", "Armature"] {
            assert!(!text.contains(absent), "{absent} in {text}");
        }
        assert_eq!(
            write_obj(&model, &options, "m.mtl"),
            write_obj(&bare, &options, "m.mtl")
        );
    }
    assert_eq!(write_stl(&model), write_stl(&bare));
}

#[test]
fn output_is_deterministic() {
    for options in [MERGED, GROUPED] {
        assert_eq!(write_glb(&scene(), &options), write_glb(&scene(), &options));
    }
}

#[test]
fn a_bone_without_its_section_is_an_error_before_anything_is_written() {
    let mut model = scene();
    model.parts[0].bone = bone(0, SectionId(7));
    let mut out = Vec::new();
    let error = write_glb_to(&model, &MERGED, &mut out).unwrap_err();
    assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
    assert_eq!(
        error.to_string(),
        "part 0 ('floor 0') hangs from section 7 of skeleton 0, which the model does not have"
    );
    assert!(out.is_empty());
    model.parts[0].bone = bone(5, SectionId(0));
    let dir =
        std::env::temp_dir().join(format!("shapegram-export-{}-bad-bone", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for file in ["m.glb", "m.obj", "m.stl"] {
        let error = save(&model, &dir.join(file), &MERGED).unwrap_err();
        assert!(
            error.to_string().contains("section 0 of skeleton 5"),
            "{error}"
        );
    }
}

#[test]
fn a_skinned_file_reads_back_in_the_rest_pose_without_bones() {
    let model = scene();
    let back = shapegram_export::read_glb(&write_glb(&model, &GROUPED)).unwrap();
    assert!(back.skeletons.is_empty());
    assert_eq!(back.parts.len(), model.parts.len());
    for part in &model.parts {
        let read = back.parts.iter().find(|p| p.name == part.name).unwrap();
        assert!(read.bone.is_none());
        let (a, b) = (read.mesh.bounds().unwrap(), part.mesh.bounds().unwrap());
        assert!(
            close(a.min, b.min, 1e-6) && close(a.max, b.max, 1e-6),
            "{}",
            part.name
        );
    }
}

/// The scene with named poses: "up" for both skeletons (the tower's middle floor turned the
/// other way, the tree's branch bent up), "down" for the tree only.
fn posed_scene() -> Model {
    let mut model = scene();
    let (mut tower_up, floors) = tower();
    let turn = Pose {
        rotation: DVec3::new(0.0, -60.0, 0.0),
        translation: DVec3::new(0.5, 0.0, 0.0),
    };
    tower_up.set_pose(floors[1], turn).unwrap();
    let bent = |degrees: f64| {
        let (mut tree, sections) = fork();
        let pose = Pose {
            rotation: DVec3::new(0.0, 0.0, degrees),
            translation: DVec3::ZERO,
        };
        tree.set_pose(sections[2], pose).unwrap();
        tree
    };
    model.skeletons[0].add_named_pose("up", &tower_up).unwrap();
    model.skeletons[1]
        .add_named_pose("up", &bent(40.0))
        .unwrap();
    model.skeletons[1]
        .add_named_pose("down", &bent(-30.0))
        .unwrap();
    model
}

#[test]
fn named_poses_become_one_keyframe_animations_of_the_free_joints() {
    let model = posed_scene();
    for options in [MERGED, GROUPED] {
        let bytes = write_glb(&model, &options);
        let read = Read::new(&bytes);
        let animations: Vec<_> = read.gltf.animations().collect();
        let names: Vec<_> = animations.iter().map(|a| a.name().unwrap()).collect();
        assert_eq!(names, ["up", "down"]);
        // One free joint in each skeleton: "up" moves both, "down" the tree only.
        let counts: Vec<_> = animations.iter().map(|a| a.channels().count()).collect();
        assert_eq!(counts, [4, 2]);
        let skins: Vec<_> = read.gltf.skins().collect();
        for animation in &animations {
            let name = animation.name().unwrap();
            let mut seen = Vec::new();
            for channel in animation.channels() {
                let node = channel.target().node().index();
                // The target is a joint node of a skin whose skeleton has the pose.
                let (k, j) = skins
                    .iter()
                    .enumerate()
                    .find_map(|(k, s)| Some((k, s.joints().position(|n| n.index() == node)?)))
                    .expect("every channel targets a joint node");
                let skeleton = &model.skeletons[k];
                let id = skeleton.order()[j];
                assert!(skeleton.section(id).limits().is_free());
                let named = skeleton
                    .named_pose(name)
                    .expect("the skeleton has the pose");
                let local = skeleton.local_in(id, &named.pose(id));
                let sampler = channel.sampler();
                assert_eq!(
                    sampler.interpolation(),
                    gltf::animation::Interpolation::Linear
                );
                let input = sampler.input();
                assert_eq!(input.count(), 1);
                assert_eq!(input.min(), Some(json!([0.0])));
                assert_eq!(input.max(), Some(json!([0.0])));
                let output = sampler.output();
                assert_eq!(output.count(), 1);
                assert_eq!(output.data_type(), DataType::F32);
                for accessor in [&input, &output] {
                    let view = accessor.view().unwrap();
                    assert_eq!(view.target(), None);
                    assert_eq!(view.offset() % 4, 0);
                }
                let reader = channel.reader(|_| Some(read.blob()));
                let times: Vec<f32> = reader.read_inputs().unwrap().collect();
                assert_eq!(times, [0.0]);
                match reader.read_outputs().unwrap() {
                    gltf::animation::util::ReadOutputs::Translations(t) => {
                        let t: Vec<[f32; 3]> = t.collect();
                        assert_eq!(t, [local.translation.as_vec3().to_array()]);
                        seen.push((node, "translation"));
                    }
                    gltf::animation::util::ReadOutputs::Rotations(r) => {
                        let r: Vec<[f32; 4]> = r.into_f32().collect();
                        let q = local.rotation.normalize().as_quat().to_array();
                        assert!(
                            r[0].iter().zip(q).all(|(a, b)| (a - b).abs() < 1e-7),
                            "{r:?} vs {q:?}"
                        );
                        seen.push((node, "rotation"));
                    }
                    _ => panic!("only translations and rotations"),
                }
            }
            // A translation and a rotation per joint, never two of one kind.
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len(), animation.channels().count());
        }
        // The joint nodes still carry the current pose.
        let tower = &model.skeletons[0];
        let middle = tower.order()[1];
        let node = skins[0].joints().nth(1).unwrap();
        let (t, _, _) = node.transform().decomposed();
        assert_eq!(t, tower.local(middle).translation.as_vec3().to_array());
    }
}

#[test]
fn files_without_named_poses_have_no_animations_and_merged_rigs_keep_them() {
    let read = Read::new(&write_glb(&scene(), &MERGED));
    assert!(read.json.get("animations").is_none());
    let merged = posed_scene().with_free_joints_only();
    let read = Read::new(&write_glb(&merged, &MERGED));
    let counts: Vec<_> = read
        .gltf
        .animations()
        .map(|a| (a.name().unwrap().to_owned(), a.channels().count()))
        .collect();
    assert_eq!(counts, [("up".to_owned(), 4), ("down".to_owned(), 2)]);
}
