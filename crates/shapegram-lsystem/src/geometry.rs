//! A turtle drawing as a 3D model: strokes become tubes (or line sets), polygons become
//! two-sided faces, one part per kind and colour.
//!
//! A tube is a generalised cylinder along its stroke: a ring of `sides` vertices at every point,
//! mitred at the joints (the ring lies in the plane that halves the bend) and carried along the
//! stroke by parallel transport, so it does not twist. Each segment tapers from its own width
//! to the next one's. Both ends are capped, so every tube is closed. A bend sharper than 120°
//! would fold the mitre, so the tube ends there and a new one starts. Tubes are smooth-shaded:
//! each ring vertex has the radial normal of its ring's frame, and the caps share the ring
//! vertices (so tubes stay closed by index) and their normals.
//!
//! As lines, every stroke is a polyline of its own points and the segments between them:
//! a few dozen bytes per segment instead of hundreds, for words of millions of segments.

use std::collections::BTreeMap;

use glam::DVec3;
use shapegram_geom::fit::proportional_map;
use shapegram_geom::{Color, DAffine3, Lines, Mesh, Model, Part, Scope};

use crate::error::Error;
use crate::rewrite::group_digits;
use crate::system::Settings;
use crate::turtle::{Drawing, Polygon, Stroke};

/// Cosine of the sharpest bend a tube follows without starting anew (120°).
const SHARPEST_BEND_COS: f64 = -0.5;

/// The model of a drawing: tubes with `settings.sides` sides and leaves, coloured from
/// `settings.colors` (colour indices past its end take its last colour, so palettes work as
/// gradients). Parts come in palette order,
/// branches before leaves of the same colour.
pub fn drawing_to_model(drawing: &Drawing, settings: &Settings) -> Model {
    let palette = Palette::of(settings);
    let sides = settings.sides.max(3) as usize;
    // Sized first: a word of a million segments would otherwise copy its hundreds of megabytes
    // of vertices, normals and faces as they grow.
    let mut sizes: BTreeMap<usize, TubeSizes> = BTreeMap::new();
    for stroke in drawing.strokes.iter().filter(|s| !s.widths.is_empty()) {
        let size = sizes.entry(palette.slot(stroke.color)).or_default();
        let tubes = sharp_bends(stroke).count() + 1;
        size.rings += stroke.widths.len() + tubes;
        size.segments += stroke.widths.len();
        size.tubes += tubes;
    }
    let mut tubes: BTreeMap<usize, (Mesh, Vec<DVec3>)> = sizes
        .into_iter()
        .map(|(slot, size)| (slot, size.reserved(sides)))
        .collect();
    let mut builder = TubeBuilder::new(sides);
    for stroke in &drawing.strokes {
        let (mesh, normals) = tubes.entry(palette.slot(stroke.color)).or_default();
        builder.add_stroke(mesh, normals, stroke);
    }
    let mut parts: BTreeMap<(usize, u8), Part> = tubes
        .into_iter()
        .filter(|(_, (mesh, _))| !mesh.is_empty())
        .map(|(slot, (mesh, normals))| {
            let part = Part {
                texture: None,
                uvs: Vec::new(),
                bone: None,
                metadata: None,
                name: format!("branches-{slot}"),
                color: palette.colors[slot],
                mesh,
                normals,
                material: None,
                surface: None,
                instance: None,
            };
            ((slot, 0), part)
        })
        .collect();
    parts.extend(leaves(drawing, &palette).map(|(slot, part)| ((slot, 1), part)));
    Model {
        skeletons: Vec::new(),
        parts: parts.into_values().collect(),
        lines: Vec::new(),
    }
}

/// The model of a drawing with strokes as line sets (one per colour, named `branches-i`, points
/// shared along each stroke) and polygons as leaves like [`drawing_to_model`]'s. Line sets come
/// in palette order, after the leaf parts.
pub fn drawing_to_lines(drawing: &Drawing, settings: &Settings) -> Model {
    let palette = Palette::of(settings);
    // Sized first: a word of a million segments would otherwise copy its points as they grow.
    let mut sizes: BTreeMap<usize, (usize, usize)> = BTreeMap::new();
    for stroke in drawing.strokes.iter().filter(|s| !s.widths.is_empty()) {
        let size = sizes.entry(palette.slot(stroke.color)).or_default();
        size.0 += stroke.points.len();
        size.1 += stroke.widths.len();
    }
    let mut lines: BTreeMap<usize, Lines> = sizes
        .into_iter()
        .map(|(slot, (points, segments))| {
            let lines = Lines {
                name: format!("branches-{slot}"),
                color: palette.colors[slot],
                points: Vec::with_capacity(points),
                segments: Vec::with_capacity(segments),
            };
            (slot, lines)
        })
        .collect();
    for stroke in drawing.strokes.iter().filter(|s| !s.widths.is_empty()) {
        let Some(set) = lines.get_mut(&palette.slot(stroke.color)) else {
            continue;
        };
        let first = set.points.len() as u32;
        set.points.extend_from_slice(&stroke.points);
        set.segments
            .extend((0..stroke.widths.len() as u32).map(|k| [first + k, first + k + 1]));
    }
    Model {
        skeletons: Vec::new(),
        parts: leaves(drawing, &palette).map(|(_, part)| part).collect(),
        lines: lines.into_values().collect(),
    }
}

/// The sizes of one colour's tubes, counted before they are built.
#[derive(Default)]
struct TubeSizes {
    /// One ring per point of each tube: a stroke's points plus one per sharp bend.
    rings: usize,
    segments: usize,
    tubes: usize,
}

impl TubeSizes {
    /// An empty mesh and normal list with room for these tubes: a ring of `sides` vertices per
    /// ring, a quad per side of each segment and two caps of `sides` vertices per tube.
    fn reserved(&self, sides: usize) -> (Mesh, Vec<DVec3>) {
        let vertices = self.rings * sides;
        let faces = self.segments * sides + 2 * self.tubes;
        let indices = (self.segments * 4 + 2 * self.tubes) * sides;
        (
            Mesh::with_capacity(vertices, faces, indices),
            Vec::with_capacity(vertices),
        )
    }
}

/// The colours parts take: the settings' palette, or the default colour when it is empty.
struct Palette {
    colors: Vec<Color>,
}

impl Palette {
    fn of(settings: &Settings) -> Self {
        let colors = if settings.colors.is_empty() {
            vec![Color::default()]
        } else {
            settings.colors.clone()
        };
        Self { colors }
    }

    /// The palette entry of a colour index: past the end, the last one.
    fn slot(&self, color: usize) -> usize {
        color.min(self.colors.len() - 1)
    }
}

/// The polygons as flat-shaded `leaves-i` parts with their palette slots, in palette order.
fn leaves<'a>(drawing: &Drawing, palette: &'a Palette) -> impl Iterator<Item = (usize, Part)> + 'a {
    let mut meshes: BTreeMap<usize, Mesh> = BTreeMap::new();
    for polygon in &drawing.polygons {
        add_polygon(
            meshes.entry(palette.slot(polygon.color)).or_default(),
            polygon,
        );
    }
    meshes
        .into_iter()
        .filter(|(_, mesh)| !mesh.is_empty())
        .map(|(slot, mesh)| {
            let part = Part {
                texture: None,
                uvs: Vec::new(),
                bone: None,
                metadata: None,
                name: format!("leaves-{slot}"),
                color: palette.colors[slot],
                mesh,
                normals: Vec::new(),
                material: None,
                surface: None,
                instance: None,
            };
            (slot, part)
        })
}

/// Default limit on the vertices of a drawing's model: about the size of a cave's largest mesh,
/// a few gigabytes once written.
pub const DEFAULT_MAX_VERTICES: usize = 10_000_000;

/// The model of a drawing like [`drawing_to_model`], or an error when it would have more than
/// `max_vertices` vertices, found before any geometry is built: a word of a few million modules
/// draws fine as SVG but makes tubes of `sides` vertices per point.
pub fn drawing_to_model_within(
    drawing: &Drawing,
    settings: &Settings,
    max_vertices: usize,
) -> Result<Model, Error> {
    let hint = "derive fewer steps, use fewer sides, draw lines, or draw an SVG";
    within(model_vertex_count(drawing, settings), max_vertices, hint)?;
    Ok(drawing_to_model(drawing, settings))
}

/// The model of a drawing like [`drawing_to_lines`], or an error when its points and leaf
/// vertices would number more than `max_vertices`.
pub fn drawing_to_lines_within(
    drawing: &Drawing,
    settings: &Settings,
    max_vertices: usize,
) -> Result<Model, Error> {
    let hint = "derive fewer steps or draw an SVG";
    within(lines_vertex_count(drawing), max_vertices, hint)?;
    Ok(drawing_to_lines(drawing, settings))
}

/// An error naming `hint` when `vertices` is over the limit.
fn within(vertices: usize, max_vertices: usize, hint: &str) -> Result<(), Error> {
    if vertices > max_vertices {
        return Err(Error::general(format!(
            "the model would have up to {} vertices, over the limit of {} ({hint})",
            group_digits(vertices),
            group_digits(max_vertices)
        )));
    }
    Ok(())
}

/// The most vertices [`drawing_to_model`] makes for `drawing`: a ring of `sides` per point of each
/// tube, and every polygon point twice (front and back; repeated points are dropped).
fn model_vertex_count(drawing: &Drawing, settings: &Settings) -> usize {
    let sides = settings.sides.max(3) as usize;
    let rings: usize = drawing
        .strokes
        .iter()
        .filter(|s| !s.widths.is_empty())
        .map(|s| s.points.len() + sharp_bends(s).count())
        .sum();
    rings
        .saturating_mul(sides)
        .saturating_add(leaf_vertex_count(drawing))
}

/// The most vertices [`drawing_to_lines`] makes: the strokes' points and the leaves' vertices.
fn lines_vertex_count(drawing: &Drawing) -> usize {
    let points: usize = drawing
        .strokes
        .iter()
        .filter(|s| !s.widths.is_empty())
        .map(|s| s.points.len())
        .sum();
    points.saturating_add(leaf_vertex_count(drawing))
}

/// Every polygon point twice (front and back; repeated points are dropped).
fn leaf_vertex_count(drawing: &Drawing) -> usize {
    let points: usize = drawing.polygons.iter().map(|p| p.points.len()).sum();
    points.saturating_mul(2)
}

/// The points of a stroke where it bends too sharply to mitre, so one tube ends and the next
/// starts.
fn sharp_bends(stroke: &Stroke) -> impl Iterator<Item = usize> + '_ {
    // Each segment's direction is computed once, as the outgoing one of a point and kept as
    // the incoming one of the next: the tube model walks every stroke's bends twice.
    let mut directions = stroke.points.windows(2).map(|w| unit(w[1] - w[0]));
    let mut incoming = directions.next().unwrap_or(DVec3::ZERO);
    (1..).zip(directions).filter_map(move |(k, outgoing)| {
        let sharp = incoming.dot(outgoing) < SHARPEST_BEND_COS;
        incoming = outgoing;
        sharp.then_some(k)
    })
}

/// `v` scaled to length 1 (`v` must not be zero). The standard library's square root is the
/// exact IEEE operation, like glam's, and runs in hardware.
fn unit(v: DVec3) -> DVec3 {
    v / v.dot(v).sqrt()
}

/// Where tubes go: a mesh and its vertex normals, kept side by side.
struct Tube<'a> {
    mesh: &'a mut Mesh,
    normals: &'a mut Vec<DVec3>,
}

/// Builds tubes; keeps the ring's cosines and sines and a scratch face between tubes.
struct TubeBuilder {
    sides: usize,
    /// Cosine and sine of each ring vertex's angle.
    circle: Vec<(f64, f64)>,
    face: Vec<u32>,
}

impl TubeBuilder {
    fn new(sides: usize) -> Self {
        let circle = (0..sides)
            .map(|j| {
                let (sin, cos) = (std::f64::consts::TAU * j as f64 / sides as f64).sin_cos();
                (cos, sin)
            })
            .collect();
        Self {
            sides,
            circle,
            face: Vec::with_capacity(sides),
        }
    }

    /// Adds the tubes of one stroke, split at bends too sharp to mitre, with a normal per
    /// vertex.
    fn add_stroke(&mut self, mesh: &mut Mesh, normals: &mut Vec<DVec3>, stroke: &Stroke) {
        let mut start = 0;
        let mut tube = Tube { mesh, normals };
        for k in sharp_bends(stroke) {
            self.add_tube(
                &mut tube,
                &stroke.points[start..=k],
                &stroke.widths[start..k],
            );
            start = k;
        }
        self.add_tube(&mut tube, &stroke.points[start..], &stroke.widths[start..]);
    }

    /// Adds a ring of vertices around `center` in the plane of `u` and `v`, slid along `along`
    /// onto the plane through `center` with normal `miter` when given, each with its radial
    /// normal; returns its first index.
    fn ring(
        &self,
        tube: &mut Tube<'_>,
        center: DVec3,
        radius: f64,
        (u, v): (DVec3, DVec3),
        miter: Option<(DVec3, DVec3)>,
    ) -> u32 {
        let first = tube.mesh.vertex_count() as u32;
        for &(cos, sin) in &self.circle {
            let radial = u * cos + v * sin;
            let offset = radial * radius;
            let q = match miter {
                Some((along, normal)) => {
                    center + offset - along * (offset.dot(normal) / along.dot(normal))
                }
                None => center + offset,
            };
            tube.mesh.add_vertex(q);
            tube.normals.push(radial);
        }
        first
    }

    /// Adds one closed tube through `points` (at least two, no repeats) with a width per
    /// segment. Rings are added one after the other, so ring `k` starts at `first + k * sides`.
    fn add_tube(&mut self, tube: &mut Tube<'_>, points: &[DVec3], widths: &[f64]) {
        let segments = widths.len();
        if segments == 0 {
            return;
        }
        let mut d = unit(points[1] - points[0]);
        let mut u = d.any_orthonormal_vector();
        let mut v = d.cross(u);
        let first = self.ring(tube, points[0], widths[0] / 2.0, (u, v), None);
        for k in 1..segments {
            let next = unit(points[k + 1] - points[k]);
            let normal = unit(d + next);
            self.ring(tube, points[k], widths[k] / 2.0, (u, v), Some((d, normal)));
            // Parallel transport: the rotation taking d to next, applied to u (Rodrigues'
            // formula without trigonometry, fine for bends below 180°).
            let (c, axis) = (d.dot(next), d.cross(next));
            u = u * c + axis.cross(u) + axis * (axis.dot(u) / (1.0 + c));
            u = unit(u - next * u.dot(next));
            v = next.cross(u);
            d = next;
        }
        self.ring(
            tube,
            points[segments],
            widths[segments - 1] / 2.0,
            (u, v),
            None,
        );
        let mesh = &mut *tube.mesh;
        let n = self.sides as u32;
        for k in 0..segments as u32 {
            let (a, b) = (first + k * n, first + (k + 1) * n);
            for j in 0..n {
                let j1 = if j + 1 == n { 0 } else { j + 1 };
                mesh.add_face(&[a + j, a + j1, b + j1, b + j]);
            }
        }
        let end = first + segments as u32 * n;
        self.face.clear();
        self.face.extend((0..n).rev().map(|j| first + j));
        mesh.add_face(&self.face);
        self.face.clear();
        self.face.extend((0..n).map(|j| end + j));
        mesh.add_face(&self.face);
    }
}

/// Adds a polygon as two faces back to back (leaves are seen from both sides), after dropping
/// points that repeat their predecessor (a turtle that walks back to its start lands there only
/// up to rounding); polygons without area are skipped.
fn add_polygon(mesh: &mut Mesh, polygon: &Polygon) {
    let Some(bounds) = shapegram_geom::Aabb::from_points(polygon.points.iter().copied()) else {
        return;
    };
    let tolerance = bounds.diagonal() * 1e-9;
    let same = |a: DVec3, b: DVec3| a.distance(b) <= tolerance;
    let mut points: Vec<DVec3> = Vec::with_capacity(polygon.points.len());
    for &p in &polygon.points {
        if points.last().is_none_or(|&q| !same(p, q)) {
            points.push(p);
        }
    }
    while points.len() > 1 && same(points[0], points[points.len() - 1]) {
        points.pop();
    }
    if points.len() < 3 || shapegram_geom::mesh::newell(points.iter().copied()) == DVec3::ZERO {
        return;
    }
    let first = mesh.vertex_count() as u32;
    for &p in points.iter().chain(points.iter().rev()) {
        mesh.add_vertex(p);
    }
    let n = points.len() as u32;
    let front: Vec<u32> = (first..first + n).collect();
    let back: Vec<u32> = (first + n..first + 2 * n).collect();
    mesh.add_face(&front);
    mesh.add_face(&back);
}

/// The model scaled uniformly (keeping its proportions) to fit the box from the origin to
/// `size`, centred in x and z and standing on y = 0. Axes where the box or the model is flat do
/// not limit the scale; an empty model is returned as it is.
pub fn fit_into_box(model: &Model, size: DVec3) -> Model {
    let Some(bounds) = model.bounds() else {
        return model.clone();
    };
    transformed(model, &proportional_map(&bounds, size))
}

/// The model fitted into the scope's box (see [`fit_into_box`]) and placed in world space with
/// the scope's origin and axes: the seam where a shape grammar plants an L-system on a lot.
pub fn fit_into_scope(model: &Model, scope: &Scope) -> Model {
    let local = fit_into_box(model, scope.size);
    transformed(&local, &scope.local_to_world())
}

/// The model under an affine map: positions and points mapped, normals by the inverse transpose
/// of the linear part and made unit again, so smooth shading survives scaling and mirroring.
fn transformed(model: &Model, map: &DAffine3) -> Model {
    let normal_map = map.matrix3.inverse().transpose();
    Model {
        skeletons: Vec::new(),
        parts: model
            .parts
            .iter()
            .map(|part| Part {
                texture: None,
                uvs: Vec::new(),
                bone: None,
                metadata: None,
                name: part.name.clone(),
                color: part.color,
                mesh: part.mesh.transformed(map),
                normals: part
                    .normals
                    .iter()
                    .map(|&n| (normal_map * n).normalize_or(n))
                    .collect(),
                material: None,
                surface: None,
                instance: None,
            })
            .collect(),
        lines: model
            .lines
            .iter()
            .map(|lines| Lines {
                name: lines.name.clone(),
                color: lines.color,
                points: lines
                    .points
                    .iter()
                    .map(|&p| map.transform_point3(p))
                    .collect(),
                segments: lines.segments.clone(),
            })
            .collect(),
    }
}
