//! Where a part's triangles are in the GLB: which parts each primitive concatenates and how
//! many triangles each face gives (what the studio maps picked triangles back to shapes with).

use crate::common;

use common::*;
use shapegram_export::{ExportOptions, face_triangles, read_glb, write_glb, write_glb_with_layout};
use shapegram_geom::primitives::cuboid;
use shapegram_geom::{Color, DVec3, Lines, Mesh, Model, Part};

fn flat(name: &str, color: Color, mesh: Mesh) -> Part {
    Part {
        texture: None,
        uvs: Vec::new(),
        bone: None,
        metadata: None,
        name: name.to_owned(),
        color,
        normals: Vec::new(),
        mesh,
        material: None,
        surface: None,
        instance: None,
    }
}

/// Two red parts and a green one between them, a face without area in the green one, and a
/// red line set.
fn model() -> Model {
    let mut green = cuboid(DVec3::ONE);
    let collinear = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0].map(|p| green.add_vertex(p));
    green.add_face(&collinear);
    Model {
        skeletons: Vec::new(),
        parts: vec![
            flat("a", RED, cuboid(DVec3::splat(2.0))),
            flat("b", GREEN, green),
            flat(
                "c",
                RED,
                Mesh::from_polygon(&[DVec3::ZERO, DVec3::X, DVec3::Y]),
            ),
        ],
        lines: vec![Lines {
            name: "stroke".to_owned(),
            color: RED,
            points: vec![DVec3::ZERO, DVec3::X],
            segments: vec![[0, 1]],
        }],
    }
}

#[test]
fn the_layout_names_the_parts_of_each_primitive() {
    let model = model();
    let merged = ExportOptions::default();
    let mut glb = Vec::new();
    let layout = write_glb_with_layout(&model, &merged, &mut glb).unwrap();
    // The same triangles as without the layout, but in face order: the first red ones are
    // the first face of part 0, as the model has it.
    let traced = read_glb(&glb).unwrap();
    let compacted = read_glb(&write_glb(&model, &merged)).unwrap();
    let triangles = |m: &Model| {
        m.parts
            .iter()
            .map(|p| p.mesh.face_count())
            .collect::<Vec<_>>()
    };
    assert_eq!(triangles(&traced), [13, 12]);
    assert_eq!(triangles(&traced), triangles(&compacted));
    let first = traced.parts[0].mesh.face_points(0).collect::<Vec<_>>();
    let face = model.parts[0].mesh.face_points(0).collect::<Vec<_>>();
    assert!(
        first.iter().all(|p| face.contains(p)),
        "{first:?} is not in {face:?}"
    );
    // One mesh: red triangles (parts 0 and 2), green (part 1), red lines.
    assert_eq!(
        layout,
        [vec![vec![Some(0), Some(2)], vec![Some(1)], vec![None]]]
    );
    let grouped = ExportOptions {
        group_by_part: true,
        ..ExportOptions::default()
    };
    let layout = write_glb_with_layout(&model, &grouped, &mut Vec::new()).unwrap();
    assert_eq!(
        layout,
        [
            vec![vec![Some(0)]],
            vec![vec![Some(1)]],
            vec![vec![Some(2)]],
            vec![vec![None]]
        ]
    );
}

#[test]
fn faces_give_their_triangles_and_the_primitive_holds_them_in_order() {
    let model = model();
    assert_eq!(face_triangles(&model.parts[0]), [2; 6]);
    // The collinear face is not written.
    assert_eq!(face_triangles(&model.parts[1]), [2, 2, 2, 2, 2, 2, 0]);
    assert_eq!(face_triangles(&model.parts[2]), [1]);
    let (json, _) = split_glb(&write_glb(&model, &ExportOptions::default()));
    let count = |primitive: usize| {
        let accessor = json["meshes"][0]["primitives"][primitive]["indices"]
            .as_u64()
            .unwrap() as usize;
        json["accessors"][accessor]["count"].as_u64().unwrap() / 3
    };
    assert_eq!((count(0), count(1)), (13, 12));
}
