//! Write → read round trips of every format, and the structure of what is written.

use crate::common;

use common::*;
use serde_json::{Value, json};
use shapegram_export::{
    ExportOptions, FlatNormals, GlbEncoding, Instancing, read_glb, read_obj, read_stl, write_glb,
    write_glb_with_layout, write_obj, write_stl,
};
use shapegram_geom::extrude::extrude_polygon;
use shapegram_geom::primitives::{cuboid, sphere};
use shapegram_geom::{Color, DVec3, Mesh, Model, Part};

// Flat normals written: these round trips check the per-corner layout (each face its own
// corners, with its normal) that `--normals` keeps; tests/compact.rs checks the default.
const GROUPED: ExportOptions = ExportOptions {
    group_by_part: true,
    encoding: GlbEncoding::Float,
    instancing: Instancing::Auto,
    flat_normals: FlatNormals::Written,
};
const MERGED: ExportOptions = ExportOptions {
    group_by_part: false,
    encoding: GlbEncoding::Float,
    instancing: Instancing::Auto,
    flat_normals: FlatNormals::Written,
};

/// Checks a part read from a flat-shaded per-corner format against the original meshes.
fn check_flat(read: &Part, originals: &[&Mesh], closed: bool) {
    let want = expected(originals);
    let name = &read.name;
    assert_eq!(read.mesh.face_count(), want.triangles, "{name}: triangles");
    assert_eq!(read.mesh.vertex_count(), want.corners, "{name}: vertices");
    assert_eq!(read.mesh.bounds(), Some(want.bounds_f32), "{name}: bounds");
    let welded = read.mesh.welded(1e-6);
    assert_eq!(
        welded.vertex_count(),
        want.vertices,
        "{name}: welded vertices"
    );
    if closed {
        assert!(welded.is_watertight(), "{name}: {:?}", welded.edge_report());
        assert_close(welded.signed_volume(), want.volume, 1e-4, name);
    } else {
        assert!(!welded.is_watertight(), "{name} is open");
    }
}

#[test]
fn glb_round_trip_one_node_per_part() {
    let model = sample_model();
    let back = read_glb(&write_glb(&model, &GROUPED)).unwrap();
    let names: Vec<&str> = back.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        ["front wall", "roof", "column", "dome", "spire", "lot"]
    );
    for (read, original) in back.parts.iter().zip(&model.parts) {
        // Colours travel as linear light: equal to the 8-bit precision they were written with.
        assert_eq!(
            read.color.to_hex(),
            original.color.to_hex(),
            "{}",
            read.name
        );
        check_flat(read, &[&original.mesh], original.name != "lot");
    }
    // The lot is one quad: two triangles sharing four vertices, all on its boundary.
    let lot = back.parts[5].mesh.welded(1e-6);
    assert_eq!(lot.edge_report().boundary, 4);
}

#[test]
fn glb_round_trip_one_primitive_per_colour() {
    let model = sample_model();
    let back = read_glb(&write_glb(&model, &MERGED)).unwrap();
    let colours: Vec<String> = back.parts.iter().map(|p| p.color.to_hex()).collect();
    assert_eq!(colours, [RED, BLUE, GREEN, GLASS, GREY].map(|c| c.to_hex()));
    assert!(back.parts.iter().all(|p| p.name == "model"));
    let p = &model.parts;
    check_flat(&back.parts[0], &[&p[0].mesh, &p[2].mesh], true);
    check_flat(&back.parts[1], &[&p[1].mesh], true);
    check_flat(&back.parts[2], &[&p[3].mesh], true);
    check_flat(&back.parts[3], &[&p[4].mesh], true);
    check_flat(&back.parts[4], &[&p[5].mesh], false);
}

#[test]
fn glb_json_has_materials_nodes_and_exact_bounds() {
    let model = sample_model();
    let bytes = write_glb(&model, &GROUPED);
    let (json, bin) = split_glb(&bytes);
    assert_eq!(
        json["asset"],
        json!({"generator": format!("shapegram {}", env!("CARGO_PKG_VERSION")), "version": "2.0"})
    );
    assert_eq!(json["scene"], 0);
    assert_eq!(json["scenes"], json!([{"nodes": [0]}]));
    assert_eq!(
        json["nodes"][0],
        json!({"name": "shapegram", "children": [1, 2, 3, 4, 5, 6]})
    );
    for (i, part) in model.parts.iter().enumerate() {
        let node = &json["nodes"][i + 1];
        assert_eq!(node["name"], part.name.as_str());
        assert_eq!(node["mesh"], i);
        assert_eq!(json["meshes"][i]["name"], part.name.as_str());
    }

    let materials = json["materials"].as_array().unwrap();
    let names: Vec<&str> = materials
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["#ff0000", "#0000ff", "#008000", "#33669980", "#808080"]
    );
    assert_eq!(materials[3]["alphaMode"], "BLEND");
    // sRGB 0.2, 0.4, 0.6 in linear light; alpha stays.
    let factor: Vec<f64> = materials[3]["pbrMetallicRoughness"]["baseColorFactor"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    for (got, want) in factor.iter().zip([0.033105, 0.132868, 0.318547, 0.5]) {
        assert!((got - want).abs() < 1e-6, "{factor:?}");
    }
    for m in materials {
        assert_eq!(m["doubleSided"], false);
        assert_eq!(m["pbrMetallicRoughness"]["metallicFactor"], 0.0);
        assert_eq!(m["pbrMetallicRoughness"]["roughnessFactor"], 0.9);
    }
    assert_eq!(materials[0]["alphaMode"], "OPAQUE");
    // Wall and column share the red material.
    let material_of = |mesh: usize| {
        json["meshes"][mesh]["primitives"][0]["material"]
            .as_u64()
            .unwrap()
    };
    assert_eq!([0, 1, 2, 3, 4, 5].map(material_of), [0, 1, 0, 2, 3, 4]);

    let accessors = json["accessors"].as_array().unwrap();
    let views = json["bufferViews"].as_array().unwrap();
    assert_eq!(json["buffers"], json!([{"byteLength": bin.len()}]));
    for view in views {
        assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0);
        assert!(view.get("byteStride").is_none());
        assert!([34962, 34963].contains(&view["target"].as_u64().unwrap()));
    }
    let f32_at = |offset: usize| f32::from_le_bytes(bin[offset..offset + 4].try_into().unwrap());
    for (i, part) in model.parts.iter().enumerate() {
        let primitive = &json["meshes"][i]["primitives"][0];
        assert_eq!(
            primitive["mode"],
            Value::Null,
            "triangles is the default mode"
        );
        let position = &accessors[primitive["attributes"]["POSITION"].as_u64().unwrap() as usize];
        let want = expected(&[&part.mesh]);
        let lo = want.bounds_f32.min.as_vec3();
        let hi = want.bounds_f32.max.as_vec3();
        assert_eq!(position["min"], json!([lo.x, lo.y, lo.z]), "{}", part.name);
        assert_eq!(position["max"], json!([hi.x, hi.y, hi.z]), "{}", part.name);
        assert_eq!(position["count"], want.corners);
        assert_eq!(position["componentType"], 5126);
        assert_eq!(position["type"], "VEC3");
        let indices = &accessors[primitive["indices"].as_u64().unwrap() as usize];
        assert_eq!(indices["count"], 3 * want.triangles);
        assert_eq!(
            indices["componentType"], 5123,
            "u16 indices for small meshes"
        );

        let normal = &accessors[primitive["attributes"]["NORMAL"].as_u64().unwrap() as usize];
        assert_eq!(normal["count"], want.corners);
        let view = &views[normal["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap() as usize;
        for k in 0..want.corners {
            let n = [0, 1, 2].map(|c| f32_at(start + 12 * k + 4 * c));
            let length = n.iter().map(|c| c * c).sum::<f32>().sqrt();
            assert!((length - 1.0).abs() < 1e-6, "{}: normal {n:?}", part.name);
        }
    }
}

#[test]
fn glb_normals_are_face_normals() {
    let model = Model::single("box", RED, cuboid(DVec3::ONE));
    let (json, bin) = split_glb(&write_glb(&model, &GROUPED));
    let normal = &json["accessors"][1];
    let start = json["bufferViews"][normal["bufferView"].as_u64().unwrap() as usize]["byteOffset"]
        .as_u64()
        .unwrap() as usize;
    let normals: Vec<[f32; 3]> = (0..24)
        .map(|k| {
            [0, 1, 2].map(|c| {
                let at = start + 12 * k + 4 * c;
                f32::from_le_bytes(bin[at..at + 4].try_into().unwrap())
            })
        })
        .collect();
    // Faces in cuboid order (-x, +x, -y, +y, -z, +z), four corners each.
    let faces = [
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, -1.0],
        [0.0, 0.0, 1.0],
    ];
    let want: Vec<[f32; 3]> = faces.iter().flat_map(|n| [*n; 4]).collect();
    assert_eq!(normals, want);
}

#[test]
fn glb_parses_with_the_gltf_crate() {
    let bytes = write_glb(&sample_model(), &GROUPED);
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    assert_eq!(gltf.meshes().len(), 6);
    assert_eq!(gltf.materials().len(), 5);
    assert_eq!(gltf.nodes().len(), 7);
    let scene = gltf.default_scene().unwrap();
    let roots: Vec<_> = scene.nodes().collect();
    assert_eq!(roots.len(), 1);
    assert_eq!(roots[0].name(), Some("shapegram"));
    assert_eq!(roots[0].children().len(), 6);
    let blob = gltf.blob.as_deref().unwrap();
    assert_eq!(blob.len(), gltf.buffers().next().unwrap().length());
    let dome = gltf.meshes().nth(3).unwrap().primitives().next().unwrap();
    let reader = dome.reader(|_| Some(blob));
    let want = expected(&[&sample_model().parts[3].mesh]);
    assert_eq!(reader.read_positions().unwrap().len(), want.corners);
    assert_eq!(
        reader.read_indices().unwrap().into_u32().len(),
        3 * want.triangles
    );
}

#[test]
fn glb_of_an_empty_model_is_valid_and_reads_back_empty() {
    // One part with no faces, one whose only triangle collapses in f32, one with NaN.
    let collapsed = Mesh::from_polygon(&[
        DVec3::new(1e6, 0.0, 0.0),
        DVec3::new(1e6 + 0.01, 0.0, 0.0),
        DVec3::new(1e6, 0.0, 0.01),
    ]);
    let nan = Mesh::from_polygon(&[DVec3::ZERO, DVec3::X, DVec3::new(f64::NAN, 1.0, 0.0)]);
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![
            Part::default(),
            Part {
                name: "sliver".into(),
                color: RED,
                mesh: collapsed,
                ..Part::default()
            },
            Part {
                name: "nan".into(),
                color: BLUE,
                mesh: nan,
                ..Part::default()
            },
        ],
        lines: Vec::new(),
    };
    for options in [GROUPED, MERGED] {
        let bytes = write_glb(&model, &options);
        assert_eq!(bytes, write_glb(&Model::default(), &options));
        let (json, bin) = split_glb(&bytes);
        assert!(bin.is_empty());
        assert_eq!(json["nodes"], json!([{"name": "shapegram"}]));
        for key in ["meshes", "materials", "accessors", "bufferViews", "buffers"] {
            assert!(json.get(key).is_none(), "{key} should be absent");
        }
        assert!(gltf::Gltf::from_slice(&bytes).is_ok());
        assert!(read_glb(&bytes).unwrap().parts.is_empty());
    }
    assert_eq!(write_stl(&model).len(), 84);
    // OBJ keeps f64 coordinates, so the sliver survives there; the empty and NaN parts do not.
    let (obj, mtl) = write_obj(&model, &GROUPED, "m.mtl");
    let groups: Vec<&str> = obj.lines().filter(|l| l.starts_with("o ")).collect();
    assert_eq!(groups, ["o sliver"]);
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 3);
    assert_eq!(mtl.matches("newmtl").count(), 1);
}

#[test]
fn large_primitives_split_into_u16_pieces_unless_their_order_must_stay() {
    let model = Model::single("ball", GREEN, sphere(DVec3::splat(2.0), 160, 120));
    let want = expected(&[&model.parts[0].mesh]);
    assert!(want.corners > 65535);
    // Triangles in face order (the studio's layout): one primitive, u32 indices.
    let mut bytes = Vec::new();
    write_glb_with_layout(&model, &MERGED, &mut bytes).unwrap();
    let (json, _) = split_glb(&bytes);
    assert_eq!(json["accessors"][0]["count"], want.corners);
    assert_eq!(json["accessors"][2]["componentType"], 5125);
    let back = read_glb(&bytes).unwrap();
    check_flat(&back.parts[0], &[&model.parts[0].mesh], true);
    // Otherwise pieces of fewer than 65,535 vertices with u16 indices, every triangle kept.
    let (json, _) = split_glb(&write_glb(&model, &MERGED));
    let primitives = json["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 2);
    let mut triangles = 0;
    for primitive in primitives {
        let accessor = |key: &str| &json["accessors"][primitive[key].as_u64().unwrap() as usize];
        let positions =
            &json["accessors"][primitive["attributes"]["POSITION"].as_u64().unwrap() as usize];
        assert!(positions["count"].as_u64().unwrap() < 65535);
        assert_eq!(accessor("indices")["componentType"], 5123);
        triangles += accessor("indices")["count"].as_u64().unwrap() / 3;
    }
    assert_eq!(triangles as usize, want.triangles);
}

#[test]
fn glb_reader_applies_node_transforms() {
    let model = Model::single("box", RED, cuboid(DVec3::new(1.0, 2.0, 3.0)));
    let (mut json, bin) = split_glb(&write_glb(&model, &GROUPED));
    // A mirroring, scaling parent and a translated child: world = parent · child.
    json["nodes"][0]["scale"] = json!([-1.0, 2.0, 1.0]);
    json["nodes"][1]["translation"] = json!([10.0, 0.0, 0.0]);
    let back = read_glb(&frame_glb(&json, &bin)).unwrap();
    let bounds = back.parts[0].mesh.bounds().unwrap();
    assert_eq!(bounds.min, DVec3::new(-11.0, 0.0, 0.0));
    assert_eq!(bounds.max, DVec3::new(-10.0, 4.0, 3.0));
    let welded = back.parts[0].mesh.welded(1e-6);
    assert!(welded.is_watertight());
    // The mirror must not turn the box inside out.
    assert_close(welded.signed_volume(), 12.0, 1e-12, "volume");
}

#[test]
fn glb_reader_turns_strips_and_fans_into_triangles() {
    // A unit square in the xz-plane facing +y, as a strip and as a fan, without indices.
    let square = [
        [0.0f32, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [1.0, 0.0, 1.0],
    ];
    let fan = [
        [0.0f32, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
    ];
    let mut bin = Vec::new();
    for p in square.iter().chain(&fan) {
        for c in p {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let accessor = |view: usize| {
        json!({"bufferView": view, "componentType": 5126, "count": 4, "type": "VEC3",
               "min": [0.0, 0.0, 0.0], "max": [1.0, 0.0, 1.0]})
    };
    let json = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48}
        ],
        "accessors": [accessor(0), accessor(1)],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0}, "mode": 5},
            {"attributes": {"POSITION": 1}, "mode": 6},
            {"attributes": {"POSITION": 0}, "mode": 1}
        ]}],
        "nodes": [{"mesh": 0, "name": "square"}],
        "scenes": [{"nodes": [0]}]
    });
    let back = read_glb(&frame_glb(&json, &bin)).unwrap();
    assert_eq!(back.parts.len(), 2, "the line primitive is skipped");
    for part in &back.parts {
        assert_eq!(part.name, "square");
        assert_eq!(part.color.to_hex(), "#ffffff", "glTF's default material");
        assert_eq!(part.mesh.face_count(), 2);
        for f in 0..2 {
            assert_eq!(part.mesh.face_normal(f), DVec3::Y);
        }
        assert_close(part.mesh.area(), 1.0, 1e-12, "area");
    }
}

#[test]
fn obj_round_trip_keeps_polygons_and_exact_positions() {
    let model = sample_model();
    let (obj, _) = write_obj(&model, &GROUPED, "model.mtl");
    let back = read_obj(&obj).unwrap();
    let names: Vec<&str> = back.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        ["front_wall", "roof", "column", "dome", "spire", "lot"]
    );
    for (read, original) in back.parts.iter().zip(&model.parts) {
        let want = expected(&[&original.mesh]);
        let name = &read.name;
        assert_eq!(
            read.color,
            Color::default(),
            "{name}: no MTL, default colour"
        );
        assert_eq!(read.mesh.face_count(), want.faces, "{name}: polygons kept");
        assert_eq!(read.mesh.vertex_count(), want.vertices, "{name}");
        // Shortest round-trip formatting: positions come back exactly (tobj orders them by
        // first use, so compare sorted).
        let sorted = |m: &Mesh| {
            let mut p: Vec<[f64; 3]> = m.positions().iter().map(|p| p.to_array()).collect();
            p.sort_by(|a, b| a.partial_cmp(b).unwrap());
            p
        };
        assert_eq!(sorted(&read.mesh), sorted(&original.mesh), "{name}");
        assert_eq!(read.mesh.bounds(), Some(want.bounds), "{name}");
        let sizes: Vec<usize> = read.mesh.faces().map(<[u32]>::len).collect();
        let original_sizes: Vec<usize> = original.mesh.faces().map(<[u32]>::len).collect();
        assert_eq!(sizes, original_sizes, "{name}");
        if original.name != "lot" {
            assert!(read.mesh.is_watertight(), "{name}");
            assert!(read.mesh.welded(1e-6).is_watertight(), "{name}");
            assert_close(read.mesh.signed_volume(), want.volume, 1e-12, name);
        }
    }
}

#[test]
fn obj_text_has_groups_materials_and_normals() {
    let model = sample_model();
    let (obj, mtl) = write_obj(&model, &GROUPED, "model.mtl");
    let lines: Vec<&str> = obj.lines().collect();
    assert_eq!(
        lines[0],
        format!("# shapegram {}", env!("CARGO_PKG_VERSION"))
    );
    assert_eq!(lines[1], "mtllib model.mtl");
    assert_eq!(lines[2], "o front_wall");
    assert_eq!(lines[3], "usemtl color_ff0000");
    assert_eq!(lines[4], "v 0.1 0 0");
    assert_eq!(lines[5], "v 2.1 0 0");
    let first_face = lines.iter().find(|l| l.starts_with("f ")).unwrap();
    assert_eq!(*first_face, "f 1//1 5//1 7//1 3//1");
    let groups: Vec<&str> = lines
        .iter()
        .filter(|l| l.starts_with("o "))
        .copied()
        .collect();
    assert_eq!(
        groups,
        [
            "o front_wall",
            "o roof",
            "o column",
            "o dome",
            "o spire",
            "o lot"
        ]
    );
    let materials: Vec<&str> = lines
        .iter()
        .filter(|l| l.starts_with("usemtl "))
        .copied()
        .collect();
    assert_eq!(
        materials,
        [
            "usemtl color_ff0000",
            "usemtl color_0000ff",
            "usemtl color_ff0000",
            "usemtl color_008000",
            "usemtl color_33669980",
            "usemtl color_808080"
        ]
    );
    let count = |prefix: &str| lines.iter().filter(|l| l.starts_with(prefix)).count();
    let faces: usize = model.parts.iter().map(|p| p.mesh.face_count()).sum();
    let vertices: usize = model.parts.iter().map(|p| p.mesh.vertex_count()).sum();
    assert_eq!(count("f "), faces);
    assert_eq!(count("vn "), faces);
    assert_eq!(count("v "), vertices);
    // The last face refers to the last vertex and normal: indices are global and 1-based.
    assert_eq!(
        lines.last().unwrap(),
        &format!(
            "f {a}//{faces} {b}//{faces} {c}//{faces} {vertices}//{faces}",
            a = vertices - 3,
            b = vertices - 2,
            c = vertices - 1
        )
    );
    assert_eq!(
        mtl,
        format!(
            "# shapegram {}\n\
             \nnewmtl color_ff0000\nKd 1 0 0\nd 1\n\
             \nnewmtl color_0000ff\nKd 0 0 1\nd 1\n\
             \nnewmtl color_008000\nKd 0 0.5 0\nd 1\n\
             \nnewmtl color_33669980\nKd 0.2 0.4 0.6\nd 0.5\n\
             \nnewmtl color_808080\nKd 0.5 0.5 0.5\nd 1\n",
            env!("CARGO_PKG_VERSION")
        )
    );
}

#[test]
fn obj_merged_has_one_group_per_material() {
    let model = sample_model();
    let (obj, _) = write_obj(&model, &MERGED, "model.mtl");
    let groups: Vec<&str> = obj.lines().filter(|l| l.starts_with("o ")).collect();
    assert_eq!(
        groups,
        [
            "o color_ff0000",
            "o color_0000ff",
            "o color_008000",
            "o color_33669980",
            "o color_808080"
        ]
    );
    let back = read_obj(&obj).unwrap();
    assert_eq!(back.parts.len(), 5);
    let red = &back.parts[0].mesh;
    let want = expected(&[&model.parts[0].mesh, &model.parts[2].mesh]);
    assert_eq!(red.face_count(), want.faces);
    assert_eq!(red.vertex_count(), want.vertices);
    assert!(red.is_watertight());
    assert_close(red.signed_volume(), want.volume, 1e-12, "red volume");
}

#[test]
fn obj_material_names_stay_unique_for_near_colours() {
    let a = Color::rgb(0.5, 0.5, 0.5);
    let b = Color::rgb(0.5001, 0.5, 0.5);
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![
            Part {
                name: "a".into(),
                color: a,
                mesh: cuboid(DVec3::ONE),
                ..Part::default()
            },
            Part {
                name: "b".into(),
                color: b,
                mesh: cuboid(DVec3::ONE),
                ..Part::default()
            },
        ],
        lines: Vec::new(),
    };
    let (obj, mtl) = write_obj(&model, &GROUPED, "m.mtl");
    assert!(obj.contains("usemtl color_808080\n") && obj.contains("usemtl color_808080_2\n"));
    assert!(mtl.contains("newmtl color_808080\nKd 0.5 0.5 0.5\n"));
    assert!(mtl.contains("newmtl color_808080_2\nKd 0.5001 0.5 0.5\n"));
}

#[test]
fn stl_box_has_twelve_triangles() {
    let model = Model::single("box", RED, cuboid(DVec3::new(1.0, 2.0, 3.0)));
    let bytes = write_stl(&model);
    assert_eq!(bytes.len(), 84 + 50 * 12);
    assert_eq!(&bytes[..9], b"shapegram");
    assert!(bytes[9..80].iter().all(|&b| b == 0));
    assert_eq!(u32::from_le_bytes(bytes[80..84].try_into().unwrap()), 12);
    let f32_at = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    // First facet: the -x face; normal, then three corners on x = 0; attribute 0.
    assert_eq!([f32_at(84), f32_at(88), f32_at(92)], [-1.0, 0.0, 0.0]);
    for corner in 0..3 {
        assert_eq!(f32_at(96 + 12 * corner), 0.0);
    }
    assert_eq!(&bytes[132..134], &[0, 0]);
    let back = read_stl(&bytes).unwrap();
    assert_eq!(back.parts.len(), 1);
    assert_eq!(back.parts[0].name, "stl");
    assert_eq!(back.parts[0].mesh.face_count(), 12);
    assert!(back.parts[0].mesh.welded(1e-6).is_watertight());
    assert_close(back.parts[0].mesh.signed_volume(), 6.0, 1e-12, "box volume");
}

#[test]
fn stl_round_trip_of_all_parts() {
    let model = closed_model();
    let bytes = write_stl(&model);
    let meshes: Vec<&Mesh> = model.parts.iter().map(|p| &p.mesh).collect();
    let want = expected(&meshes);
    assert_eq!(bytes.len(), 84 + 50 * want.triangles);
    let back = read_stl(&bytes).unwrap();
    let mesh = &back.parts[0].mesh;
    assert_eq!(mesh.face_count(), want.triangles);
    assert_eq!(mesh.bounds(), Some(want.bounds_f32));
    let welded = mesh.welded(1e-6);
    assert_eq!(welded.vertex_count(), want.vertices);
    assert!(welded.is_watertight(), "{:?}", welded.edge_report());
    assert_close(welded.signed_volume(), want.volume, 1e-4, "volume");
}

#[test]
fn stl_reads_ascii_and_binary_with_a_solid_header() {
    let ascii = "solid tetra\n\
        facet normal 0 0 -1\n outer loop\n vertex 0 0 0\n vertex 0 1 0\n vertex 1 0 0\n endloop\nendfacet\n\
        facet normal 0 -1 0\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n vertex 0 0 1\n endloop\nendfacet\n\
        facet normal -1 0 0\n outer loop\n vertex 0 0 0\n vertex 0 0 1\n vertex 0 1 0\n endloop\nendfacet\n\
        facet normal 1 1 1\n outer loop\n vertex 1 0 0\n vertex 0 1 0\n vertex 0 0 1\n endloop\nendfacet\n\
        endsolid tetra\n";
    let back = read_stl(ascii.as_bytes()).unwrap();
    let mesh = &back.parts[0].mesh;
    assert_eq!(mesh.face_count(), 4);
    assert_eq!(mesh.vertex_count(), 4, "stl_io shares identical vertices");
    assert!(mesh.is_watertight());
    assert_close(mesh.signed_volume(), 1.0 / 6.0, 1e-12, "tetrahedron");

    // Binary files from other tools often start their header with "solid".
    let mut binary = write_stl(&Model::single("box", RED, cuboid(DVec3::ONE)));
    binary[..9].copy_from_slice(b"solid box");
    let back = read_stl(&binary).unwrap();
    assert_eq!(back.parts[0].mesh.face_count(), 12);
}

#[test]
fn concave_faces_survive_every_format() {
    // An L-shaped prism: its caps are non-convex hexagons.
    let outline = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ]
    .map(|(x, z)| DVec3::new(x, 0.0, z));
    let mesh = extrude_polygon(&outline, 1.5).unwrap();
    let model = Model::single("annex", BLUE, mesh.clone());
    let want = expected(&[&mesh]);
    assert_eq!(want.triangles, 2 * 4 + 6 * 2);
    assert_close(want.volume, 4.5, 1e-12, "fixture volume");

    let glb = read_glb(&write_glb(&model, &GROUPED)).unwrap();
    check_flat(&glb.parts[0], &[&mesh], true);

    let (obj, _) = write_obj(&model, &GROUPED, "m.mtl");
    assert_eq!(
        obj.lines().filter(|l| l.split(' ').count() == 7).count(),
        2,
        "two 6-gon faces"
    );
    let back = read_obj(&obj).unwrap();
    assert_eq!(back.parts[0].mesh.face_count(), 8);
    assert!(back.parts[0].mesh.is_watertight());
    assert_close(back.parts[0].mesh.signed_volume(), 4.5, 1e-12, "OBJ volume");

    let stl = read_stl(&write_stl(&model)).unwrap();
    assert_eq!(stl.parts[0].mesh.face_count(), 20);
    assert!(stl.parts[0].mesh.welded(1e-6).is_watertight());
    assert_close(stl.parts[0].mesh.signed_volume(), 4.5, 1e-6, "STL volume");
}

#[test]
fn writers_are_deterministic() {
    let model = sample_model();
    for options in [GROUPED, MERGED] {
        assert_eq!(
            write_glb(&model, &options),
            write_glb(&model.clone(), &options)
        );
        assert_eq!(
            write_obj(&model, &options, "a.mtl"),
            write_obj(&model.clone(), &options, "a.mtl")
        );
    }
    assert_eq!(write_stl(&model), write_stl(&model.clone()));
}
