//! Offsets of non-convex polygons and CGA's inside/border split: areas by formula, polygons that
//! fall apart or grow holes, other planes, invalid input, and property tests that the inside and
//! the border always tile the polygon.

use crate::common;

use common::{footprint_loop, l_footprint, polyomino, star_footprint, u_footprint};
use proptest::prelude::*;
use shapegram_geom::{
    DAffine3, DQuat, DVec3,
    mesh::newell,
    offset::{inset_border, offset_convex, offset_polygon},
};

const EPS: f64 = 1e-9;

fn assert_close(a: f64, b: f64, tolerance: f64) {
    assert!((a - b).abs() <= tolerance * b.abs().max(1.0), "{a} != {b}");
}

/// Signed area about +y: positive for loops counter-clockwise seen from above.
fn area_up(points: &[DVec3]) -> f64 {
    newell(points.iter().copied()).y * 0.5
}

fn total_area(loops: &[Vec<DVec3>]) -> f64 {
    loops.iter().map(|l| area_up(l)).sum()
}

/// Two 4×4 squares joined by a corridor 1 wide and 2 long.
fn dumbbell() -> Vec<DVec3> {
    footprint_loop(&[
        (0.0, 0.0),
        (4.0, 0.0),
        (4.0, 1.5),
        (6.0, 1.5),
        (6.0, 0.0),
        (10.0, 0.0),
        (10.0, 4.0),
        (6.0, 4.0),
        (6.0, 2.5),
        (4.0, 2.5),
        (4.0, 4.0),
        (0.0, 4.0),
    ])
}

#[test]
fn l_shape_insets_and_grows_by_the_mitre_formula() {
    // A rectilinear polygon offset by d (mitred) has area A + P·d + (convex − reflex corners)·d²:
    // for the L, 12 + 16d + 4d².
    let l = l_footprint();
    for d in [-0.75, -0.5, -0.25, 0.25, 0.5, 2.0] {
        let loops = offset_polygon(&l, d);
        assert_eq!(loops.len(), 1, "d = {d}");
        assert_eq!(loops[0].len(), 6);
        assert_close(area_up(&loops[0]), 12.0 + 16.0 * d + 4.0 * d * d, EPS);
    }
    let inset = &offset_polygon(&l, -0.5)[0];
    for corner in [
        (0.5, 0.5),
        (3.5, 0.5),
        (3.5, 1.5),
        (1.5, 1.5),
        (1.5, 3.5),
        (0.5, 3.5),
    ] {
        assert!(
            inset
                .iter()
                .any(|p| p.distance(DVec3::new(corner.0, 0.0, corner.1)) < EPS)
        );
    }
    // Arms 2 wide vanish at an inset of 1.
    assert!(offset_polygon(&l, -1.0).is_empty());
    assert!(offset_polygon(&l, -3.0).is_empty());
}

#[test]
fn convex_polygons_go_through_offset_convex() {
    let rectangle = footprint_loop(&[(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (0.0, 2.0)]);
    for d in [-0.5, 0.5] {
        let loops = offset_polygon(&rectangle, d);
        assert_eq!(loops, vec![offset_convex(&rectangle, d).unwrap()]);
        assert_close(area_up(&loops[0]), (4.0 + 2.0 * d) * (2.0 + 2.0 * d), EPS);
    }
    assert!(offset_polygon(&rectangle, -1.0).is_empty());
}

#[test]
fn an_inset_can_fall_apart_and_an_offset_can_close_a_notch() {
    // The corridor is gone at 0.5; at 0.75 two squares of side 2.5 are left.
    let parts = offset_polygon(&dumbbell(), -0.75);
    assert_eq!(parts.len(), 2);
    for part in &parts {
        assert_close(area_up(part), 6.25, EPS);
    }
    // The notch of the U is 2 wide: open at 0.5 (area 18 + 13 + 4·0.25 = 32), filled at 1.5
    // (the full 9 × 7 rectangle).
    let u = u_footprint();
    let open = offset_polygon(&u, 0.5);
    assert_eq!(open.len(), 1);
    assert_close(area_up(&open[0]), 32.0, EPS);
    let closed = offset_polygon(&u, 1.5);
    assert_eq!(closed.len(), 1);
    assert_close(area_up(&closed[0]), 63.0, EPS);
}

#[test]
fn a_bay_that_closes_off_becomes_a_hole() {
    // A 6 × 6 square ring (wall 1 thick) with a slot 0.4 wide through its right wall: growing by
    // 0.3 closes the slot at 0.2 and leaves the courtyard as a hole.
    let c = footprint_loop(&[
        (0.0, 0.0),
        (6.0, 0.0),
        (6.0, 2.8),
        (5.0, 2.8),
        (5.0, 1.0),
        (1.0, 1.0),
        (1.0, 5.0),
        (5.0, 5.0),
        (5.0, 3.2),
        (6.0, 3.2),
        (6.0, 6.0),
        (0.0, 6.0),
    ]);
    let loops = offset_polygon(&c, 0.3);
    assert_eq!(loops.len(), 2);
    let (outer, hole): (Vec<_>, Vec<_>) = loops.iter().partition(|l| area_up(l) > 0.0);
    assert_eq!((outer.len(), hole.len()), (1, 1));
    assert_close(area_up(outer[0]), 6.6 * 6.6, EPS);
    assert_close(area_up(hole[0]), -3.4 * 3.4, EPS);
    // Grown by 0.1 the slot is still open: one outline of area A + P·d + (convex − reflex)·d²,
    // with A = 19.6, P = 23.6 + 15.6 + 2 and 8 convex and 4 reflex corners.
    let open = offset_polygon(&c, 0.1);
    assert_eq!(open.len(), 1);
    assert_close(area_up(&open[0]), 19.6 + 41.2 * 0.1 + 4.0 * 0.01, EPS);
}

#[test]
fn inside_and_border_tile_the_l() {
    let l = l_footprint();
    let (inside, border) = inset_border(&l, -0.5);
    assert_eq!(inside.len(), 1);
    assert_close(area_up(&inside[0]), 5.0, EPS);
    // One trapezoid per edge, starting with that edge, counter-clockwise like the L.
    assert_eq!(border.len(), 6);
    for (i, quad) in border.iter().enumerate() {
        assert_eq!(quad.len(), 4, "border {i}");
        assert!(area_up(quad) > 0.0);
        assert!(quad[0].distance(l[i]) < EPS && quad[1].distance(l[(i + 1) % 6]) < EPS);
    }
    assert_close(total_area(&border), 7.0, EPS);
    // The border shares its inner corners with the inside.
    for p in &inside[0] {
        assert!(border.iter().flatten().any(|q| q.distance(*p) < EPS));
    }
}

#[test]
fn a_vanished_inset_leaves_only_border() {
    for d in [1.0, 1.5, 10.0] {
        let (inside, border) = inset_border(&l_footprint(), -d);
        assert!(inside.is_empty());
        assert_eq!(border.len(), 6);
        assert_close(total_area(&border), 12.0, EPS);
        // The arm ends shrink to triangles, the others to trapezoids.
        let mut sizes: Vec<usize> = border.iter().map(Vec::len).collect();
        sizes.sort_unstable();
        assert_eq!(sizes, vec![3, 3, 4, 4, 4, 4]);
    }
}

#[test]
fn growing_borders_lie_outside() {
    let l = l_footprint();
    let (inside, border) = inset_border(&l, 0.5);
    assert_eq!(inside, vec![l.clone()]);
    assert_eq!(border.len(), 6);
    assert_close(total_area(&border), 21.0 - 12.0, EPS);
    for (i, quad) in border.iter().enumerate() {
        assert!(area_up(quad) > 0.0);
        // Each border holds its edge.
        for corner in [l[i], l[(i + 1) % 6]] {
            assert!(quad.iter().any(|q| q.distance(corner) < EPS));
        }
    }
    let (inside, border) = inset_border(&l, 0.0);
    assert_eq!((inside, border.len()), (vec![l], 0));
}

#[test]
fn offsets_work_in_any_plane() {
    let turn = DAffine3::from_rotation_translation(
        DQuat::from_euler(glam::EulerRot::XYZ, 0.4, 1.1, -2.0),
        DVec3::new(10.0, -3.0, 7.0),
    );
    let l: Vec<DVec3> = l_footprint()
        .iter()
        .map(|&p| turn.transform_point3(p))
        .collect();
    let normal = turn.transform_vector3(DVec3::Y);
    let loops = offset_polygon(&l, -0.5);
    assert_eq!(loops.len(), 1);
    assert_close(
        newell(loops[0].iter().copied()).dot(normal) * 0.5,
        5.0,
        1e-8,
    );
    let (inside, border) = inset_border(&l, -0.5);
    for p in inside.iter().chain(&border).flatten() {
        assert!((*p - l[0]).dot(normal).abs() < 1e-9);
    }
    let area = |loops: &[Vec<DVec3>]| -> f64 {
        loops
            .iter()
            .map(|l| newell(l.iter().copied()).dot(normal) * 0.5)
            .sum()
    };
    assert_close(area(&inside) + area(&border), 12.0, 1e-8);
}

#[test]
fn invalid_input_gives_nothing() {
    let l = l_footprint();
    assert!(offset_polygon(&l, f64::NAN).is_empty());
    assert_eq!(inset_border(&l, f64::INFINITY), (Vec::new(), Vec::new()));
    let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
    let bow_tie = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 2.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 2.0),
    ];
    for bad in [&line[..], &bow_tie[..], &l[..2]] {
        assert!(offset_polygon(bad, -0.1).is_empty());
        assert_eq!(inset_border(bad, -0.1), (Vec::new(), Vec::new()));
    }
    // Zero distance: the polygon as it is, without repeated corners.
    let mut repeated = l.clone();
    repeated.insert(2, l[2]);
    assert_eq!(offset_polygon(&repeated, 0.0), vec![l]);
}

/// A random polyomino outline (see [`common::polyomino`]).
fn polyomino_footprint() -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec((0..64usize, 0..4u8), 1..24)
        .prop_filter_map("holes or corner contacts", |choices| polyomino(&choices))
}

/// Checks the inside/border split of one polygon at one distance.
fn check_tiling(footprint: &[DVec3], distance: f64) {
    let area = area_up(footprint);
    let (inside, border) = inset_border(footprint, distance);
    assert_eq!(border.len(), footprint.len());
    for piece in &border {
        assert!(area_up(piece) > 0.0, "border piece without area");
    }
    let size = shapegram_geom::Aabb::from_points(footprint.iter().copied())
        .unwrap()
        .diagonal();
    let tolerance = 1e-8 * size * size;
    if distance < 0.0 {
        for loop_ in &inside {
            assert!(area_up(loop_) > 0.0);
        }
        let inset = total_area(&inside);
        assert!((inset + total_area(&border) - area).abs() < tolerance);
        assert!(
            (total_area(&offset_polygon(footprint, distance)) - inset).abs() < tolerance,
            "offset_polygon and inset_border disagree"
        );
    } else {
        assert_eq!(inside, vec![footprint.to_vec()]);
        let grown = total_area(&offset_polygon(footprint, distance));
        assert!((area + total_area(&border) - grown).abs() < tolerance);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn inside_and_border_tile_polyominoes(
        footprint in polyomino_footprint(),
        distance in -3.0..2.0f64,
    ) {
        check_tiling(&footprint, distance);
    }

    #[test]
    fn inside_and_border_tile_star_shapes(
        footprint in star_footprint(),
        distance in -6.0..4.0f64,
    ) {
        check_tiling(&footprint, distance);
    }
}
