//! Wavefront OBJ + MTL writer.
//!
//! Faces stay polygons (`f a//n b//n c//n d//n`), one `vn` per face. Numbers are written with
//! Rust's `{}` formatting: the shortest decimal that reads back as the same f64 (f32 for colours),
//! never in exponent notation, so files are exact, deterministic and readable by every parser.

use std::fmt::Write;

use shapegram_geom::{Mesh, Model};

use crate::ExportOptions;
use crate::flat::{Palette, face_is_exportable, sanitized_name};

/// Faces of one part that go into the file.
struct Piece<'a> {
    mesh: &'a Mesh,
    faces: Vec<usize>,
}

/// One `o` block: name, material index and the parts it holds.
struct Object<'a> {
    name: String,
    material: usize,
    pieces: Vec<Piece<'a>>,
}

/// `-0` would print as "-0"; normalising keeps files tidy and identical for equal geometry.
fn num(x: f64) -> f64 {
    x + 0.0
}

/// OBJ text that references `mtl_file_name` via `mtllib`, and the MTL text.
pub fn write_obj(model: &Model, options: &ExportOptions, mtl_file_name: &str) -> (String, String) {
    let mut palette = Palette::default();
    let mut objects: Vec<Object<'_>> = Vec::new();
    for part in &model.parts {
        let faces: Vec<usize> = (0..part.mesh.face_count())
            .filter(|&i| face_is_exportable(&part.mesh, i))
            .collect();
        if faces.is_empty() {
            continue;
        }
        let material = palette.material(part.color);
        let piece = Piece {
            mesh: &part.mesh,
            faces,
        };
        let existing = if options.group_by_part {
            None
        } else {
            objects.iter_mut().find(|o| o.material == material)
        };
        match existing {
            Some(object) => object.pieces.push(piece),
            None => objects.push(Object {
                name: sanitized_name(&part.name),
                material,
                pieces: vec![piece],
            }),
        }
    }
    let material_names = palette.unique_names();
    if !options.group_by_part {
        for object in &mut objects {
            object.name.clone_from(&material_names[object.material]);
        }
    }

    let mut obj = String::new();
    let mut line = |text: std::fmt::Arguments<'_>| {
        obj.write_fmt(text)
            .expect("writing to a String cannot fail");
        obj.push('\n');
    };
    line(format_args!("# shapegram {}", env!("CARGO_PKG_VERSION")));
    line(format_args!("mtllib {mtl_file_name}"));
    // OBJ indices are global and 1-based.
    let (mut vertex_base, mut normal_base) = (1usize, 1usize);
    let mut remap = Vec::new();
    for object in &objects {
        line(format_args!("o {}", object.name));
        line(format_args!("usemtl {}", material_names[object.material]));
        for piece in &object.pieces {
            let mesh = piece.mesh;
            // Only vertices that kept faces use, in mesh order.
            remap.clear();
            remap.resize(mesh.vertex_count(), usize::MAX);
            for &f in &piece.faces {
                for &v in mesh.face(f) {
                    remap[v as usize] = 0;
                }
            }
            let mut next = vertex_base;
            for (v, slot) in remap.iter_mut().enumerate() {
                if *slot == 0 {
                    *slot = next;
                    next += 1;
                    let p = mesh.position(v as u32);
                    line(format_args!("v {} {} {}", num(p.x), num(p.y), num(p.z)));
                }
            }
            vertex_base = next;
            for &f in &piece.faces {
                let n = mesh.face_normal(f);
                line(format_args!("vn {} {} {}", num(n.x), num(n.y), num(n.z)));
            }
            for (k, &f) in piece.faces.iter().enumerate() {
                let normal = normal_base + k;
                let mut face = String::from("f");
                for &v in mesh.face(f) {
                    write!(face, " {}//{normal}", remap[v as usize])
                        .expect("writing to a String cannot fail");
                }
                line(format_args!("{face}"));
            }
            normal_base += piece.faces.len();
        }
    }

    let mut mtl = format!("# shapegram {}\n", env!("CARGO_PKG_VERSION"));
    for (name, [r, g, b, a]) in material_names.iter().zip(palette.colors()) {
        mtl.push_str(&format!("\nnewmtl {name}\nKd {r} {g} {b}\nd {a}\n"));
    }
    (obj, mtl)
}
