//! What the writers share: which faces make it into a file, their f32 triangles, and the
//! materials (one per distinct colour, in order of first appearance).

use std::collections::{BTreeMap, BTreeSet};

use shapegram_geom::mesh::newell;
use shapegram_geom::triangulate::{Triangulator, is_convex};
use shapegram_geom::{Color, DVec3, Mesh};

/// Whether face `i` is written at all. Faces without area (zero Newell normal) have no side to
/// show and no valid normal, and corners that are not finite in f32 (NaN, infinite, or beyond
/// f32 range) would put NaN or infinity into files whose readers reject them; every writer
/// drops both.
pub(crate) fn face_is_exportable(mesh: &Mesh, i: usize) -> bool {
    mesh.face_normal(i) != DVec3::ZERO && mesh.face_points(i).all(|p| p.as_vec3().is_finite())
}

/// A face converted to f32: its unit normal, the corners its triangles use, and the triangles
/// (indices into `corners`, wound like the face).
pub(crate) struct FlatFace<'a> {
    pub normal: [f32; 3],
    pub corners: &'a [[f32; 3]],
    pub triangles: &'a [[u32; 3]],
}

/// Calls `visit` for every exportable face that keeps at least one triangle, in face order.
///
/// Triangles that lose their area when the corners are rounded to f32 are dropped here, because
/// the validator and slicers see the f32 geometry, not ours.
pub(crate) fn flat_faces(mesh: &Mesh, mut visit: impl FnMut(FlatFace<'_>)) {
    let mut triangulator = Triangulator::new();
    let mut points = Vec::new();
    let mut rounded = Vec::new();
    let mut used = Vec::new();
    let mut corners = Vec::new();
    let mut triangles = Vec::new();
    let mut fanned;
    for i in 0..mesh.face_count() {
        points.clear();
        points.extend(mesh.face_points(i));
        let normal = newell(points.iter().copied());
        if normal == DVec3::ZERO || !points.iter().all(|p| p.as_vec3().is_finite()) {
            continue;
        }
        rounded.clear();
        rounded.extend(points.iter().map(|p| p.as_vec3().to_array()));
        used.clear();
        used.resize(points.len(), u32::MAX);
        corners.clear();
        triangles.clear();
        // Triangles and convex quads, most faces of real models, need no triangulator.
        let fan: &[[u32; 3]] = match points.len() {
            3 => &[[0, 1, 2]],
            4 if is_convex(&points) => &[[0, 1, 2], [0, 2, 3]],
            _ => {
                fanned = triangulator.triangulate(&points, &[]);
                &fanned
            }
        };
        for &triangle in fan {
            if !has_f32_area(triangle.map(|c| rounded[c as usize])) {
                continue;
            }
            triangles.push(triangle.map(|c| {
                let slot = &mut used[c as usize];
                if *slot == u32::MAX {
                    *slot = corners.len() as u32;
                    corners.push(rounded[c as usize]);
                }
                *slot
            }));
        }
        if !triangles.is_empty() {
            visit(FlatFace {
                normal: unit(normal),
                corners: &corners,
                triangles: &triangles,
            });
        }
    }
}

/// A Newell normal as a unit f32 vector. `f64::sqrt` is correctly rounded on every platform, like
/// glam's libm one, but runs as one instruction.
fn unit(normal: DVec3) -> [f32; 3] {
    (normal / normal.length_squared().sqrt())
        .as_vec3()
        .to_array()
}

/// Whether a triangle of f32 corners spans an angle that f32 can resolve: the sine of its angle
/// at the first corner is above f32 precision (so slivers of collinear corners count as empty).
fn has_f32_area(corners: [[f32; 3]; 3]) -> bool {
    let [a, b, c] = corners.map(|p| DVec3::from(p.map(f64::from)));
    let (ab, ac) = (b - a, c - a);
    let cross = ab.cross(ac).length_squared();
    let eps = f64::from(f32::EPSILON);
    cross > eps * eps * ab.length_squared() * ac.length_squared()
}

/// Colour channels as written: clamped to `0..=1`, NaN replaced, and -0 made +0 so that equal
/// colours compare equal bit for bit.
pub(crate) fn sanitized(color: Color) -> [f32; 4] {
    let channel = |c: f32, fallback: f32| {
        if c.is_nan() {
            fallback
        } else {
            c.clamp(0.0, 1.0) + 0.0
        }
    };
    [
        channel(color.r, 0.0),
        channel(color.g, 0.0),
        channel(color.b, 0.0),
        channel(color.a, 1.0),
    ]
}

/// The distinct colours of a model in order of first appearance: one material each.
#[derive(Default)]
pub(crate) struct Palette {
    colors: Vec<[f32; 4]>,
    index: BTreeMap<[u32; 4], usize>,
}

impl Palette {
    /// The material index of a colour, adding it when new.
    pub fn material(&mut self, color: Color) -> usize {
        let rgba = sanitized(color);
        *self.index.entry(rgba.map(f32::to_bits)).or_insert_with(|| {
            self.colors.push(rgba);
            self.colors.len() - 1
        })
    }

    /// The sanitized colours, by material index.
    pub fn colors(&self) -> &[[f32; 4]] {
        &self.colors
    }

    /// `#rrggbb` (or `#rrggbbaa`) per material; two colours closer than 1/255 share a name.
    pub fn hex_names(&self) -> Vec<String> {
        self.colors
            .iter()
            .map(|&[r, g, b, a]| Color { r, g, b, a }.to_hex())
            .collect()
    }

    /// Names safe for MTL (no `#`, which some OBJ readers take for a comment) and unique, since
    /// `usemtl` refers to materials by name.
    pub fn unique_names(&self) -> Vec<String> {
        let mut taken = BTreeSet::new();
        self.hex_names()
            .into_iter()
            .map(|hex| {
                let base = format!("color_{}", hex.trim_start_matches('#'));
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

/// Group names as OBJ wants them: whitespace would end the name, so it becomes `_`.
pub(crate) fn sanitized_name(name: &str) -> String {
    if name.trim().is_empty() {
        return "part".to_owned();
    }
    name.chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect()
}
