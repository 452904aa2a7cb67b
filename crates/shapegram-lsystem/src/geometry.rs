//! A turtle drawing as a 3D model: strokes become tubes, polygons become two-sided faces, one
//! part per kind and colour.
//!
//! A tube is a generalised cylinder along its stroke: a ring of `sides` vertices at every point,
//! mitred at the joints (the ring lies in the plane that halves the bend) and carried along the
//! stroke by parallel transport, so it does not twist. Each segment tapers from its own width
//! to the next one's. Both ends are capped, so every tube is closed. A bend sharper than 120°
//! would fold the mitre, so the tube ends there and a new one starts.

use std::collections::BTreeMap;

use glam::{DQuat, DVec3};
use shapegram_geom::{Color, DAffine3, Mesh, Model, Part, Scope};

use crate::system::Settings;
use crate::turtle::{Drawing, Polygon, Stroke};

/// Cosine of the sharpest bend a tube follows without starting anew (120°).
const SHARPEST_BEND_COS: f64 = -0.5;

/// The model of a drawing: tubes with `settings.sides` sides and leaves, coloured from
/// `settings.colors` (colour indices past the end wrap around). Parts come in palette order,
/// branches before leaves of the same colour.
pub fn drawing_to_model(drawing: &Drawing, settings: &Settings) -> Model {
    let mut meshes: BTreeMap<(usize, u8), Mesh> = BTreeMap::new();
    let palette = if settings.colors.is_empty() {
        vec![Color::default()]
    } else {
        settings.colors.clone()
    };
    let slot = |color: usize| color % palette.len();
    for stroke in &drawing.strokes {
        let mesh = meshes.entry((slot(stroke.color), 0)).or_default();
        add_stroke(mesh, stroke, settings.sides.max(3) as usize);
    }
    for polygon in &drawing.polygons {
        let mesh = meshes.entry((slot(polygon.color), 1)).or_default();
        add_polygon(mesh, polygon);
    }
    let parts = meshes
        .into_iter()
        .filter(|(_, mesh)| !mesh.is_empty())
        .map(|((color, kind), mesh)| Part {
            name: format!("{}-{color}", if kind == 0 { "branches" } else { "leaves" }),
            color: palette[color],
            mesh,
        })
        .collect();
    Model { parts }
}

/// Adds the tubes of one stroke, split at bends too sharp to mitre.
fn add_stroke(mesh: &mut Mesh, stroke: &Stroke, sides: usize) {
    let mut start = 0;
    for k in 1..stroke.widths.len() {
        let incoming = stroke.points[k] - stroke.points[k - 1];
        let outgoing = stroke.points[k + 1] - stroke.points[k];
        if incoming
            .normalize_or_zero()
            .dot(outgoing.normalize_or_zero())
            < SHARPEST_BEND_COS
        {
            add_tube(
                mesh,
                &stroke.points[start..=k],
                &stroke.widths[start..k],
                sides,
            );
            start = k;
        }
    }
    add_tube(
        mesh,
        &stroke.points[start..],
        &stroke.widths[start..],
        sides,
    );
}

/// Adds one closed tube through `points` (at least two) with a width per segment.
fn add_tube(mesh: &mut Mesh, points: &[DVec3], widths: &[f64], sides: usize) {
    let segments = widths.len();
    if segments == 0 {
        return;
    }
    let direction = |k: usize| (points[k + 1] - points[k]).normalize();
    let mut d = direction(0);
    let mut u = d.any_orthonormal_vector();
    let mut v = d.cross(u);
    let (sin, cos): (Vec<f64>, Vec<f64>) = (0..sides)
        .map(|j| (std::f64::consts::TAU * j as f64 / sides as f64).sin_cos())
        .unzip();
    let mut rings: Vec<u32> = Vec::with_capacity(segments + 1);
    let ring = |mesh: &mut Mesh,
                center: DVec3,
                radius: f64,
                u: DVec3,
                v: DVec3,
                miter: Option<(DVec3, DVec3)>| {
        let first = mesh.vertex_count() as u32;
        for j in 0..sides {
            let mut q = center + (u * cos[j] + v * sin[j]) * radius;
            if let Some((along, normal)) = miter {
                // Slide the point along the incoming segment onto the mitre plane.
                let t = -(q - center).dot(normal) / along.dot(normal);
                q += along * t;
            }
            mesh.add_vertex(q);
        }
        first
    };
    rings.push(ring(mesh, points[0], widths[0] / 2.0, u, v, None));
    for k in 1..segments {
        let next = direction(k);
        let normal = (d + next).normalize();
        rings.push(ring(
            mesh,
            points[k],
            widths[k] / 2.0,
            u,
            v,
            Some((d, normal)),
        ));
        let turn = DQuat::from_rotation_arc(d, next);
        u = (turn * u).normalize();
        v = next.cross(u);
        d = next;
    }
    rings.push(ring(
        mesh,
        points[segments],
        widths[segments - 1] / 2.0,
        u,
        v,
        None,
    ));
    let n = sides as u32;
    for pair in rings.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        for j in 0..n {
            let j1 = (j + 1) % n;
            mesh.add_face(&[a + j, a + j1, b + j1, b + j]);
        }
    }
    let start: Vec<u32> = (0..n).rev().map(|j| rings[0] + j).collect();
    let end: Vec<u32> = (0..n).map(|j| rings[segments] + j).collect();
    mesh.add_face(&start);
    mesh.add_face(&end);
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
    let extent = bounds.size();
    let tiny = 1e-12 * extent.max_element().max(size.max_element());
    let scale = (0..3)
        .filter(|&k| size[k] > tiny && extent[k] > tiny)
        .map(|k| size[k] / extent[k])
        .reduce(f64::min)
        .unwrap_or(1.0);
    let offset = DVec3::new(
        (size.x - extent.x * scale) / 2.0,
        0.0,
        (size.z - extent.z * scale) / 2.0,
    );
    let map = DAffine3::from_translation(offset)
        * DAffine3::from_scale(DVec3::splat(scale))
        * DAffine3::from_translation(-bounds.min);
    transformed(model, &map)
}

/// The model fitted into the scope's box (see [`fit_into_box`]) and placed in world space with
/// the scope's origin and axes: the seam where a shape grammar plants an L-system on a lot.
pub fn fit_into_scope(model: &Model, scope: &Scope) -> Model {
    let local = fit_into_box(model, scope.size);
    transformed(&local, &scope.local_to_world())
}

fn transformed(model: &Model, map: &DAffine3) -> Model {
    Model {
        parts: model
            .parts
            .iter()
            .map(|part| Part {
                name: part.name.clone(),
                color: part.color,
                mesh: part.mesh.transformed(map),
            })
            .collect(),
    }
}
