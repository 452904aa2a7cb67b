//! Triangulation of polygons with many corners on straight lines (stepped outlines, roof faces),
//! where ear clipping alone leaves zero-area slivers, needles and T-junctions: the triangles must
//! cover the polygon exactly, share whole edges, and each have area.

mod common;

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
    let flat: [(f64, f64); 32] = [
        (0.0, 0.0),
        (6.123233995736766e-17, 1.0),
        (-0.49999999999999972, 1.8660254037844388),
        (3.8857805861880479e-16, 2.7320508075688776),
        (4.4981039857617246e-16, 3.7320508075688776),
        (0.86602540378443915, 4.2320508075688776),
        (1.3660254037844393, 5.098076211353316),
        (2.3660254037844393, 5.098076211353316),
        (3.2320508075688781, 5.598076211353316),
        (4.0980762113533169, 5.098076211353316),
        (5.0980762113533169, 5.098076211353316),
        (5.5980762113533169, 4.2320508075688776),
        (6.4641016151377553, 3.7320508075688776),
        (6.4641016151377553, 2.7320508075688776),
        (6.9641016151377553, 1.866025403784439),
        (6.4641016151377553, 1.0000000000000004),
        (6.4641016151377553, 4.4408920985006262e-16),
        (5.5980762113533169, -0.4999999999999995),
        (5.0980762113533169, -1.3660254037844382),
        (4.0980762113533169, -1.3660254037844384),
        (3.2320508075688781, -1.8660254037844384),
        (2.3660254037844393, -1.3660254037844384),
        (1.3660254037844393, -1.3660254037844386),
        (0.86602540378443882, -0.50000000000000022),
        (2.2204460492503131e-16, -1.1102230246251565e-16),
        (3.8347585052928339e-17, 0.99999999999999989),
        (-0.50000000000000044, 1.8660254037844384),
        (-3.3306690738754696e-16, 2.7320508075688767),
        (-5.1676392725964988e-16, 3.7320508075688767),
        (0.86602540378443782, 4.2320508075688767),
        (1.3660254037844379, 5.0980762113533151),
        (2.3660254037844379, 5.0980762113533151),
    ];
    let points: Vec<DVec3> = flat.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect();
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
