//! Wavefront OBJ + MTL writer.
//!
//! Faces stay polygons. A flat part writes one `vn` per face (`f a//n b//n c//n`); a smooth
//! part one `vn` per vertex, in the order of its `v` lines (`f a//a' b//b' c//c'`). A line set
//! writes its points and one `l a b` per segment, in an object of its own. Numbers are written
//! with Rust's `{}` formatting: the shortest decimal that reads back as the same f64 (f32 for
//! colours), never in exponent notation, so files are exact, deterministic and readable by every
//! parser.
//!
//! OBJ has no skins, so parts that hang from a skeleton are written in the current pose
//! ([`Model::posed`]).
//!
//! A textured part (see [`shapegram_geom::Part::texture`]) writes one `vt` per vertex, in the
//! order of its `v` lines, with v up as CGA has it (`f a/t/n`), and its material names the
//! image with `map_Kd`; [`save`](crate::save) writes the images beside the MTL.

use std::borrow::Cow;
use std::fmt::Write as _;
use std::io::{self, Write};

use std::sync::Arc;

use shapegram_geom::{Color, DVec2, DVec3, MapTransform, Mesh, Model, Surface, Texture};

use crate::ExportOptions;
use crate::flat::{
    Palette, face_is_exportable, is_smooth, posed, sanitized_name, segment_is_exportable,
    texture_files, texture_uvs, usable_normals,
};

/// What one part or line set puts into an object.
enum Piece<'a> {
    /// Faces of a part, with one normal per vertex when `normals` is given, and one uv per
    /// vertex when the part is textured.
    Faces {
        mesh: &'a Mesh,
        faces: Vec<usize>,
        normals: Option<Cow<'a, [DVec3]>>,
        uvs: Option<&'a [DVec2]>,
    },
    /// Segments of a line set.
    Segments {
        points: &'a [DVec3],
        segments: Vec<[u32; 2]>,
    },
}

/// One `o` block: name, material index, whether it holds lines, and its pieces.
struct Object<'a> {
    name: String,
    material: usize,
    lines: bool,
    pieces: Vec<Piece<'a>>,
}

/// `-0` would print as "-0"; normalising keeps files tidy and identical for equal geometry.
fn num(x: f64) -> f64 {
    x + 0.0
}

/// OBJ text that references `mtl_file_name` via `mtllib`, and the MTL text.
///
/// # Panics
/// If a part's bone names a section the model does not have (see [`write_obj_to`]).
pub fn write_obj(model: &Model, options: &ExportOptions, mtl_file_name: &str) -> (String, String) {
    let mut obj = Vec::new();
    let mtl =
        write_obj_to(model, options, mtl_file_name, &mut obj).unwrap_or_else(|e| panic!("{e}"));
    let obj = String::from_utf8(obj).expect("OBJ text is built from strings");
    (obj, mtl)
}

/// Writes the OBJ text to `out` (wrap files in a `BufWriter`) and returns the MTL text; see
/// [`write_obj`]. A part whose bone names a section the model does not have is an
/// `InvalidInput` error, found before anything is written.
pub fn write_obj_to(
    model: &Model,
    options: &ExportOptions,
    mtl_file_name: &str,
    out: &mut impl Write,
) -> io::Result<String> {
    let model = posed(model)?;
    let files = texture_files(&model);
    let mut palette = Palette::default();
    let mut objects: Vec<Object<'_>> = Vec::new();
    let parts = model.parts.iter().map(|part| {
        let faces: Vec<usize> = (0..part.mesh.face_count())
            .filter(|&i| face_is_exportable(&part.mesh, i))
            .collect();
        let normals = is_smooth(part).then(|| usable_normals(part));
        let uvs = texture_uvs(part);
        let texture = uvs
            .and(part.texture.as_ref())
            .and_then(|t| files.iter().position(|(path, _, _)| *path == t.path));
        let piece = Piece::Faces {
            mesh: &part.mesh,
            faces,
            normals,
            uvs: uvs.filter(|_| texture.is_some()),
        };
        let look = Look {
            color: part.color,
            texture,
            name: part.material.as_ref(),
            surface: part.surface.as_ref(),
            textured: uvs.is_some(),
        };
        (&part.name, look, false, piece)
    });
    let lines = model.lines.iter().map(|lines| {
        let segments: Vec<[u32; 2]> = lines
            .segments
            .iter()
            .copied()
            .filter(|&s| segment_is_exportable(&lines.points, s))
            .collect();
        let piece = Piece::Segments {
            points: &lines.points,
            segments,
        };
        (&lines.name, Look::of_color(lines.color), true, piece)
    });
    for (name, look, lines, piece) in parts.chain(lines) {
        let empty = match &piece {
            Piece::Faces { faces, .. } => faces.is_empty(),
            Piece::Segments { segments, .. } => segments.is_empty(),
        };
        if empty {
            continue;
        }
        let material = palette.material(
            look.color,
            look.texture,
            look.name,
            look.surface,
            look.textured,
        );
        let existing = if options.group_by_part {
            None
        } else {
            objects
                .iter_mut()
                .find(|o| o.material == material && o.lines == lines)
        };
        match existing {
            Some(object) => object.pieces.push(piece),
            None => objects.push(Object {
                name: sanitized_name(name),
                material,
                lines,
                pieces: vec![piece],
            }),
        }
    }
    let material_names = palette.unique_names();
    if !options.group_by_part {
        for object in &mut objects {
            object.name.clone_from(&material_names[object.material]);
            if object.lines {
                object.name.push_str("_lines");
            }
        }
    }

    writeln!(out, "# shapegram {}", env!("CARGO_PKG_VERSION"))?;
    writeln!(out, "mtllib {mtl_file_name}")?;
    let mut numbering = Numbering::default();
    for object in &objects {
        writeln!(out, "o {}", object.name)?;
        writeln!(out, "usemtl {}", material_names[object.material])?;
        for piece in &object.pieces {
            match piece {
                Piece::Faces {
                    mesh,
                    faces,
                    normals,
                    uvs,
                } => numbering.write_faces(out, mesh, faces, normals.as_deref(), *uvs)?,
                Piece::Segments { points, segments } => {
                    numbering.write_segments(out, points, segments)?
                }
            }
        }
    }

    let mut mtl = format!("# shapegram {}\n", env!("CARGO_PKG_VERSION"));
    let materials = material_names.iter().zip(palette.colors());
    let looks = palette.textures().iter().zip(palette.surfaces());
    for ((name, [r, g, b, a]), (texture, surface)) in materials.zip(looks) {
        mtl.push_str(&format!("\nnewmtl {name}\n"));
        if let Some([r, g, b]) = surface.as_ref().and_then(|s| s.finish.ambient) {
            mtl.push_str(&format!("Ka {r} {g} {b}\n"));
        }
        mtl.push_str(&format!("Kd {r} {g} {b}\nd {a}\n"));
        if let Some(texture) = texture {
            let transform = surface.as_ref().map(|s| s.transforms[0]);
            let options = map_options(transform.unwrap_or_default());
            mtl.push_str(&format!("map_Kd {options}{}\n", files[*texture].1));
        }
        if let Some(surface) = surface {
            let file = |t: &Texture| {
                let at = files.iter().position(|(path, _, _)| *path == t.path);
                at.map(|i| files[i].1.as_str())
            };
            surface_lines(&mut mtl, surface, file);
        }
    }
    Ok(mtl)
}

/// How a part or line set looks: what its material is made of.
struct Look<'a> {
    color: Color,
    texture: Option<usize>,
    name: Option<&'a Arc<str>>,
    surface: Option<&'a Arc<Surface>>,
    textured: bool,
}

impl Look<'_> {
    /// A plain colour.
    fn of_color(color: Color) -> Self {
        Self {
            color,
            texture: None,
            name: None,
            surface: None,
            textured: false,
        }
    }
}

/// The MTL statements of a surface's attributes and layers (after `Kd`, `d` and `map_Kd`):
/// `Ks`, `Ns`, `Ke`, the PBR extension's `Pr` and `Pm`, and the maps `map_Ks`, `map_Bump`
/// (with `-bm` for the bump value), `norm`, `map_d`, `map_Ke`, `map_Pr` and `map_Pm`; `file`
/// names each image's file. MTL has no place for reflectivity, the dirt map or the occlusion
/// map.
fn surface_lines<'a>(
    mtl: &mut String,
    surface: &'a Surface,
    file: impl Fn(&'a Texture) -> Option<&'a str>,
) {
    let finish = &surface.finish;
    let mut line = |statement: &str, value: String| {
        let _ = writeln!(mtl, "{statement} {value}");
    };
    if let Some([r, g, b]) = finish.specular {
        line("Ks", format!("{r} {g} {b}"));
    }
    if let Some(shininess) = finish.shininess {
        line("Ns", shininess.to_string());
    }
    if let Some([r, g, b]) = finish.emissive {
        line("Ke", format!("{r} {g} {b}"));
    }
    if let Some(roughness) = finish.roughness {
        line("Pr", roughness.to_string());
    }
    if let Some(metallic) = finish.metallic {
        line("Pm", metallic.to_string());
    }
    let maps = &surface.maps;
    // Each statement with its layer's uv set, for the layer's transform.
    let layers = [
        ("map_Ks", &maps.specular, 3),
        ("map_Bump", &maps.bump, 1),
        ("norm", &maps.normal, 5),
        ("map_d", &maps.opacity, 4),
        ("map_Ke", &maps.emissive, 6),
        ("map_Pr", &maps.roughness, 8),
        ("map_Pm", &maps.metallic, 9),
    ];
    for (statement, map, set) in layers {
        let Some(name) = map.as_deref().and_then(&file) else {
            continue;
        };
        let options = map_options(surface.transforms[set]);
        match finish.bump_value.filter(|_| statement == "map_Bump") {
            Some(bump) => line(statement, format!("-bm {bump} {options}{name}")),
            None => line(statement, format!("{options}{name}")),
        }
    }
}

/// The options of a texture statement that place its image as `transform` does, each
/// followed by a space: `-s su sv 1` and `-o tu tv 0` (MTL reads a uv as scaled, then
/// moved). MTL cannot turn a map, so a map turned by `rw` gets none: it is written as it lies
/// on the uvs (GLB carries the whole transform).
fn map_options(transform: MapTransform) -> String {
    let MapTransform { su, sv, tu, tv, rw } = transform;
    let mut options = String::new();
    if rw != 0.0 {
        return options;
    }
    if (su, sv) != (1.0, 1.0) {
        let _ = write!(options, "-s {su} {sv} 1 ");
    }
    if (tu, tv) != (0.0, 0.0) {
        let _ = write!(options, "-o {tu} {tv} 0 ");
    }
    options
}

/// The file's running vertex and normal numbers (OBJ indices are global and 1-based) and the
/// renumbering of the piece at hand.
struct Numbering {
    next_vertex: usize,
    next_normal: usize,
    next_uv: usize,
    remap: Vec<usize>,
}

impl Default for Numbering {
    fn default() -> Self {
        Self {
            next_vertex: 1,
            next_normal: 1,
            next_uv: 1,
            remap: Vec::new(),
        }
    }
}

impl Numbering {
    /// Writes the used vertices of `positions` (those `corners` lists) in their order and
    /// numbers them; returns the number of the first.
    fn write_vertices(
        &mut self,
        out: &mut impl Write,
        positions: &[DVec3],
        corners: impl Iterator<Item = u32>,
    ) -> io::Result<usize> {
        self.remap.clear();
        self.remap.resize(positions.len(), usize::MAX);
        for v in corners {
            self.remap[v as usize] = 0;
        }
        let first = self.next_vertex;
        for (slot, p) in self.remap.iter_mut().zip(positions) {
            if *slot == 0 {
                *slot = self.next_vertex;
                self.next_vertex += 1;
                writeln!(out, "v {} {} {}", num(p.x), num(p.y), num(p.z))?;
            }
        }
        Ok(first)
    }

    fn write_faces(
        &mut self,
        out: &mut impl Write,
        mesh: &Mesh,
        faces: &[usize],
        normals: Option<&[DVec3]>,
        uvs: Option<&[DVec2]>,
    ) -> io::Result<()> {
        let corners = faces.iter().flat_map(|&f| mesh.face(f).iter().copied());
        let first = self.write_vertices(out, mesh.positions(), corners)?;
        // A uv per written vertex, in the order of the `v` lines (v up, as OBJ has it).
        if let Some(uvs) = uvs {
            for (slot, uv) in self.remap.iter().zip(uvs) {
                if *slot != usize::MAX {
                    writeln!(out, "vt {} {}", num(uv.x), num(uv.y))?;
                }
            }
        }
        let mut unit = |n: DVec3| -> io::Result<()> {
            let n = n / n.length();
            writeln!(out, "vn {} {} {}", num(n.x), num(n.y), num(n.z))
        };
        match normals {
            Some(normals) => {
                for (slot, &n) in self.remap.iter().zip(normals) {
                    if *slot != usize::MAX {
                        unit(n)?;
                    }
                }
            }
            None => {
                for &f in faces {
                    unit(mesh.face_normal(f))?;
                }
            }
        }
        let mut line = String::new();
        for (k, &f) in faces.iter().enumerate() {
            line.clear();
            line.push('f');
            for &v in mesh.face(f) {
                let vertex = self.remap[v as usize];
                let normal = match normals {
                    Some(_) => self.next_normal + (vertex - first),
                    None => self.next_normal + k,
                };
                let written = match uvs {
                    Some(_) => {
                        let uv = self.next_uv + (vertex - first);
                        write!(line, " {vertex}/{uv}/{normal}")
                    }
                    None => write!(line, " {vertex}//{normal}"),
                };
                written.expect("writing to a String cannot fail");
            }
            writeln!(out, "{line}")?;
        }
        self.next_normal += match normals {
            Some(_) => self.next_vertex - first,
            None => faces.len(),
        };
        if uvs.is_some() {
            self.next_uv += self.next_vertex - first;
        }
        Ok(())
    }

    fn write_segments(
        &mut self,
        out: &mut impl Write,
        points: &[DVec3],
        segments: &[[u32; 2]],
    ) -> io::Result<()> {
        self.write_vertices(out, points, segments.iter().flatten().copied())?;
        for &[a, b] in segments {
            writeln!(
                out,
                "l {} {}",
                self.remap[a as usize], self.remap[b as usize]
            )?;
        }
        Ok(())
    }
}
