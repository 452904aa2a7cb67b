//! Shapes shared by the kernel's test files (each file uses some of them).
#![allow(dead_code)]

use shapegram_geom::{DVec2, DVec3, Mesh, extrude::extrude_polygon, primitives};

/// An L-shaped footprint extruded to a non-convex prism: the 4×4 square at the origin minus
/// `[2,4]×[2,4]` (in x and z), height 3. Volume 12 · 3 = 36.
pub fn l_prism() -> Mesh {
    let l = [
        (0.0, 0.0),
        (4.0, 0.0),
        (4.0, 2.0),
        (2.0, 2.0),
        (2.0, 4.0),
        (0.0, 4.0),
    ];
    let footprint = primitives::footprint(&l.map(|(x, z)| DVec2::new(x, z))).unwrap();
    let points: Vec<DVec3> = footprint.face_points(0).collect();
    extrude_polygon(&points, 3.0).unwrap()
}

/// A U-shaped prism, open towards +z: the 6×4 rectangle minus `[2,4]×[1,4]`, height 2.
/// Volume (24 − 6) · 2 = 36.
pub fn u_prism() -> Mesh {
    let u = [
        (0.0, 0.0),
        (6.0, 0.0),
        (6.0, 4.0),
        (4.0, 4.0),
        (4.0, 1.0),
        (2.0, 1.0),
        (2.0, 4.0),
        (0.0, 4.0),
    ];
    prism(&u, 2.0)
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
    let points: Vec<DVec2> = outline.iter().map(|&(x, z)| DVec2::new(x, z)).collect();
    let footprint = primitives::footprint(&points).unwrap();
    let loop_: Vec<DVec3> = footprint.face_points(0).collect();
    extrude_polygon(&loop_, height).unwrap()
}
