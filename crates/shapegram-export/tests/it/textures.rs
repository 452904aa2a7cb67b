//! Textured parts in GLB: TEXCOORD_0 with v turned down as glTF has it, the images embedded
//! once each, materials with a base colour texture, blended when the image has alpha.

use crate::common;

use std::sync::Arc;

use common::split_glb;
use shapegram_export::{ExportOptions, write_glb};
use shapegram_geom::{Color, DVec2, DVec3, Mesh, Model, Part, Texture};

const BRICK: &[u8] = include_bytes!("../../../../examples/textures/brick.png");

/// The header of a PNG with an alpha channel (colour type 6): all the writer reads of it.
fn rgba_png() -> Vec<u8> {
    let mut bytes = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
    bytes.extend_from_slice(&[0, 0, 0, 2, 0, 0, 0, 2, 8, 6, 0, 0, 0, 0, 0, 0, 0]);
    bytes
}

/// A 2 × 1 quad at height `y`, its uvs running 0…2 along x and 0…1 along z.
fn quad_part(name: &str, y: f64, image: Option<&[u8]>, path: &str) -> Part {
    let positions = vec![
        DVec3::new(0.0, y, 0.0),
        DVec3::new(2.0, y, 0.0),
        DVec3::new(2.0, y, -1.0),
        DVec3::new(0.0, y, -1.0),
    ];
    let mesh = Mesh::from_faces(positions.clone(), [[0u32, 1, 2, 3]]);
    Part {
        name: name.to_owned(),
        color: Color::rgb(1.0, 1.0, 1.0),
        uvs: positions.iter().map(|p| DVec2::new(p.x, -p.z)).collect(),
        texture: Some(Arc::new(Texture {
            path: Arc::from(path),
            image: image.map(Arc::from),
        })),
        mesh,
        ..Part::default()
    }
}

fn model(parts: Vec<Part>) -> Model {
    Model {
        parts,
        ..Model::default()
    }
}

/// Each primitive's TEXCOORD_0 by vertex position, read with the `gltf` crate.
fn uvs_by_position(bytes: &[u8]) -> Vec<Vec<([f32; 3], [f32; 2])>> {
    let gltf = gltf::Gltf::from_slice(bytes).unwrap();
    let blob = gltf.blob.clone();
    let mut found = Vec::new();
    for mesh in gltf.meshes() {
        for primitive in mesh.primitives() {
            let reader = primitive.reader(|_| blob.as_deref());
            let Some(uvs) = reader.read_tex_coords(0) else {
                found.push(Vec::new());
                continue;
            };
            let positions = reader.read_positions().unwrap();
            found.push(positions.zip(uvs.into_f32()).collect());
        }
    }
    found
}

#[test]
fn a_textured_part_has_its_uvs_with_v_down_and_its_image_embedded() {
    let bytes = write_glb(
        &model(vec![quad_part(
            "Wall",
            0.0,
            Some(BRICK),
            "textures/brick.png",
        )]),
        &ExportOptions::default(),
    );
    let uvs = uvs_by_position(&bytes);
    assert_eq!(uvs.len(), 1);
    let mut corners = uvs[0].clone();
    corners.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    // CGA's v runs up the image, glTF's down: v = 1 − v.
    assert_eq!(
        corners,
        [
            ([0.0, 0.0, -1.0], [0.0, 0.0]),
            ([0.0, 0.0, 0.0], [0.0, 1.0]),
            ([2.0, 0.0, -1.0], [2.0, 0.0]),
            ([2.0, 0.0, 0.0], [2.0, 1.0]),
        ]
    );
    let (json, bin) = split_glb(&bytes);
    assert_eq!(json["images"][0]["mimeType"], "image/png");
    assert_eq!(json["images"][0]["name"], "brick.png");
    let view = &json["bufferViews"][json["images"][0]["bufferView"].as_u64().unwrap() as usize];
    let (offset, length) = (
        view["byteOffset"].as_u64().unwrap() as usize,
        view["byteLength"].as_u64().unwrap() as usize,
    );
    assert_eq!(&bin[offset..offset + length], BRICK);
    assert_eq!(json["textures"], serde_json::json!([{ "source": 0 }]));
    let material = &json["materials"][0];
    assert_eq!(
        material["pbrMetallicRoughness"]["baseColorTexture"],
        serde_json::json!({ "index": 0, "texCoord": 0 })
    );
    assert_eq!(material["alphaMode"], "OPAQUE");
}

#[test]
fn images_are_embedded_once_and_alpha_blends() {
    let bytes = write_glb(
        &model(vec![
            quad_part("Wall", 0.0, Some(BRICK), "textures/brick.png"),
            quad_part("Wall2", 1.0, Some(BRICK), "textures/brick.png"),
            quad_part("Leaves", 2.0, Some(&rgba_png()), "leaves.png"),
        ]),
        &ExportOptions::default(),
    );
    let (json, _) = split_glb(&bytes);
    assert_eq!(json["images"].as_array().unwrap().len(), 2);
    let materials = json["materials"].as_array().unwrap();
    // Same colour, same image: one material; another image: another material.
    assert_eq!(materials.len(), 2);
    assert_eq!(materials[1]["alphaMode"], "BLEND");
    assert_eq!(
        materials[1]["pbrMetallicRoughness"]["baseColorTexture"]["index"],
        1
    );
}

#[test]
fn a_texture_without_an_image_leaves_the_part_in_its_colour() {
    let bytes = write_glb(
        &model(vec![
            quad_part("Missing", 0.0, None, "missing.png"),
            quad_part("NotAnImage", 1.0, Some(b"GIF89a"), "old.gif"),
        ]),
        &ExportOptions::default(),
    );
    let (json, _) = split_glb(&bytes);
    assert!(json.get("images").is_none() && json.get("textures").is_none());
    assert!(uvs_by_position(&bytes).iter().all(Vec::is_empty));
    assert!(
        json["materials"][0]["pbrMetallicRoughness"]
            .get("baseColorTexture")
            .is_none()
    );
}

#[test]
fn obj_writes_vt_per_vertex_and_map_kd_and_save_writes_the_images() {
    let model = model(vec![
        quad_part("Wall", 0.0, Some(BRICK), "textures/brick.png"),
        quad_part("Other", 1.0, Some(BRICK), "other/brick.png"),
        quad_part("Plain", 2.0, None, "missing.png"),
    ]);
    let (obj, mtl) = shapegram_export::write_obj(&model, &ExportOptions::default(), "m.mtl");
    // v up as CGA has it: the uvs as given, one per vertex in the order of the `v` lines.
    let vts: Vec<&str> = obj.lines().filter(|l| l.starts_with("vt ")).collect();
    assert_eq!(vts, ["vt 0 0", "vt 2 0", "vt 2 1", "vt 0 1"].repeat(2));
    let faces: Vec<&str> = obj.lines().filter(|l| l.starts_with("f ")).collect();
    assert_eq!(
        faces,
        [
            "f 1/1/1 2/2/1 3/3/1 4/4/1",
            "f 5/5/2 6/6/2 7/7/2 8/8/2",
            "f 9//3 10//3 11//3 12//3"
        ]
    );
    // Two images of one name: the second is renamed.
    let maps: Vec<&str> = mtl.lines().filter(|l| l.starts_with("map_Kd")).collect();
    assert_eq!(maps, ["map_Kd brick.png", "map_Kd brick_2.png"]);

    let dir = common::scratch_dir("obj_textures");
    shapegram_export::save(&model, &dir.join("house.obj"), &ExportOptions::default()).unwrap();
    assert_eq!(std::fs::read(dir.join("brick.png")).unwrap(), BRICK);
    assert_eq!(std::fs::read(dir.join("brick_2.png")).unwrap(), BRICK);
    assert!(!dir.join("missing.png").exists());
    let back = shapegram_export::load(&dir.join("house.obj")).unwrap();
    assert_eq!(
        back.parts
            .iter()
            .map(|p| p.mesh.face_count())
            .sum::<usize>(),
        3
    );
}

#[test]
fn buffers_carry_uvs_for_every_vertex_and_each_image_once() {
    let plain = Part {
        name: "Box".into(),
        mesh: shapegram_geom::primitives::cuboid(DVec3::ONE),
        ..Part::default()
    };
    let model = model(vec![
        plain.clone(),
        quad_part("Wall", 0.0, Some(BRICK), "textures/brick.png"),
        quad_part("Wall2", 1.0, Some(BRICK), "textures/brick.png"),
    ]);
    let buffers = shapegram_export::Buffers::of_model(&model);
    assert_eq!(buffers.uvs.len(), buffers.positions.len());
    let textures: Vec<Option<u32>> = buffers.parts.iter().map(|p| p.texture).collect();
    assert_eq!(textures, [None, Some(0), Some(0)]);
    assert_eq!(buffers.textures.len(), 1);
    assert_eq!(buffers.textures[0].image.as_deref(), Some(BRICK));
    // The box's 24 corners have no uvs to speak of; the quads' are glTF's (v down).
    assert!(buffers.uvs[..24].iter().all(|uv| *uv == [0.0, 0.0]));
    let wall = buffers.parts[1];
    let range = wall.first_vertex as usize..(wall.first_vertex + wall.vertex_count) as usize;
    let mut corners: Vec<([f32; 3], [f32; 2])> = range
        .map(|v| (buffers.positions[v], buffers.uvs[v]))
        .collect();
    corners.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    assert_eq!(
        corners,
        [
            ([0.0, 0.0, -1.0], [0.0, 0.0]),
            ([0.0, 0.0, 0.0], [0.0, 1.0]),
            ([2.0, 0.0, -1.0], [2.0, 0.0]),
            ([2.0, 0.0, 0.0], [2.0, 1.0]),
        ]
    );
    // Without a textured part there are no uvs at all.
    let buffers = shapegram_export::Buffers::of_model(&self::model(vec![plain]));
    assert!(buffers.uvs.is_empty() && buffers.textures.is_empty());
}
