//! Triangulation of polygons with many corners on straight lines (stepped outlines, roof faces),
//! where ear clipping alone leaves zero-area slivers, needles and T-junctions: the triangles must
//! cover the polygon exactly, share whole edges, and each have area.

use crate::common;

use common::polyomino;
use proptest::prelude::*;
use shapegram_geom::{DAffine3, DQuat, DVec3, Mesh, mesh::newell};

/// Checks the triangulation of one polygon face: area, conformity, no degenerate triangle.
fn check(points: &[DVec3]) -> Result<(), TestCaseError> {
    let face = Mesh::from_polygon(points);
    let triangles = face.triangulate();
    let normal = newell(points.iter().copied());
    let area = normal.length() * 0.5;
    let size = face.bounds().unwrap().diagonal();
    let mut sum = 0.0;
    for t in &triangles {
        let [a, b, c] = t.map(|i| face.position(i));
        let twice = (b - a).cross(c - a);
        // Wound like the polygon, with area by the workspace's measure of degenerate.
        prop_assert!(twice.dot(normal) > 0.0);
        prop_assert!(
            twice.length() * 0.5 >= 1e-12 * size * size,
            "degenerate triangle"
        );
        sum += twice.length() * 0.5;
    }
    prop_assert!(
        (sum - area).abs() < 1e-9 * size * size,
        "area {} of {}",
        sum,
        area
    );
    // Inner edges pair up, and the open edges are exactly the polygon's edges.
    let soup = Mesh::from_faces(points.to_vec(), triangles.iter().map(|t| t.to_vec()));
    let mut open = soup.boundary_edges();
    open.sort_unstable();
    let n = points.len() as u32;
    let mut outline: Vec<(u32, u32)> = (0..n).map(|i| (i, (i + 1) % n)).collect();
    outline.sort_unstable();
    prop_assert_eq!(open, outline);
    Ok(())
}

/// Two columns of steps: the bottom edge and the tops hold many corners on straight lines.
#[test]
fn stepped_outline_in_a_turned_plane() {
    let outline = common::footprint_loop(&[
        (0.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (3.0, 2.0),
        (3.0, 1.0),
        (5.0, 1.0),
        (5.0, 3.0),
        (8.0, 3.0),
        (8.0, 1.0),
        (10.0, 1.0),
        (10.0, 0.0),
        (0.0, 0.0),
    ]);
    let turn = DAffine3::from_rotation_translation(
        DQuat::from_euler(glam::EulerRot::XYZ, 2.79, -0.27, 0.59),
        DVec3::new(3.0, -7.0, 11.0),
    );
    let turned: Vec<DVec3> = outline.iter().map(|&p| turn.transform_point3(p)).collect();
    check(&turned).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn polyomino_outlines_triangulate_cleanly(
        outline in prop::collection::vec((0..64usize, 0..4u8), 1..24)
            .prop_filter_map("holes or corner contacts", |choices| polyomino(&choices)),
        angles in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
    ) {
        let turn = DAffine3::from_rotation_translation(
            DQuat::from_euler(glam::EulerRot::XYZ, angles.0, angles.1, angles.2),
            DVec3::new(-20.0, 4.0, 9.0),
        );
        let turned: Vec<DVec3> = outline.iter().map(|&p| turn.transform_point3(p)).collect();
        check(&turned)?;
    }
}

#[test]
fn a_self_intersecting_spiral_ends() {
    // The zig-zag leaf of an L-system (16 × `.f+(30).f-(60)`): it crosses itself and runs
    // through its own corners, which once kept the repair of earcut's triangles splitting forever.
    let mut points = Vec::new();
    let (mut at, mut heading) = (DVec3::ZERO, 90f64);
    for _ in 0..16 {
        for turn in [30.0, -60.0] {
            points.push(at);
            let (sin, cos) = heading.to_radians().sin_cos();
            at += DVec3::new(cos, sin, 0.0);
            heading += turn;
        }
    }
    let triangles = Mesh::from_polygon(&points).triangulate();
    // Earcut's n - 2 triangles and at most 16 n + 64 repair splits.
    assert!(triangles.len() >= points.len() - 2);
    assert!(
        triangles.len() <= 17 * points.len() + 62,
        "{}",
        triangles.len()
    );
    assert!(
        triangles
            .iter()
            .flatten()
            .all(|&i| (i as usize) < points.len())
    );
}
