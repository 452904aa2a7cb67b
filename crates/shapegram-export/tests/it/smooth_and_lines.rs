//! Smooth parts (one normal per shared vertex) and line sets in every format: what is written,
//! and what reads back.

use crate::common;

use common::*;
use serde_json::{Value, json};
use shapegram_export::{
    ExportOptions, FlatNormals, GlbEncoding, Instancing, read_glb, read_obj, read_stl, save,
    write_glb, write_obj, write_stl,
};
use shapegram_geom::primitives::{cuboid, sphere};
use shapegram_geom::{DAffine3, DVec3, Lines, Mesh, Model, Part};

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

fn smooth(name: &str, mesh: Mesh) -> Part {
    Part {
        texture: None,
        uvs: Vec::new(),
        bone: None,
        metadata: None,
        name: name.to_owned(),
        color: GREEN,
        normals: mesh.vertex_normals(),
        mesh,
        material: None,
        surface: None,
        instance: None,
    }
}

/// A ball of shared vertices, off the origin so coordinates are not all exact in f32.
fn ball() -> Part {
    let mesh = sphere(DVec3::splat(2.0), 16, 8)
        .transformed(&DAffine3::from_translation(DVec3::new(0.1, 0.2, 0.3)));
    smooth("ball", mesh)
}

/// A red stroke of three segments, plus what the writers must drop: a segment to a NaN point,
/// one of zero length, one to a missing point, and an unused point.
fn stroke() -> Lines {
    Lines {
        name: "stroke".to_owned(),
        color: RED,
        points: vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(f64::NAN, 0.0, 0.0),
            DVec3::splat(5.0),
            DVec3::new(1.0, 2.0, 0.5),
        ],
        segments: vec![[0, 1], [1, 2], [2, 3], [2, 2], [9, 1], [2, 5]],
    }
}

/// What [`stroke`] reads back as: used points in order, valid segments renumbered.
fn stroke_written() -> (Vec<DVec3>, Vec<[u32; 2]>) {
    (
        vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(1.0, 2.0, 0.5),
        ],
        vec![[0, 1], [1, 2], [2, 3]],
    )
}

/// The normal a part read back has at the vertex at `position` (readers may reorder vertices).
fn normal_at(part: &Part, position: DVec3) -> DVec3 {
    let at = part.mesh.positions().iter().position(|&p| p == position);
    part.normals[at.unwrap_or_else(|| panic!("no vertex at {position}"))]
}

fn accessor<'a>(json: &'a Value, primitive: &Value, key: &str) -> &'a Value {
    let index = match key {
        "indices" => &primitive["indices"],
        _ => &primitive["attributes"][key],
    };
    &json["accessors"][index.as_u64().unwrap() as usize]
}

/// The f32 triples of a VEC3 accessor.
fn vec3s(json: &Value, bin: &[u8], accessor: &Value) -> Vec<[f32; 3]> {
    let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap() as usize;
    (0..accessor["count"].as_u64().unwrap() as usize)
        .map(|k| {
            [0, 1, 2].map(|c| {
                let at = start + 12 * k + 4 * c;
                f32::from_le_bytes(bin[at..at + 4].try_into().unwrap())
            })
        })
        .collect()
}

#[test]
fn glb_smooth_cube_keeps_its_eight_corners() {
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![smooth("cube", cuboid(DVec3::ONE))],
        lines: Vec::new(),
    };
    let (json, bin) = split_glb(&write_glb(&model, &GROUPED));
    let primitive = &json["meshes"][0]["primitives"][0];
    assert_eq!(accessor(&json, primitive, "POSITION")["count"], 8);
    assert_eq!(accessor(&json, primitive, "indices")["count"], 36);
    let normals = vec3s(&json, &bin, accessor(&json, primitive, "NORMAL"));
    let positions = vec3s(&json, &bin, accessor(&json, primitive, "POSITION"));
    // Every corner's normal points away from the centre along the diagonal.
    let third = 1.0 / 3f32.sqrt();
    for (p, n) in positions.iter().zip(&normals) {
        let want = p.map(|c| if c > 0.5 { third } else { -third });
        assert_eq!(*n, want, "corner {p:?}");
    }
}

#[test]
fn glb_smooth_part_round_trips_with_its_normals() {
    let part = ball();
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![part.clone()],
        lines: Vec::new(),
    };
    let bytes = write_glb(&model, &GROUPED);
    let (json, _) = split_glb(&bytes);
    let primitive = &json["meshes"][0]["primitives"][0];
    let vertices = part.mesh.vertex_count();
    let triangles = part.mesh.triangulate().len();
    assert_eq!(accessor(&json, primitive, "POSITION")["count"], vertices);
    assert_eq!(accessor(&json, primitive, "NORMAL")["count"], vertices);
    assert_eq!(
        accessor(&json, primitive, "indices")["count"],
        3 * triangles
    );

    let back = read_glb(&bytes).unwrap();
    let read = &back.parts[0];
    assert_eq!(read.name, "ball");
    assert_eq!(read.mesh.vertex_count(), vertices);
    assert_eq!(read.mesh.face_count(), triangles);
    assert_eq!(read.normals.len(), vertices);
    // Vertices come back in vertex-cache order: each is one of the part's, with its normal.
    for (q, m) in read.mesh.positions().iter().zip(&read.normals) {
        let written = |p: &DVec3| p.as_vec3().as_dvec3() == *q;
        let v = part.mesh.positions().iter().position(written).unwrap();
        let n = part.normals[v];
        assert!(n.distance(*m) < 1e-6, "{n} read as {m}");
    }
    assert!(read.mesh.is_watertight());
    assert_close(
        read.mesh.signed_volume(),
        part.mesh.signed_volume(),
        1e-6,
        "volume",
    );
}

#[test]
fn flat_parts_read_back_without_normals() {
    let model = sample_model();
    for back in [
        read_glb(&write_glb(&model, &GROUPED)).unwrap(),
        read_obj(&write_obj(&model, &GROUPED, "m.mtl").0).unwrap(),
    ] {
        assert_eq!(back.parts.len(), model.parts.len());
        assert!(back.parts.iter().all(|p| p.normals.is_empty()));
    }
}

#[test]
fn unusable_normals_become_face_normals_and_unused_vertices_go() {
    let mut part = smooth("cube", cuboid(DVec3::ONE));
    part.normals[0] = DVec3::new(f64::NAN, 0.0, 0.0);
    part.normals[1] = DVec3::ZERO;
    // A vertex no face uses, where nothing finite could be written.
    part.mesh.add_vertex(DVec3::splat(f64::INFINITY));
    part.normals.push(DVec3::ZERO);
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![part],
        lines: Vec::new(),
    };
    let glb = read_glb(&write_glb(&model, &GROUPED)).unwrap();
    let obj = read_obj(&write_obj(&model, &GROUPED, "m.mtl").0).unwrap();
    for back in [glb, obj] {
        let read = &back.parts[0];
        assert_eq!(read.mesh.vertex_count(), 8);
        // Corner 0 is first on the -x face, corner 1 (x = 1) on the +x face.
        assert_eq!(normal_at(read, DVec3::ZERO), DVec3::NEG_X);
        assert_eq!(normal_at(read, DVec3::X), DVec3::X);
        let far = normal_at(read, DVec3::ONE);
        assert!((far - DVec3::ONE.normalize()).length() < 1e-6, "{far}");
    }
}

#[test]
fn smooth_vertices_left_out_renumber_the_rest() {
    // The cube behind an unused NaN vertex, so every index moves down by one when written.
    let cube = cuboid(DVec3::ONE);
    let mut positions = vec![DVec3::splat(f64::NAN)];
    positions.extend_from_slice(cube.positions());
    let faces: Vec<Vec<u32>> = cube
        .faces()
        .map(|f| f.iter().map(|v| v + 1).collect())
        .collect();
    let part = smooth("cube", Mesh::from_faces(positions, faces));
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![part],
        lines: Vec::new(),
    };
    for options in [GROUPED, MERGED] {
        let read = &read_glb(&write_glb(&model, &options)).unwrap().parts[0];
        let mut positions = read.mesh.positions().to_vec();
        positions.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
        let mut expected = cube.positions().to_vec();
        expected.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
        assert_eq!(positions, expected);
        assert_eq!(read.mesh.face_count(), 12);
        assert!(read.mesh.is_watertight());
        assert_close(read.mesh.signed_volume(), 1.0, 1e-12, "volume");
        for (p, n) in read.mesh.positions().iter().zip(&read.normals) {
            assert!((*n - (*p - 0.5).normalize()).length() < 1e-6, "{p}: {n}");
        }
    }
}

#[test]
fn glb_lines_are_a_primitive_of_their_own() {
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![Part {
            texture: None,
            uvs: Vec::new(),
            bone: None,
            metadata: None,
            name: "box".to_owned(),
            color: RED,
            mesh: cuboid(DVec3::ONE),
            normals: Vec::new(),
            material: None,
            surface: None,
            instance: None,
        }],
        lines: vec![stroke()],
    };
    let bytes = write_glb(&model, &MERGED);
    let (json, _) = split_glb(&bytes);
    // Same colour, same material, but two primitives: a primitive has one mode.
    assert_eq!(json["materials"].as_array().unwrap().len(), 1);
    let primitives = json["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 2);
    assert_eq!(primitives[0]["mode"], Value::Null);
    let lines = &primitives[1];
    assert_eq!(lines["mode"], 1, "LINES");
    assert_eq!(lines["material"], 0);
    assert_eq!(
        lines["attributes"]
            .as_object()
            .unwrap()
            .keys()
            .collect::<Vec<_>>(),
        ["POSITION"]
    );
    let position = accessor(&json, lines, "POSITION");
    assert_eq!(position["count"], 4);
    assert_eq!(position["min"], json!([0.0, 0.0, 0.0]));
    assert_eq!(position["max"], json!([1.0, 2.0, 0.5]));
    let indices = accessor(&json, lines, "indices");
    assert_eq!(indices["count"], 6);
    assert_eq!(indices["componentType"], 5123);
    assert!(gltf::Gltf::from_slice(&bytes).is_ok());

    let back = read_glb(&bytes).unwrap();
    assert_eq!(back.parts.len(), 1);
    assert_eq!(back.lines.len(), 1);
    let read = &back.lines[0];
    assert_eq!(read.name, "model");
    assert_eq!(read.color.to_hex(), RED.to_hex());
    let (points, segments) = stroke_written();
    assert_eq!(read.points, points);
    assert_eq!(read.segments, segments);

    let grouped = read_glb(&write_glb(&model, &GROUPED)).unwrap();
    assert_eq!(grouped.parts[0].name, "box");
    assert_eq!(grouped.lines[0].name, "stroke");
}

#[test]
fn glb_lines_past_65535_points_use_u32_indices() {
    let n = 70_000u32;
    let lines = Lines {
        name: "long".to_owned(),
        color: BLUE,
        points: (0..n).map(|i| DVec3::new(f64::from(i), 0.0, 0.0)).collect(),
        segments: (0..n - 1).map(|i| [i, i + 1]).collect(),
    };
    let model = Model {
        skeletons: Vec::new(),
        parts: Vec::new(),
        lines: vec![lines.clone()],
    };
    let bytes = write_glb(&model, &GROUPED);
    let (json, _) = split_glb(&bytes);
    let primitive = &json["meshes"][0]["primitives"][0];
    assert_eq!(accessor(&json, primitive, "indices")["componentType"], 5125);
    let back = read_glb(&bytes).unwrap();
    assert!(back.parts.is_empty());
    assert_eq!(back.lines[0].points, lines.points);
    assert_eq!(back.lines[0].segments, lines.segments);
}

#[test]
fn glb_reader_turns_line_strips_and_loops_into_segments() {
    let model = Model {
        skeletons: Vec::new(),
        parts: Vec::new(),
        lines: vec![stroke()],
    };
    let (mut json, bin) = split_glb(&write_glb(&model, &GROUPED));
    // The index list 0 1 1 2 2 3 read as a strip and as a loop.
    for (mode, count) in [(3, 5), (2, 6)] {
        json["meshes"][0]["primitives"][0]["mode"] = json!(mode);
        let back = read_glb(&frame_glb(&json, &bin)).unwrap();
        let segments = &back.lines[0].segments;
        assert_eq!(segments.len(), count, "mode {mode}");
        assert_eq!(segments[..3], [[0, 1], [1, 1], [1, 2]]);
    }
}

#[test]
fn obj_smooth_part_and_lines_round_trip_exactly() {
    let part = ball();
    let mut flat = part.clone();
    flat.name = "flat ball".to_owned();
    flat.normals.clear();
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![part.clone(), flat],
        lines: vec![stroke()],
    };
    let (obj, mtl) = write_obj(&model, &GROUPED, "m.mtl");
    let vertices = part.mesh.vertex_count();
    let lines: Vec<&str> = obj.lines().collect();
    let ball_end = lines.iter().position(|l| *l == "o flat_ball").unwrap();
    let count =
        |prefix: &str, within: &[&str]| within.iter().filter(|l| l.starts_with(prefix)).count();
    assert_eq!(count("vn ", &lines[..ball_end]), vertices);
    // In the first object, vertex k has normal k.
    assert!(
        lines[..ball_end]
            .iter()
            .filter(|l| l.starts_with("f "))
            .flat_map(|l| l.split_whitespace().skip(1))
            .all(|corner| {
                let (v, n) = corner.split_once("//").unwrap();
                v == n
            })
    );
    let stroke_at = lines.iter().position(|l| *l == "o stroke").unwrap();
    // Vertex numbers go on after the two balls' vertices.
    let v = |k: usize| 2 * vertices + k;
    let want = [
        "o stroke".to_owned(),
        "usemtl color_ff0000".to_owned(),
        "v 0 0 0".to_owned(),
        "v 1 0 0".to_owned(),
        "v 1 2 0".to_owned(),
        "v 1 2 0.5".to_owned(),
        format!("l {} {}", v(1), v(2)),
        format!("l {} {}", v(2), v(3)),
        format!("l {} {}", v(3), v(4)),
    ];
    assert_eq!(lines[stroke_at..], want);
    assert_eq!(mtl.matches("newmtl").count(), 2);

    let back = read_obj(&obj).unwrap();
    assert_eq!(back.parts.len(), 2);
    let read = &back.parts[0];
    assert_eq!(read.mesh.vertex_count(), vertices);
    for (&p, n) in part.mesh.positions().iter().zip(&part.normals) {
        let m = normal_at(read, p);
        assert!(n.distance(m) < 1e-15, "{n} read as {m}");
    }
    assert!(back.parts[1].normals.is_empty());
    let (points, segments) = stroke_written();
    assert_eq!(back.lines.len(), 1);
    assert_eq!(back.lines[0].name, "stroke");
    assert_eq!(back.lines[0].points, points);
    assert_eq!(back.lines[0].segments, segments);

    // Merged, lines still get an object of their own, named after their material.
    let (merged, _) = write_obj(&model, &MERGED, "m.mtl");
    let objects: Vec<&str> = merged.lines().filter(|l| l.starts_with("o ")).collect();
    assert_eq!(objects, ["o color_008000", "o color_ff0000_lines"]);
}

#[test]
fn obj_reader_splits_polylines_into_segments() {
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\no path\nl 1 2 3 4\nl 4 1\n";
    let back = read_obj(text).unwrap();
    assert!(back.parts.is_empty());
    assert_eq!(back.lines.len(), 1);
    assert_eq!(back.lines[0].name, "path");
    assert_eq!(back.lines[0].points.len(), 4);
    assert_eq!(back.lines[0].segments, [[0, 1], [1, 2], [2, 3], [3, 0]]);
}

#[test]
fn stl_leaves_lines_out() {
    let only_lines = Model {
        skeletons: Vec::new(),
        parts: Vec::new(),
        lines: vec![stroke()],
    };
    assert_eq!(write_stl(&only_lines).len(), 84);
    let with_box = Model {
        skeletons: Vec::new(),
        parts: vec![smooth("cube", cuboid(DVec3::ONE))],
        lines: vec![stroke()],
    };
    let bytes = write_stl(&with_box);
    assert_eq!(bytes.len(), 84 + 12 * 50);
    assert_eq!(read_stl(&bytes).unwrap().parts[0].mesh.face_count(), 12);
}

#[test]
fn save_streams_the_same_bytes_as_the_writers() {
    let mut model = sample_model();
    model.parts.push(ball());
    model.lines.push(stroke());
    let dir = scratch_dir("stream");
    for options in [GROUPED, MERGED] {
        let glb = dir.join("model.glb");
        save(&model, &glb, &options).unwrap();
        assert_eq!(std::fs::read(&glb).unwrap(), write_glb(&model, &options));
        let obj = dir.join("model.obj");
        save(&model, &obj, &options).unwrap();
        let (text, mtl) = write_obj(&model, &options, "model.mtl");
        assert_eq!(std::fs::read_to_string(&obj).unwrap(), text);
        assert_eq!(std::fs::read_to_string(dir.join("model.mtl")).unwrap(), mtl);
    }
    let stl = dir.join("model.stl");
    save(&model, &stl, &GROUPED).unwrap();
    assert_eq!(std::fs::read(&stl).unwrap(), write_stl(&model));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn smooth_parts_and_lines_are_written_deterministically() {
    let mut model = sample_model();
    model.parts.push(ball());
    model.lines.push(stroke());
    for options in [GROUPED, MERGED] {
        assert_eq!(write_glb(&model, &options), write_glb(&model, &options));
        assert_eq!(
            write_obj(&model, &options, "m.mtl"),
            write_obj(&model, &options, "m.mtl")
        );
    }
}

#[test]
fn a_smooth_part_past_65535_vertices_splits_into_windows_that_read_back_the_same_triangles() {
    // 400 × 200 rings: 79,602 shared vertices, more than u16 indices can name.
    let part = smooth("globe", sphere(DVec3::splat(2.0), 400, 200));
    let vertices = part.mesh.vertex_count();
    assert_eq!(vertices, 79_602);
    let model = Model {
        skeletons: Vec::new(),
        parts: vec![part.clone()],
        lines: Vec::new(),
    };
    let bytes = write_glb(&model, &MERGED);
    let (json, _) = split_glb(&bytes);
    let primitives = json["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 2);
    let mut written = 0;
    for primitive in primitives {
        assert_eq!(accessor(&json, primitive, "indices")["componentType"], 5123);
        let count = accessor(&json, primitive, "POSITION")["count"]
            .as_u64()
            .unwrap();
        assert_eq!(accessor(&json, primitive, "NORMAL")["count"], count);
        written += count as usize;
    }
    // The windows overlap by the 401 vertices that the quads on either side of the cut share
    // (a ring and one more, as the cut falls inside a ring).
    assert_eq!(written, vertices + 401);

    // Every face's triangles as the writer splits them (quads and triangles, all convex), in
    // face order, in f32.
    let f32_point = |p: DVec3| p.as_vec3().to_array();
    let expected: Vec<[[f32; 3]; 3]> = (0..part.mesh.face_count())
        .flat_map(|i| {
            let face = part.mesh.face(i);
            let corner = |k: usize| f32_point(part.mesh.position(face[k]));
            let fan: &[[usize; 3]] = if face.len() == 3 {
                &[[0, 1, 2]]
            } else {
                &[[0, 1, 2], [0, 2, 3]]
            };
            fan.iter().map(move |t| t.map(corner)).collect::<Vec<_>>()
        })
        .collect();
    let back = read_glb(&bytes).unwrap();
    let read: Vec<[[f32; 3]; 3]> = back
        .parts
        .iter()
        .flat_map(|p| {
            (0..p.mesh.face_count())
                .map(|i| {
                    let face = p.mesh.face(i);
                    [0, 1, 2].map(|k| f32_point(p.mesh.position(face[k])))
                })
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(read.len(), expected.len());
    assert!(read == expected, "the triangles read back differ");
}
