//! Shapes shared by the kernel's test files (each file uses some of them).
#![allow(dead_code)]

use proptest::prelude::*;
use shapegram_geom::{DVec2, DVec3, Mesh, extrude::extrude_polygon, primitives};

/// An L-shaped footprint extruded to a non-convex prism: the 4×4 square at the origin minus
/// `[2,4]×[2,4]` (in x and z), height 3. Volume 12 · 3 = 36.
pub fn l_prism() -> Mesh {
    prism(&L_OUTLINE, 3.0)
}

/// The 4 × 4 square minus `[2,4] × [2,4]`, as `(x, z)` corners: area 12.
const L_OUTLINE: [(f64, f64); 6] = [
    (0.0, 0.0),
    (4.0, 0.0),
    (4.0, 2.0),
    (2.0, 2.0),
    (2.0, 4.0),
    (0.0, 4.0),
];

/// A U-shaped prism, open towards +z: the 6×4 rectangle minus `[2,4]×[1,4]`, height 2.
/// Volume (24 − 6) · 2 = 36.
pub fn u_prism() -> Mesh {
    prism(&U_OUTLINE, 2.0)
}

/// The 6 × 4 rectangle minus the notch `[2,4] × [1,4]`, open towards +z, as `(x, z)` corners:
/// area 18, perimeter 26.
const U_OUTLINE: [(f64, f64); 8] = [
    (0.0, 0.0),
    (6.0, 0.0),
    (6.0, 4.0),
    (4.0, 4.0),
    (4.0, 1.0),
    (2.0, 1.0),
    (2.0, 4.0),
    (0.0, 4.0),
];

/// The U outline as a footprint loop facing up.
pub fn u_footprint() -> Vec<DVec3> {
    footprint_loop(&U_OUTLINE)
}

/// A square tube along y: outer 4×4, inner hole 2×2, height 3, with the top and bottom rings made
/// of four trapezoids each. Volume (16 − 4) · 3 = 36.
pub fn tube() -> Mesh {
    let ring = |r: f64| {
        [(-r, -r), (r, -r), (r, r), (-r, r)]
            .map(|(x, z)| [DVec3::new(x, 0.0, z), DVec3::new(x, 3.0, z)])
    };
    let (outer, inner) = (ring(2.0), ring(1.0));
    let positions: Vec<DVec3> = outer.iter().chain(&inner).flatten().copied().collect();
    // Vertex ids: outer corner k bottom 2k, top 2k+1; inner corner k bottom 8+2k, top 9+2k.
    let (ob, ot, ib, it) = (
        |k: u32| 2 * k,
        |k: u32| 2 * k + 1,
        |k: u32| 8 + 2 * k,
        |k: u32| 9 + 2 * k,
    );
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for k in 0..4 {
        let j = (k + 1) % 4;
        // The corner order (−,−), (+,−), (+,+), (−,+) runs clockwise seen from above (+y).
        faces.push(vec![ob(k), ot(k), ot(j), ob(j)]); // outer wall, facing out
        faces.push(vec![ib(k), ib(j), it(j), it(k)]); // inner wall, facing the hole
        faces.push(vec![ot(k), it(k), it(j), ot(j)]); // top trapezoid
        faces.push(vec![ob(k), ob(j), ib(j), ib(k)]); // bottom trapezoid
    }
    Mesh::from_faces(positions, faces)
}

/// The footprint of `(x, z)` points extruded up by `height`.
fn prism(outline: &[(f64, f64)], height: f64) -> Mesh {
    extrude_polygon(&footprint_loop(outline), height).unwrap()
}

/// A horizontal polygon at y = 0 from `(x, z)` points in either winding, counter-clockwise about
/// +y (facing up), as footprints are.
pub fn footprint_loop(outline: &[(f64, f64)]) -> Vec<DVec3> {
    let points: Vec<DVec2> = outline.iter().map(|&(x, z)| DVec2::new(x, z)).collect();
    primitives::footprint(&points)
        .unwrap()
        .face_points(0)
        .collect()
}

/// The L of [`l_prism`] as a footprint loop: the 4×4 square minus `[2,4]×[2,4]`, area 12.
pub fn l_footprint() -> Vec<DVec3> {
    footprint_loop(&L_OUTLINE)
}

/// Area of a planar polygon.
pub fn polygon_area(points: &[DVec3]) -> f64 {
    shapegram_geom::mesh::newell(points.iter().copied()).length() * 0.5
}

/// The outline of a polyomino grown from cell (0, 0) by adding, in turn, the neighbour of an
/// existing cell picked by each `(cell, side)` choice, as a footprint (unit cells in x and z).
/// `None` when the cells enclose a hole or touch only at a corner somewhere (the outline would not
/// be a simple polygon).
pub fn polyomino(choices: &[(usize, u8)]) -> Option<Vec<DVec3>> {
    use std::collections::{BTreeMap, BTreeSet};
    let mut cells: Vec<(i32, i32)> = vec![(0, 0)];
    for &(pick, side) in choices {
        let (x, z) = cells[pick % cells.len()];
        let next = match side % 4 {
            0 => (x + 1, z),
            1 => (x - 1, z),
            2 => (x, z + 1),
            _ => (x, z - 1),
        };
        if !cells.contains(&next) {
            cells.push(next);
        }
    }
    let set: BTreeSet<(i32, i32)> = cells.iter().copied().collect();
    // Holes: empty cells inside the bounding box not reachable from outside it.
    let (x0, x1) = (
        set.iter().map(|c| c.0).min()? - 1,
        set.iter().map(|c| c.0).max()? + 1,
    );
    let (z0, z1) = (
        set.iter().map(|c| c.1).min()? - 1,
        set.iter().map(|c| c.1).max()? + 1,
    );
    let mut outside = BTreeSet::from([(x0, z0)]);
    let mut stack = vec![(x0, z0)];
    while let Some((x, z)) = stack.pop() {
        for n in [(x + 1, z), (x - 1, z), (x, z + 1), (x, z - 1)] {
            if n.0 >= x0
                && n.0 <= x1
                && n.1 >= z0
                && n.1 <= z1
                && !set.contains(&n)
                && outside.insert(n)
            {
                stack.push(n);
            }
        }
    }
    let area = ((x1 - x0 + 1) * (z1 - z0 + 1)) as usize;
    if outside.len() + set.len() != area {
        return None;
    }
    // Boundary edges of the cells, counter-clockwise in (x, z), where no neighbour cell is.
    let mut next: BTreeMap<(i32, i32), (i32, i32)> = BTreeMap::new();
    for &(x, z) in &set {
        let sides = [
            ((x, z), (x + 1, z), (x, z - 1)),
            ((x + 1, z), (x + 1, z + 1), (x + 1, z)),
            ((x + 1, z + 1), (x, z + 1), (x, z + 1)),
            ((x, z + 1), (x, z), (x - 1, z)),
        ];
        for (a, b, neighbour) in sides {
            if !set.contains(&neighbour) && next.insert(a, b).is_some() {
                return None; // two outline edges leave one corner: cells touch at a corner
            }
        }
    }
    let start = *next.keys().next()?;
    let mut outline = vec![start];
    let mut at = next[&start];
    while at != start {
        outline.push(at);
        at = next[&at];
    }
    if outline.len() != next.len() {
        return None;
    }
    let points: Vec<(f64, f64)> = outline
        .iter()
        .map(|&(x, z)| (f64::from(x), f64::from(z)))
        .collect();
    Some(footprint_loop(&points))
}

/// A star-shaped polygon: corners at sorted angles with random radii (usually not convex).
pub fn star_footprint() -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec((0.0..1.0f64, 1.0..10.0f64), 3..14).prop_filter_map(
        "corners too close",
        |mut corners| {
            corners.sort_by(|a, b| a.0.total_cmp(&b.0));
            corners.dedup_by(|a, b| (a.0 - b.0).abs() < 0.02);
            // Every angular gap under half a turn keeps the centre inside: star-shaped about it.
            let gaps = corners.windows(2).map(|w| w[1].0 - w[0].0).chain(
                corners
                    .first()
                    .zip(corners.last())
                    .map(|(f, l)| f.0 + 1.0 - l.0),
            );
            if gaps.fold(0.0, f64::max) >= 0.45 {
                return None;
            }
            let points: Vec<DVec3> = corners
                .iter()
                .map(|&(a, r)| {
                    let a = a * std::f64::consts::TAU;
                    DVec3::new(r * a.cos(), 0.0, -r * a.sin())
                })
                .collect();
            (points.len() >= 3 && polygon_area(&points) > 1.0).then_some(points)
        },
    )
}
