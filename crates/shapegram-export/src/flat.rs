//! What the writers share: which faces make it into a file, their f32 triangles, and the
//! materials (one per distinct colour, in order of first appearance).

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet};

use std::io;
use std::sync::Arc;

use shapegram_geom::mesh::{newell, newell_quad};
use shapegram_geom::triangulate::{Triangulator, is_convex_about, is_convex_quad};
use shapegram_geom::{Color, DVec2, DVec3, Maps, Mesh, Model, Part, Surface, SurfaceKey, Texture};

/// An `InvalidInput` error for the first part whose bone names a skeleton or section the model
/// does not have (posing or skinning it would index out of bounds).
pub(crate) fn check_bones(model: &Model) -> io::Result<()> {
    for (i, part) in model.parts.iter().enumerate() {
        let Some(bone) = part.bone else { continue };
        let exists = model
            .skeletons
            .get(bone.skeleton as usize)
            .is_some_and(|skeleton| bone.section.index() < skeleton.len());
        if !exists {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "part {i} ('{}') hangs from section {} of skeleton {}, which the model does not have",
                    part.name, bone.section.0, bone.skeleton
                ),
            ));
        }
    }
    Ok(())
}

/// The model as formats without skins write it: in its current pose ([`Model::posed`]), or
/// borrowed as it is when no part hangs from a skeleton.
pub(crate) fn posed(model: &Model) -> io::Result<Cow<'_, Model>> {
    check_bones(model)?;
    Ok(if model.parts.iter().any(|p| p.bone.is_some()) {
        Cow::Owned(model.posed())
    } else {
        Cow::Borrowed(model)
    })
}

/// Whether face `i` is written at all. Faces without area (zero Newell normal) have no side to
/// show and no valid normal, and corners that are not finite in f32 (NaN, infinite, or beyond
/// f32 range) would put NaN or infinity into files whose readers reject them; every writer
/// drops both.
pub(crate) fn face_is_exportable(mesh: &Mesh, i: usize) -> bool {
    mesh.face_normal(i) != DVec3::ZERO && mesh.face_points(i).all(|p| p.as_vec3().is_finite())
}

/// Whether a part is shaded smooth: it has one normal per vertex. Parts whose normals do not
/// match their vertices in number are written flat.
pub(crate) fn is_smooth(part: &Part) -> bool {
    !part.normals.is_empty() && part.normals.len() == part.mesh.vertex_count()
}

/// The part's normals, where those that cannot be made unit (zero or not finite) are replaced
/// by the normal of the first exportable face around their vertex.
pub(crate) fn usable_normals(part: &Part) -> Cow<'_, [DVec3]> {
    // A finite, non-zero squared length makes a unit vector; no square root needed (glam's
    // is a software one here, and parts have millions of normals).
    let usable = |n: &DVec3| {
        let squared = n.length_squared();
        (squared > 0.0) & squared.is_finite()
    };
    let mut normals = Cow::Borrowed(part.normals.as_slice());
    // A fold without a branch per normal rather than `all`: nearly every part's normals are
    // all usable, so `all` would read the whole list too.
    if !normals.iter().fold(true, |ok, n| ok & usable(n)) {
        let fixed = normals.to_mut();
        let mesh = &part.mesh;
        for i in (0..mesh.face_count()).filter(|&i| face_is_exportable(mesh, i)) {
            for &v in mesh.face(i) {
                if !usable(&fixed[v as usize]) {
                    fixed[v as usize] = mesh.face_normal(i);
                }
            }
        }
    }
    normals
}

/// Whether a segment of a line set is written: both points exist, are finite in f32 and stay
/// apart when rounded to f32.
pub(crate) fn segment_is_exportable(points: &[DVec3], segment: [u32; 2]) -> bool {
    let point = |i: u32| {
        points
            .get(i as usize)
            .map(|p| p.as_vec3())
            .filter(|p| p.is_finite())
    };
    matches!((point(segment[0]), point(segment[1])), (Some(p), Some(q)) if p != q)
}

/// A face converted to f32: its unit normal, the corners its triangles use, and the triangles
/// (indices into `corners`, wound like the face).
pub(crate) struct FlatFace<'a> {
    pub normal: [f32; 3],
    pub corners: &'a [[f32; 3]],
    /// The mesh vertex of each corner.
    pub vertices: &'a [u32],
    pub triangles: &'a [[u32; 3]],
}

/// Splits faces into the triangles the writers emit, with scratch space kept between faces.
///
/// Triangles that lose their area when the corners are rounded to f32 are dropped, because the
/// validator and slicers see the f32 geometry, not ours.
#[derive(Default)]
pub(crate) struct FaceSplitter {
    triangulator: Triangulator,
    points: Vec<DVec3>,
    rounded: Vec<[f32; 3]>,
    /// The f32 corners of the last quad split, kept apart from `rounded`: a list's length and
    /// capacity cost more to keep than four corners.
    quad: [[f32; 3]; 4],
    /// Whether the face last split was a quad (its corners in `quad`).
    last_was_quad: bool,
    fanned: Vec<[u32; 3]>,
}

impl FaceSplitter {
    /// The Newell normal of face `i` and its triangles as corner positions within the loop
    /// (appended to `out`), or `None` for a face that is not written at all (see
    /// [`face_is_exportable`]); a face may keep no triangle.
    pub fn split(&mut self, mesh: &Mesh, i: usize, out: &mut Vec<[u32; 3]>) -> Option<DVec3> {
        self.split_loop(mesh.positions(), mesh.face(i), out)
    }

    /// [`Self::split`] of the face with corners `face` (indices into `positions`).
    pub fn split_loop(
        &mut self,
        positions: &[DVec3],
        face: &[u32],
        out: &mut Vec<[u32; 3]>,
    ) -> Option<DVec3> {
        if let &[a, b, c, d] = face {
            // Corner by corner, not in an array: an array of corners went through the stack,
            // and reading it back stalled on every quad.
            let p = |v: u32| positions[v as usize];
            return self.split_quad(p(a), p(b), p(c), p(d), out);
        }
        self.points.clear();
        self.points
            .extend(face.iter().map(|&v| positions[v as usize]));
        let normal = newell(self.points.iter().copied());
        if normal == DVec3::ZERO || !self.points.iter().all(|p| p.as_vec3().is_finite()) {
            return None;
        }
        self.last_was_quad = false;
        self.rounded.clear();
        self.rounded
            .extend(self.points.iter().map(|p| p.as_vec3().to_array()));
        // Triangles and convex quads, most faces of real models, need no triangulator; nor do
        // other convex polygons (such as tube caps) whose fan keeps every triangle, which is
        // what the triangulator would return for them.
        let n = self.points.len() as u32;
        let rounded = &self.rounded;
        let corners = |t: &[u32; 3]| {
            [
                rounded[t[0] as usize],
                rounded[t[1] as usize],
                rounded[t[2] as usize],
            ]
        };
        let fan: &[[u32; 3]] = match n {
            3 => &[[0, 1, 2]],
            4 if is_convex_about(&self.points, normal) => &[[0, 1, 2], [0, 2, 3]],
            _ if is_convex_about(&self.points, normal)
                && (1..n - 1).all(|i| has_f32_area(corners(&[0, i, i + 1]))) =>
            {
                self.fanned.clear();
                self.fanned.extend((1..n - 1).map(|i| [0, i, i + 1]));
                &self.fanned
            }
            _ => {
                self.fanned = self.triangulator.triangulate(&self.points, &[]);
                &self.fanned
            }
        };
        for t in fan {
            if has_f32_area(corners(t)) {
                out.push(*t);
            }
        }
        Some(normal)
    }

    /// [`Self::split`] of the quad `a b c d`, in locals rather than the scratch lists: a tube
    /// is millions of quads. The same tests in the same order give the same normal and
    /// triangles.
    fn split_quad(
        &mut self,
        a: DVec3,
        b: DVec3,
        c: DVec3,
        d: DVec3,
        out: &mut Vec<[u32; 3]>,
    ) -> Option<DVec3> {
        let normal = newell_quad(a, b, c, d);
        let (ra, rb, rc, rd) = (a.as_vec3(), b.as_vec3(), c.as_vec3(), d.as_vec3());
        // `x - x` is 0 for a finite `x` and NaN otherwise: one sum tests all twelve
        // coordinates without a branch each.
        #[allow(clippy::eq_op, reason = "zero or NaN: the test itself")]
        let finite = ((ra - ra) + (rb - rb) + (rc - rc) + (rd - rd)).element_sum() == 0.0;
        if normal == DVec3::ZERO || !finite {
            return None;
        }
        let rounded = [ra.to_array(), rb.to_array(), rc.to_array(), rd.to_array()];
        self.quad = rounded;
        self.last_was_quad = true;
        if is_convex_quad(a, b, c, d, normal) {
            let kept = fan_f32_areas(rounded);
            for (t, kept) in [[0, 1, 2], [0, 2, 3]].into_iter().zip(kept) {
                if kept {
                    out.push(t);
                }
            }
            return Some(normal);
        }
        self.fanned = self.triangulator.triangulate(&[a, b, c, d], &[]);
        for t in &self.fanned {
            if has_f32_area(t.map(|c| rounded[c as usize])) {
                out.push(*t);
            }
        }
        Some(normal)
    }

    /// The f32 corners of the face last split.
    fn rounded(&self) -> &[[f32; 3]] {
        if self.last_was_quad {
            &self.quad
        } else {
            &self.rounded
        }
    }
}

/// Calls `visit` for every exportable face that keeps at least one triangle, in face order.
pub(crate) fn flat_faces(mesh: &Mesh, mut visit: impl FnMut(FlatFace<'_>)) {
    let mut splitter = FaceSplitter::default();
    let mut fan = Vec::new();
    let mut used = Vec::new();
    let mut corners = Vec::new();
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for i in 0..mesh.face_count() {
        fan.clear();
        let Some(normal) = splitter.split(mesh, i, &mut fan) else {
            continue;
        };
        if fan.is_empty() {
            continue;
        }
        let rounded = splitter.rounded();
        let face = mesh.face(i);
        used.clear();
        used.resize(rounded.len(), u32::MAX);
        corners.clear();
        vertices.clear();
        triangles.clear();
        for &triangle in &fan {
            triangles.push(triangle.map(|c| {
                let slot = &mut used[c as usize];
                if *slot == u32::MAX {
                    *slot = corners.len() as u32;
                    corners.push(rounded[c as usize]);
                    vertices.push(face[c as usize]);
                }
                *slot
            }));
        }
        visit(FlatFace {
            normal: unit(normal),
            corners: &corners,
            vertices: &vertices,
            triangles: &triangles,
        });
    }
}

/// A Newell normal as a unit f32 vector. `f64::sqrt` is correctly rounded on every platform, like
/// glam's libm one, but runs as one instruction.
pub(crate) fn unit(normal: DVec3) -> [f32; 3] {
    (normal / normal.length_squared().sqrt())
        .as_vec3()
        .to_array()
}

/// Whether a triangle of f32 corners spans an angle that f32 can resolve: the sine of its angle
/// at the first corner is above f32 precision (so slivers of collinear corners count as empty).
#[inline]
fn has_f32_area([a, b, c]: [[f32; 3]; 3]) -> bool {
    // Element by element: `array::map` went out of line through the stack here, and that
    // round trip cost more than the arithmetic.
    let wide = |p: [f32; 3]| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
    let (a, b, c) = (wide(a), wide(b), wide(c));
    let (ab, ac) = (b - a, c - a);
    let cross = ab.cross(ac).length_squared();
    let eps = f64::from(f32::EPSILON);
    cross > eps * eps * ab.length_squared() * ac.length_squared()
}

/// [`has_f32_area`] of a convex quad's two fan triangles, `[0, 1, 2]` and `[0, 2, 3]`, with
/// the same arithmetic: their shared corner and diagonal are widened and measured once.
#[inline]
fn fan_f32_areas([a, b, c, d]: [[f32; 3]; 4]) -> [bool; 2] {
    let wide = |p: [f32; 3]| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
    let a = wide(a);
    let (ab, ac, ad) = (wide(b) - a, wide(c) - a, wide(d) - a);
    let (ab2, ac2, ad2) = (
        ab.length_squared(),
        ac.length_squared(),
        ad.length_squared(),
    );
    let eps = f64::from(f32::EPSILON);
    [
        ab.cross(ac).length_squared() > eps * eps * ab2 * ac2,
        ac.cross(ad).length_squared() > eps * eps * ac2 * ad2,
    ]
}

/// A textured part's uvs: one per mesh vertex, when a texture layer (the colour map or one of
/// [`Part::surface`]'s) has an image the formats can carry (PNG or JPEG); else the part is
/// drawn in its colour alone.
pub(crate) fn texture_uvs(part: &Part) -> Option<&[DVec2]> {
    let surface_maps = part.surface.iter().flat_map(|s| s.maps.layers());
    let drawn = part.texture.as_ref().is_some_and(|t| drawable(t))
        || surface_maps.filter_map(|(_, t)| t).any(|t| drawable(t));
    (drawn && part.uvs.len() == part.mesh.positions().len()).then_some(&part.uvs)
}

/// Whether a texture has an image the formats can carry.
pub(crate) fn drawable(texture: &Texture) -> bool {
    texture.mime_type().is_some()
}

/// The textures a part is drawn with (its colour map, then its other layers in CGA's order),
/// those with images, when it has uvs for them.
pub(crate) fn drawn_textures(part: &Part) -> impl Iterator<Item = &Arc<Texture>> {
    let textured = texture_uvs(part).is_some();
    let surface_maps = part.surface.iter().flat_map(|s| s.maps.layers());
    part.texture
        .iter()
        .chain(surface_maps.filter_map(|(_, t)| t))
        .filter(move |t| textured && drawable(t))
}

/// The image files a model's textured parts need beside an OBJ's MTL (every layer's), by
/// texture path in order of first use: each named after its path's last component, made unique with `_2`, `_3` … .
pub(crate) fn texture_files(model: &Model) -> Vec<(Arc<str>, String, Arc<[u8]>)> {
    let mut files: Vec<(Arc<str>, String, Arc<[u8]>)> = Vec::new();
    for texture in model.parts.iter().flat_map(drawn_textures) {
        if files.iter().any(|(path, _, _)| *path == texture.path) {
            continue;
        }
        let Some(image) = texture.image.clone() else {
            continue;
        };
        let base = texture.path.rsplit(['/', '\\']).next().unwrap_or_default();
        let base = if base.is_empty() { "texture" } else { base };
        let (stem, extension) = base.rsplit_once('.').unwrap_or((base, ""));
        let mut name = base.to_owned();
        let mut n = 2;
        while files.iter().any(|(_, taken, _)| *taken == name) {
            name = format!("{stem}_{n}.{extension}");
            n += 1;
        }
        files.push((texture.path.clone(), name, image));
    }
    files
}

/// What tells two materials apart: the colour's bits, the texture's index, the name and the
/// surface.
type MaterialKey = (
    [u32; 4],
    Option<usize>,
    Option<Arc<str>>,
    Option<SurfaceKey>,
);

/// The distinct materials of a model: a colour, the texture (if any) it is drawn with, the
/// name the grammar gave it (if any) and its other attributes and layers (if any), in order of
/// first appearance.
#[derive(Default)]
pub(crate) struct Palette {
    colors: Vec<[f32; 4]>,
    textures: Vec<Option<usize>>,
    names: Vec<Option<Arc<str>>>,
    surfaces: Vec<Option<Arc<Surface>>>,
    index: BTreeMap<MaterialKey, usize>,
}

impl Palette {
    /// The material index of a colour with a texture (an index the caller keeps), a name and a
    /// surface, adding it when new. The surface's layers count only when `textured` (the part
    /// has uvs for them) and have images.
    pub fn material(
        &mut self,
        color: Color,
        texture: Option<usize>,
        name: Option<&Arc<str>>,
        surface: Option<&Arc<Surface>>,
        textured: bool,
    ) -> usize {
        let rgba = color.sanitized();
        let surface = surface.map(|s| drawn_surface(s, textured));
        let key = surface.as_ref().map(|s| s.key());
        *self
            .index
            .entry((rgba.map(f32::to_bits), texture, name.cloned(), key))
            .or_insert_with(|| {
                self.colors.push(rgba);
                self.textures.push(texture);
                self.names.push(name.cloned());
                self.surfaces.push(surface);
                self.colors.len() - 1
            })
    }

    /// The texture of each material.
    pub fn textures(&self) -> &[Option<usize>] {
        &self.textures
    }

    /// The surface of each material, its layers those that are drawn.
    pub fn surfaces(&self) -> &[Option<Arc<Surface>>] {
        &self.surfaces
    }

    /// The sanitized colours, by material index.
    pub fn colors(&self) -> &[[f32; 4]] {
        &self.colors
    }

    /// Per material: the grammar's name for it, else `#rrggbb` (or `#rrggbbaa`), where two
    /// colours closer than 1/255 share a name.
    pub fn names(&self) -> Vec<String> {
        self.colors
            .iter()
            .zip(&self.names)
            .map(|(&[r, g, b, a], name)| match name {
                Some(name) => name.to_string(),
                None => Color { r, g, b, a }.to_hex(),
            })
            .collect()
    }

    /// Names safe for MTL (no `#`, which some OBJ readers take for a comment, no whitespace,
    /// which ends a name) and unique, since `usemtl` refers to materials by name.
    pub fn unique_names(&self) -> Vec<String> {
        let mut taken = BTreeSet::new();
        self.names()
            .into_iter()
            .zip(&self.names)
            .map(|(name, given)| {
                let base = match given {
                    Some(_) => sanitized_name(&name.replace('#', "_")),
                    None => format!("color_{}", name.trim_start_matches('#')),
                };
                let mut name = base.clone();
                let mut n = 2;
                while !taken.insert(name.clone()) {
                    name = format!("{base}_{n}");
                    n += 1;
                }
                name
            })
            .collect()
    }
}

/// A surface with the layers that are drawn: none without uvs, and only those with images
/// (the same surface when that is all of them).
fn drawn_surface(surface: &Arc<Surface>, textured: bool) -> Arc<Surface> {
    let kept = |t: &Option<Arc<Texture>>| t.as_ref().filter(|t| textured && drawable(t)).cloned();
    let maps = &surface.maps;
    let drawn = Maps {
        bump: kept(&maps.bump),
        dirt: kept(&maps.dirt),
        specular: kept(&maps.specular),
        opacity: kept(&maps.opacity),
        normal: kept(&maps.normal),
        emissive: kept(&maps.emissive),
        occlusion: kept(&maps.occlusion),
        roughness: kept(&maps.roughness),
        metallic: kept(&maps.metallic),
    };
    if drawn == *maps {
        surface.clone()
    } else {
        Arc::new(Surface {
            finish: surface.finish,
            maps: drawn,
            transforms: surface.transforms,
        })
    }
}

/// Group names as OBJ wants them: whitespace would end the name, so it becomes `_`.
pub(crate) fn sanitized_name(name: &str) -> String {
    if name.trim().is_empty() {
        return "part".to_owned();
    }
    name.chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Splits the single face of a polygon.
    fn split(points: &[DVec3]) -> (Option<DVec3>, Vec<[u32; 3]>) {
        let mut fan = Vec::new();
        let normal = FaceSplitter::default().split(&Mesh::from_polygon(points), 0, &mut fan);
        (normal, fan)
    }

    #[test]
    fn a_quad_fan_keeps_the_triangles_with_f32_area() {
        // Quads from wide to slivers thinner than f32 can resolve, some corners repeated.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut random = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u32 << 24) as f32 - 0.5
        };
        let mut seen = [[0; 2]; 2];
        for k in 0..20_000 {
            let width = [1.0, 1e-7, 1e-8, 0.0][k % 4];
            let mut quad = [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ];
            for p in &mut quad {
                *p = [p[0] + random(), p[1] * width + random() * width, 3.0];
            }
            if k % 5 == 0 {
                quad[3] = quad[2];
            }
            let [a, b, c, d] = quad;
            let expected = [has_f32_area([a, b, c]), has_f32_area([a, c, d])];
            assert_eq!(fan_f32_areas(quad), expected, "{quad:?}");
            for (i, kept) in expected.into_iter().enumerate() {
                seen[i][usize::from(kept)] += 1;
            }
        }
        assert!(seen.iter().flatten().all(|&n| n > 100), "{seen:?}");
    }

    #[test]
    fn quads_split_as_the_other_polygons() {
        let p = |x, y| DVec3::new(x, y, 0.0);
        let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
        assert_eq!(
            split(&square),
            (Some(DVec3::new(0.0, 0.0, 2.0)), vec![[0, 1, 2], [0, 2, 3]])
        );
        // A dart whose reflex corner is the last: the triangulator cuts along 1-3.
        let dart = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.8, 0.2)];
        let (normal, fan) = split(&dart);
        assert_eq!(normal, Some(newell(dart.into_iter())));
        assert_eq!(fan.len(), 2);
        assert!(
            fan.iter().all(|t| t.contains(&1) && t.contains(&3)),
            "{fan:?}"
        );
        // A sliver keeps the triangle with area; a face without area or finite corners none.
        let sliver = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.5, 0.5)];
        assert_eq!(split(&sliver).1, vec![[0, 1, 2]]);
        let flat = [p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0), p(3.0, 0.0)];
        assert_eq!(split(&flat), (None, vec![]));
        let far = [p(0.0, 0.0), p(1e300, 0.0), p(1e300, 1e300), p(0.0, 1e300)];
        assert_eq!(split(&far), (None, vec![]));
        let beyond_f32 = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(-4e38, 1.0)];
        assert_eq!(split(&beyond_f32), (None, vec![]));
        let nan = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, f64::NAN), p(0.0, 1.0)];
        assert_eq!(split(&nan), (None, vec![]));
    }
}
