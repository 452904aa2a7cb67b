//! Parts that repeat a prototype ([`Part::instance`]) in GLB: one mesh placed by nodes or by
//! `EXT_mesh_gpu_instancing`, as [`Instancing`] asks, read back as the same triangles.

use crate::common;

use std::collections::HashMap;
use std::sync::Arc;

use common::*;
use serde_json::Value;
use shapegram_export::{ExportOptions, Instancing, read_glb, write_glb, write_obj};
use shapegram_geom::kinematics::{Frame, Skeleton};
use shapegram_geom::primitives::{cone, cuboid};
use shapegram_geom::{
    Bone, Color, DAffine3, DQuat, DVec3, Instance, Mesh, MetaValue, Metadata, Model, Part,
};

const GREEN: Color = Color::rgb(0.2, 0.6, 0.2);

fn options(instancing: Instancing) -> ExportOptions {
    ExportOptions {
        instancing,
        ..ExportOptions::default()
    }
}

/// Where copy `i` of the prototype goes: turned about y, scaled unevenly, moved along a grid.
fn placement(i: usize) -> DAffine3 {
    let scale = DVec3::new(1.0 + (i % 3) as f64, 2.0, 0.5 + (i % 2) as f64);
    let turn = DQuat::from_rotation_y(0.3 * i as f64);
    let at = DVec3::new(3.0 * (i % 10) as f64, 0.25, 4.0 * (i / 10) as f64);
    DAffine3::from_scale_rotation_translation(scale, turn, at)
}

/// A copy of `prototype` placed by `transform`, as the engine hands it over.
fn copy(prototype: &Mesh, id: u32, transform: DAffine3, color: Color) -> Part {
    Part {
        instance: Some(Instance {
            prototype: id,
            transform,
        }),
        ..Part::new(
            "Crown".to_owned(),
            color,
            prototype.transformed(&transform),
            Vec::new(),
        )
    }
}

/// A ground part and fifty copies of one cone.
fn orchard() -> Model {
    let crown = cone(DVec3::ONE, 12);
    let mut parts = vec![Part::new(
        "Ground".to_owned(),
        GREY,
        cuboid(DVec3::new(30.0, 0.2, 20.0)),
        Vec::new(),
    )];
    parts.extend((0..50).map(|i| copy(&crown, 0, placement(i), GREEN)));
    Model {
        parts,
        ..Model::default()
    }
}

fn meshes_of(json: &Value) -> usize {
    json["meshes"].as_array().unwrap().len()
}

/// The nodes that draw mesh `mesh`.
fn nodes_of(json: &Value, mesh: u64) -> Vec<&Value> {
    json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|n| n["mesh"].as_u64() == Some(mesh))
        .collect()
}

/// Every triangle of a model, as its three corners.
fn triangles(model: &Model) -> Vec<[DVec3; 3]> {
    let mut all = Vec::new();
    for part in &model.parts {
        let mesh = &part.mesh;
        for f in 0..mesh.face_count() {
            let face = mesh.face(f);
            for k in 1..face.len() - 1 {
                all.push([face[0], face[k], face[k + 1]].map(|v| mesh.position(v)));
            }
        }
    }
    all
}

/// Whether two files' models draw the same triangles, corners within 0.1 mm (f32 rounding)
/// and in the same turning order, whatever the order of triangles and corners.
fn same_triangles(a: &Model, b: &Model) -> bool {
    let (a, b) = (triangles(a), triangles(b));
    if a.len() != b.len() {
        return false;
    }
    let cell = |t: &[DVec3; 3]| {
        let c = (t[0] + t[1] + t[2]) / 3.0 * 100.0;
        [c.x, c.y, c.z].map(|x| x.floor() as i64)
    };
    let mut cells: HashMap<[i64; 3], Vec<[DVec3; 3]>> = HashMap::new();
    for t in a {
        cells.entry(cell(&t)).or_default().push(t);
    }
    let same = |x: &[DVec3; 3], y: &[DVec3; 3]| {
        (0..3).any(|r| (0..3).all(|i| x[i].distance(y[(i + r) % 3]) < 1e-4))
    };
    b.iter().all(|t| {
        let [x, y, z] = cell(t);
        let near = (-1..=1)
            .flat_map(|i| (-1..=1).flat_map(move |j| (-1..=1).map(move |k| [x + i, y + j, z + k])));
        for key in near {
            if let Some(list) = cells.get_mut(&key)
                && let Some(at) = list.iter().position(|u| same(u, t))
            {
                list.swap_remove(at);
                return true;
            }
        }
        false
    })
}

#[test]
fn nodes_draw_one_mesh_fifty_times() {
    let model = orchard();
    let bytes = write_glb(&model, &options(Instancing::Nodes));
    let (json, _) = split_glb(&bytes);
    assert_eq!(meshes_of(&json), 2, "the ground's mesh and the crown's");
    let crowns = nodes_of(&json, 1);
    assert_eq!(crowns.len(), 50);
    for (i, node) in crowns.iter().enumerate() {
        assert_eq!(node["name"], "Crown");
        let (scale, _, translation) = placement(i).to_scale_rotation_translation();
        let floats = |v: &Value| -> Vec<f64> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        let near = |a: Vec<f64>, b: DVec3| {
            a.iter()
                .zip(b.to_array())
                .all(|(x, y)| (x - y).abs() < 1e-5)
        };
        assert!(near(floats(&node["scale"]), scale), "{node}");
        assert!(near(floats(&node["translation"]), translation), "{node}");
        assert_eq!(floats(&node["rotation"]).len(), 4);
    }
    assert!(json.get("extensionsUsed").is_none());
}

#[test]
fn gpu_instancing_draws_one_node_with_fifty_transforms() {
    let bytes = write_glb(&orchard(), &options(Instancing::Gpu));
    let (json, _) = split_glb(&bytes);
    assert_eq!(meshes_of(&json), 2);
    let crowns = nodes_of(&json, 1);
    assert_eq!(crowns.len(), 1);
    let attributes = &crowns[0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
    for (name, kind) in [
        ("TRANSLATION", "VEC3"),
        ("ROTATION", "VEC4"),
        ("SCALE", "VEC3"),
    ] {
        let accessor = &json["accessors"][attributes[name].as_u64().unwrap() as usize];
        assert_eq!(accessor["count"], 50, "{name}");
        assert_eq!(accessor["type"], kind, "{name}");
        assert_eq!(accessor["componentType"], 5126, "{name}: f32");
    }
    assert_eq!(
        json["extensionsUsed"],
        serde_json::json!(["EXT_mesh_gpu_instancing"])
    );
    // Readers that lack the extension still read the file.
    assert!(json.get("extensionsRequired").is_none());
}

#[test]
fn instanced_files_are_smaller_and_read_back_as_the_flat_triangles() {
    let model = orchard();
    let flat = write_glb(&model, &options(Instancing::None));
    let nodes = write_glb(&model, &options(Instancing::Nodes));
    let gpu = write_glb(&model, &options(Instancing::Gpu));
    let auto = write_glb(&model, &options(Instancing::Auto));
    assert!(nodes.len() < flat.len(), "{} < {}", nodes.len(), flat.len());
    assert!(gpu.len() < nodes.len(), "{} < {}", gpu.len(), nodes.len());
    assert_eq!(auto, gpu, "fifty cones: GPU instancing is the smallest");
    let expected = read_glb(&flat).unwrap();
    assert_eq!(
        triangles(&expected).len(),
        12 + 50 * 22,
        "a box and fifty 12-sided cones"
    );
    for (what, bytes) in [("nodes", &nodes), ("gpu", &gpu)] {
        let read = read_glb(bytes).unwrap();
        assert_eq!(read.parts.len(), 51, "{what}: the ground and fifty crowns");
        assert!(same_triangles(&read, &expected), "{what}");
    }
    // The check sees crowns out of place.
    let mut moved = expected.clone();
    moved.parts[1]
        .mesh
        .transform(&DAffine3::from_translation(DVec3::X * 1e-3));
    assert!(!same_triangles(&moved, &expected));
}

#[test]
fn writing_is_deterministic() {
    let model = orchard();
    for instancing in [Instancing::Nodes, Instancing::Gpu, Instancing::Auto] {
        assert_eq!(
            write_glb(&model, &options(instancing)),
            write_glb(&model.clone(), &options(instancing)),
            "{instancing:?}"
        );
    }
}

#[test]
fn without_instancing_the_file_is_as_if_no_part_repeated() {
    let mut model = orchard();
    let instanced = write_glb(&model, &options(Instancing::None));
    for part in &mut model.parts {
        part.instance = None;
    }
    assert_eq!(instanced, write_glb(&model, &options(Instancing::Auto)));
}

#[test]
fn obj_stays_flat() {
    let model = orchard();
    let plain = {
        let mut plain = model.clone();
        plain.parts.iter_mut().for_each(|p| p.instance = None);
        plain
    };
    let (obj, mtl) = write_obj(&model, &ExportOptions::default(), "m.mtl");
    assert_eq!(
        (obj, mtl),
        write_obj(&plain, &ExportOptions::default(), "m.mtl")
    );
}

#[test]
fn materials_part_the_copies_of_one_prototype() {
    let crown = cone(DVec3::ONE, 12);
    let red = Color::rgb(0.8, 0.1, 0.1);
    let parts = (0..6)
        .map(|i| {
            copy(
                &crown,
                0,
                placement(i),
                if i % 2 == 0 { GREEN } else { red },
            )
        })
        .collect();
    let model = Model {
        parts,
        ..Model::default()
    };
    let (json, _) = split_glb(&write_glb(&model, &options(Instancing::Nodes)));
    assert_eq!(meshes_of(&json), 2, "a mesh per material");
    assert_eq!(nodes_of(&json, 0).len(), 3);
    assert_eq!(nodes_of(&json, 1).len(), 3);
    assert_ne!(
        json["meshes"][0]["primitives"][0]["material"],
        json["meshes"][1]["primitives"][0]["material"]
    );
}

#[test]
fn a_prototype_used_once_and_small_copies_stay_flat() {
    let triangle = Mesh::from_faces(
        vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        [[0u32, 1, 2]].as_slice(),
    );
    let mut parts = vec![copy(&cone(DVec3::ONE, 12), 0, placement(0), GREEN)];
    parts.extend((0..2).map(|i| copy(&triangle, 1, placement(i + 1), GREEN)));
    let model = Model {
        parts,
        ..Model::default()
    };
    // Auto: two triangles cost less flat than an instancing node.
    let auto = write_glb(&model, &options(Instancing::Auto));
    let (json, _) = split_glb(&auto);
    assert_eq!(meshes_of(&json), 1);
    assert!(json.get("extensionsUsed").is_none());
    // Nodes: the triangle twice by nodes, the cone (used once) merged with nothing else.
    let (json, _) = split_glb(&write_glb(&model, &options(Instancing::Nodes)));
    assert_eq!(meshes_of(&json), 2);
    assert_eq!(nodes_of(&json, 1).len(), 2);
}

#[test]
fn skinned_parts_are_never_instanced() {
    let mut model = orchard();
    let skeleton = Skeleton::new(Frame::IDENTITY, "Orchard");
    let root = skeleton.root();
    model.skeletons.push(skeleton);
    for part in &mut model.parts {
        part.bone = Some(Bone {
            skeleton: 0,
            section: root,
        });
    }
    let (json, _) = split_glb(&write_glb(&model, &options(Instancing::Gpu)));
    assert!(json.get("extensionsUsed").is_none());
    let nodes = json["nodes"].as_array().unwrap();
    assert!(nodes.iter().all(|n| n.get("scale").is_none()));
    assert_eq!(meshes_of(&json), 1, "one skinned mesh");
}

#[test]
fn metadata_goes_into_each_use_node() {
    let mut model = orchard();
    for (i, part) in model.parts.iter_mut().enumerate().skip(1) {
        part.metadata = Some(Arc::new(Metadata {
            rule: Some("Crown".to_owned()),
            path: Some(format!("Lot[0]/Spot[{i}]/Crown[0]")),
            attributes: vec![("height".to_owned(), MetaValue::Number(i as f64))],
            ..Metadata::default()
        }));
    }
    // GPU instancing has no place for per-copy metadata: the copies keep their nodes.
    let bytes = write_glb(&model, &options(Instancing::Gpu));
    let (json, _) = split_glb(&bytes);
    let crowns = nodes_of(&json, 1);
    assert_eq!(crowns.len(), 50);
    assert!(json.get("extensionsUsed").is_none());
    let last = &crowns[49]["extras"]["shapegram"];
    assert_eq!(
        *last,
        serde_json::json!({
            "rule": "Crown",
            "path": "Lot[0]/Spot[50]/Crown[0]",
            "goals": [],
            "tags": [],
            "attributes": {"height": 50.0},
        })
    );
}

#[test]
fn uses_hang_under_the_node_of_their_lot() {
    let lot = |k: usize, area: f64| {
        Arc::new(Metadata {
            rule: Some("Lot".to_owned()),
            path: Some(format!("Lot[{k}]")),
            leaves: Some(25),
            reports: Some(vec![
                ("lot.area_n".to_owned(), MetaValue::Number(1.0)),
                ("lot.area_sum".to_owned(), MetaValue::Number(area)),
            ]),
            ..Metadata::default()
        })
    };
    let lots = [lot(0, 200.0), lot(1, 48.0)];
    let mut model = orchard();
    for (i, part) in model.parts.iter_mut().enumerate().skip(1) {
        part.metadata = Some(Arc::new(Metadata {
            rule: Some("Crown".to_owned()),
            reports: Some(Vec::new()),
            lot: Some(lots[i % 2].clone()),
            ..Metadata::default()
        }));
    }
    let bytes = write_glb(&model, &options(Instancing::Gpu));
    let (json, _) = split_glb(&bytes);
    let nodes = json["nodes"].as_array().unwrap();
    // The root, the ground, two lots and fifty crowns; the lots come before their first use.
    assert_eq!(nodes.len(), 54);
    assert_eq!(json["nodes"][0]["children"], serde_json::json!([1, 2, 4]));
    assert_eq!(nodes[2]["name"], "Lot[1]");
    assert_eq!(nodes[4]["name"], "Lot[0]");
    assert!(nodes[2].get("mesh").is_none());
    assert_eq!(
        nodes[4]["extras"]["shapegram"],
        serde_json::json!({
            "rule": "Lot",
            "path": "Lot[0]",
            "leaves": 25,
            "goals": [],
            "tags": [],
            "attributes": {},
            "reports": {"lot.area_n": 1.0, "lot.area_sum": 200.0},
        })
    );
    for lot in [2, 4] {
        let children = nodes[lot]["children"].as_array().unwrap();
        assert_eq!(children.len(), 25);
        for child in children {
            let crown = &nodes[child.as_u64().unwrap() as usize];
            assert_eq!(
                crown["extras"]["shapegram"]["reports"],
                serde_json::json!({})
            );
        }
    }
    // The lots' nodes have no transformation: the file reads back as the flat one.
    let flat = read_glb(&write_glb(&orchard(), &options(Instancing::None))).unwrap();
    let back = read_glb(&bytes).unwrap();
    assert_eq!(
        back.merged_mesh().face_count(),
        flat.merged_mesh().face_count()
    );
    assert!((back.merged_mesh().area() - flat.merged_mesh().area()).abs() < 1e-6);
}

#[test]
fn broken_instancing_data_is_an_error_not_a_panic() {
    let bytes = write_glb(&orchard(), &options(Instancing::Gpu));
    let (json, bin) = split_glb(&bytes);
    let node = json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n.get("extensions").is_some())
        .unwrap();
    let attributes = [
        "nodes",
        &node.to_string(),
        "extensions",
        "EXT_mesh_gpu_instancing",
        "attributes",
    ];
    let broken = |edit: &dyn Fn(&mut Value)| {
        let mut json = json.clone();
        let mut at = &mut json;
        for key in attributes {
            at = match key.parse::<usize>() {
                Ok(i) => &mut at[i],
                Err(_) => &mut at[key],
            };
        }
        edit(at);
        read_glb(&frame_glb(&json, &bin)).unwrap_err().to_string()
    };
    let missing = broken(&|a| a["TRANSLATION"] = 999.into());
    assert!(
        missing.contains("EXT_mesh_gpu_instancing: TRANSLATION names no accessor"),
        "{missing}"
    );
    // The ground's indices: not VEC3 floats.
    let indices = json["meshes"][0]["primitives"][0]["indices"].clone();
    let wrong = broken(&|a| a["SCALE"] = indices.clone());
    assert!(wrong.contains("SCALE: unexpected type"), "{wrong}");
    let none = broken(&|a| *a = serde_json::json!({}));
    assert!(none.contains("no attributes"), "{none}");
}
