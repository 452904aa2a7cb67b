//! Closed primitives built to fill the box `[0, size]`, with y up, and flat footprints.
//!
//! Curved primitives are polyhedra inscribed in the smooth shape. A cylinder with `n` sides is the
//! prism over the inscribed regular `n`-gon, so its volume is `n·sin(2π/n)/(2π)` of the smooth one
//! (−0.16 % at 64 sides); a UV sphere of 32 segments × 16 rings has 1.6 % less volume than the
//! smooth sphere. [`cylinder_volume`] and [`sphere_volume`] give the exact volumes of these
//! polyhedra.

use std::f64::consts::{PI, TAU};

use crate::{DVec2, DVec3, Mesh, mesh::newell};

/// The box `[0, size]` as six quads.
pub fn cuboid(size: DVec3) -> Mesh {
    let corners: Vec<DVec3> = (0..8)
        .map(|i| {
            let bit = |b: usize| if i & b != 0 { 1.0 } else { 0.0 };
            size * DVec3::new(bit(1), bit(2), bit(4))
        })
        .collect();
    // Corner index = x + 2y + 4z; every loop is counter-clockwise seen from outside, and every
    // side face starts with its bottom edge, so its component frame has y up the wall.
    let faces: [[u32; 4]; 6] = [
        [0, 4, 6, 2], // x = 0 (left)
        [5, 1, 3, 7], // x = sx (right)
        [0, 1, 5, 4], // y = 0 (bottom)
        [2, 6, 7, 3], // y = sy (top)
        [1, 0, 2, 3], // z = 0 (back)
        [4, 5, 7, 6], // z = sz (front)
    ];
    Mesh::from_quads(corners, &faces)
}

/// A horizontal rectangle `[0, width] × [0, depth]` in the xz-plane, facing up (+y): a lot.
pub fn quad(width: f64, depth: f64) -> Mesh {
    footprint(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(width, 0.0),
        DVec2::new(width, depth),
        DVec2::new(0.0, depth),
    ])
    .expect("a rectangle is a valid footprint")
}

/// A horizontal polygon at y = 0 from `(x, z)` points in either winding, facing up (+y).
/// Returns `None` for fewer than three points or a polygon without area.
pub fn footprint(points: &[DVec2]) -> Option<Mesh> {
    if points.len() < 3 {
        return None;
    }
    let mut loop_: Vec<DVec3> = points.iter().map(|p| DVec3::new(p.x, 0.0, p.y)).collect();
    let normal = newell(loop_.iter().copied());
    if normal.y.abs() <= f64::EPSILON * normal.length().max(1.0) || !normal.is_finite() {
        return None;
    }
    if normal.y < 0.0 {
        loop_.reverse();
    }
    Some(Mesh::from_polygon(&loop_))
}

/// A point on the ellipse inscribed in the box's xz-rectangle at angle `a`, at height `y`.
fn ellipse_point(size: DVec3, a: f64, y: f64) -> DVec3 {
    // Counter-clockwise seen from above (+y) means increasing angle from +x towards −z.
    DVec3::new(
        size.x * 0.5 * (1.0 + a.cos()),
        y,
        size.z * 0.5 * (1.0 - a.sin()),
    )
}

/// An upright prism with `sides` faces around the ellipse inscribed in the box (a cylinder).
/// `sides` is raised to at least 3.
pub fn cylinder(size: DVec3, sides: u32) -> Mesh {
    let n = sides.max(3);
    let mut positions = Vec::with_capacity(2 * n as usize);
    for k in 0..n {
        let a = TAU * f64::from(k) / f64::from(n);
        positions.push(ellipse_point(size, a, 0.0));
        positions.push(ellipse_point(size, a, size.y));
    }
    let mut mesh = Mesh::from_faces(positions, std::iter::empty::<[u32; 0]>());
    let bottom: Vec<u32> = (0..n).rev().map(|k| 2 * k).collect();
    let top: Vec<u32> = (0..n).map(|k| 2 * k + 1).collect();
    mesh.add_face(&bottom);
    mesh.add_face(&top);
    for k in 0..n {
        let j = (k + 1) % n;
        mesh.add_face(&[2 * k, 2 * j, 2 * j + 1, 2 * k + 1]);
    }
    mesh
}

/// A flat disk: the polygon of `vertices` corners (at least 3) on the ellipse inscribed in the
/// box's face across axis `flat` (at 0 along it), facing along that axis. The first corner lies
/// at the high end of the first axis after `flat` in the order x, y, z that is not up the face
/// (x for a disk facing y or z, y for one facing x), the others follow counter-clockwise.
pub fn disk(size: DVec3, flat: usize, vertices: u32) -> Mesh {
    let n = vertices.max(3);
    // (u, v) with u × v along the flat axis.
    let (u, v, v_sign) = match flat {
        0 => (1, 2, 1.0),
        2 => (0, 1, 1.0),
        _ => (0, 2, -1.0),
    };
    let points: Vec<DVec3> = (0..n)
        .map(|k| {
            let a = TAU * f64::from(k) / f64::from(n);
            let mut p = DVec3::ZERO;
            p[u] = size[u] * 0.5 * (1.0 + a.cos());
            p[v] = size[v] * 0.5 * (1.0 + v_sign * a.sin());
            p
        })
        .collect();
    Mesh::from_polygon(&points)
}

/// An upright cone with `sides` faces around the ellipse inscribed in the box's base, apex at the
/// top centre. `sides` is raised to at least 3.
pub fn cone(size: DVec3, sides: u32) -> Mesh {
    let n = sides.max(3);
    let mut positions: Vec<DVec3> = (0..n)
        .map(|k| ellipse_point(size, TAU * f64::from(k) / f64::from(n), 0.0))
        .collect();
    positions.push(DVec3::new(size.x * 0.5, size.y, size.z * 0.5));
    let apex = n;
    let mut mesh = Mesh::from_faces(positions, [(0..n).rev().collect::<Vec<_>>()]);
    for k in 0..n {
        mesh.add_face(&[k, (k + 1) % n, apex]);
    }
    mesh
}

/// A pyramid over the box's full base rectangle with its apex at the top centre.
pub fn pyramid(size: DVec3) -> Mesh {
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(size.x, 0.0, 0.0),
        DVec3::new(size.x, 0.0, size.z),
        DVec3::new(0.0, 0.0, size.z),
        DVec3::new(size.x * 0.5, size.y, size.z * 0.5),
    ];
    let faces: [&[u32]; 5] = [
        &[0, 1, 2, 3],
        &[1, 0, 4],
        &[2, 1, 4],
        &[3, 2, 4],
        &[0, 3, 4],
    ];
    Mesh::from_faces(positions, faces)
}

/// A UV sphere (an ellipsoid when the size is not uniform) inscribed in the box, with `segments`
/// around and `rings` from pole to pole; triangles at the poles, quads elsewhere. The counts are
/// raised to at least 3 and 2.
pub fn sphere(size: DVec3, segments: u32, rings: u32) -> Mesh {
    let (s, r) = (segments.max(3), rings.max(2));
    let half = size * 0.5;
    let point = |ring: u32, seg: u32| {
        let polar = PI * f64::from(ring) / f64::from(r);
        let azimuth = TAU * f64::from(seg) / f64::from(s);
        half + half
            * DVec3::new(
                polar.sin() * azimuth.cos(),
                polar.cos(),
                -polar.sin() * azimuth.sin(),
            )
    };
    let mut positions = vec![point(0, 0)];
    for ring in 1..r {
        positions.extend((0..s).map(|seg| point(ring, seg)));
    }
    positions.push(point(r, 0));
    let south = (positions.len() - 1) as u32;
    let at = |ring: u32, seg: u32| 1 + (ring - 1) * s + seg % s;
    let mut mesh = Mesh::from_faces(positions, std::iter::empty::<[u32; 0]>());
    for seg in 0..s {
        mesh.add_face(&[0, at(1, seg), at(1, seg + 1)]);
        for ring in 1..r - 1 {
            mesh.add_face(&[
                at(ring, seg),
                at(ring + 1, seg),
                at(ring + 1, seg + 1),
                at(ring, seg + 1),
            ]);
        }
        mesh.add_face(&[at(r - 1, seg), south, at(r - 1, seg + 1)]);
    }
    mesh
}

/// Exact volume of [`cylinder`] with these arguments.
pub fn cylinder_volume(size: DVec3, sides: u32) -> f64 {
    let n = f64::from(sides.max(3));
    size.x * size.z * 0.25 * n * 0.5 * (TAU / n).sin() * size.y
}

/// Exact volume of [`sphere`] with these arguments: the sum of the frusta between rings.
pub fn sphere_volume(size: DVec3, segments: u32, rings: u32) -> f64 {
    let (s, r) = (f64::from(segments.max(3)), rings.max(2));
    // The polygon of a ring of radius ρ has area ρ²·s·sin(2π/s)/2; between two rings the solid is
    // a prismatoid, whose volume is h/6·(A₀ + 4·A_mid + A₁).
    let polygon_area = |rho: f64| rho * rho * s * 0.5 * (TAU / s).sin();
    let unit: f64 = (0..r)
        .map(|k| {
            let (p0, p1) = (
                PI * f64::from(k) / f64::from(r),
                PI * f64::from(k + 1) / f64::from(r),
            );
            let h = p0.cos() - p1.cos();
            let mid = 0.5 * (p0.sin() + p1.sin());
            h / 6.0 * (polygon_area(p0.sin()) + 4.0 * polygon_area(mid) + polygon_area(p1.sin()))
        })
        .sum();
    unit * size.x * size.y * size.z / 8.0
}
