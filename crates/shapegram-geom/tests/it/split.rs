//! Plane cuts on hand-picked cases: through vertices, edges and faces, non-convex faces, caps with
//! holes, several planes at once.

use crate::common;

use shapegram_geom::{
    DVec3, Mesh, Plane,
    primitives::{cuboid, cylinder},
    split::{slice_faces, split, split_polygon, split_slabs},
};

/// Area of the faces lying in `plane` whose normal is `plane.normal` (the cap of the part below).
fn cap_area(mesh: &Mesh, plane: &Plane, facing: DVec3) -> f64 {
    (0..mesh.face_count())
        .filter(|&f| {
            mesh.face_points(f)
                .all(|p| plane.signed_distance(p).abs() < 1e-9)
                && mesh.face_normal(f).abs_diff_eq(facing, 1e-9)
        })
        .map(|f| mesh.face_area(f))
        .sum()
}

fn assert_parts(mesh: &Mesh, plane: Plane, below_volume: f64, above_volume: f64) -> (Mesh, Mesh) {
    let (below, above) = split(mesh, &plane);
    for (part, volume) in [(&below, below_volume), (&above, above_volume)] {
        assert!(
            (part.signed_volume() - volume).abs() < 1e-9,
            "{} != {volume}",
            part.signed_volume()
        );
        if volume > 0.0 {
            let report = part.edge_report();
            assert!(report.is_watertight(), "{report:?}");
        } else {
            assert!(part.is_empty());
        }
    }
    (below, above)
}

#[test]
fn box_cut_in_half_gets_two_caps() {
    let b = cuboid(DVec3::new(2.0, 3.0, 4.0));
    let plane = Plane {
        normal: DVec3::Y,
        offset: 1.5,
    };
    let (below, above) = assert_parts(&b, plane, 12.0, 12.0);
    assert_eq!((below.face_count(), above.face_count()), (6, 6));
    assert_eq!((below.vertex_count(), above.vertex_count()), (8, 8));
    assert_eq!(cap_area(&below, &plane, DVec3::Y), 8.0);
    assert_eq!(cap_area(&above, &plane, -DVec3::Y), 8.0);
    assert_eq!(below.bounds().unwrap().max, DVec3::new(2.0, 1.5, 4.0));
}

#[test]
fn cut_through_three_corners_reuses_them() {
    let cube = cuboid(DVec3::ONE);
    let plane = Plane::from_point_normal(DVec3::X, DVec3::ONE);
    let (tip, rest) = assert_parts(&cube, plane, 1.0 / 6.0, 5.0 / 6.0);
    assert_eq!((tip.vertex_count(), tip.face_count()), (4, 4));
    assert_eq!((rest.vertex_count(), rest.face_count()), (7, 7));
}

#[test]
fn cut_along_a_diagonal_through_two_edges() {
    let cube = cuboid(DVec3::ONE);
    let plane = Plane::from_point_normal(DVec3::ZERO, DVec3::new(1.0, 0.0, -1.0));
    let (a, b) = assert_parts(&cube, plane, 0.5, 0.5);
    assert_eq!((a.face_count(), b.face_count()), (5, 5));
    assert_eq!((a.vertex_count(), b.vertex_count()), (6, 6));
}

#[test]
fn planes_on_faces_or_outside_leave_the_solid_whole() {
    let b = cuboid(DVec3::new(2.0, 3.0, 4.0));
    for (offset, below) in [(0.0, 0.0), (3.0, 24.0), (-1.0, 0.0), (7.0, 24.0)] {
        let plane = Plane {
            normal: DVec3::Y,
            offset,
        };
        let (lo, hi) = assert_parts(&b, plane, below, 24.0 - below);
        assert_eq!(lo.face_count() + hi.face_count(), 6, "no caps at {offset}");
    }
}

#[test]
fn cut_across_both_arms_of_a_u_gives_two_closed_pieces_in_one_part() {
    let u = common::u_prism();
    let plane = Plane {
        normal: DVec3::Z,
        offset: 2.5,
    };
    let (_, arms) = assert_parts(&u, plane, 24.0, 12.0);
    assert_eq!(arms.face_count(), 12);
    assert_eq!(cap_area(&arms, &plane, -DVec3::Z), 8.0);
    // The bottom of the U is one face crossed twice; its part above the cut is two faces.
    let bottoms = (0..arms.face_count())
        .filter(|&f| arms.face_normal(f) == -DVec3::Y)
        .count();
    assert_eq!(bottoms, 2);
}

#[test]
fn cut_through_a_tube_gives_ring_caps() {
    let tube = common::tube();
    let plane = Plane {
        normal: DVec3::Y,
        offset: 1.5,
    };
    let (below, above) = assert_parts(&tube, plane, 18.0, 18.0);
    assert!((cap_area(&below, &plane, DVec3::Y) - 12.0).abs() < 1e-12);
    assert!((cap_area(&above, &plane, -DVec3::Y) - 12.0).abs() < 1e-12);
    assert!((below.area() + above.area() - tube.area() - 24.0).abs() < 1e-9);
}

#[test]
fn reflex_corner_on_the_plane_splits_an_l_cleanly() {
    // The plane x = 2 passes through the L's reflex edge: the top and bottom faces touch the cut
    // line at their reflex corner.
    let l = common::l_prism();
    let plane = Plane {
        normal: DVec3::X,
        offset: 2.0,
    };
    let (left, right) = assert_parts(&l, plane, 24.0, 12.0);
    // The left part keeps the L's own face on the plane beside the new cap: 7 faces.
    assert_eq!((left.face_count(), right.face_count()), (7, 6));
    assert_eq!(cap_area(&left, &plane, DVec3::X), 12.0);
}

#[test]
fn comb_polygon_splits_into_one_piece_per_tooth() {
    // A comb with three teeth pointing up (+y) in the xy-plane, counter-clockwise about +z.
    let comb: Vec<DVec3> = [
        (0.0, 0.0),
        (5.0, 0.0),
        (5.0, 3.0),
        (4.0, 3.0),
        (4.0, 1.0),
        (3.0, 1.0),
        (3.0, 3.0),
        (2.0, 3.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 3.0),
        (0.0, 3.0),
    ]
    .iter()
    .map(|&(x, y)| DVec3::new(x, y, 0.0))
    .collect();
    let plane = Plane {
        normal: DVec3::Y,
        offset: 2.0,
    };
    let (below, above) = split_polygon(&comb, &plane);
    assert_eq!((below.len(), above.len()), (1, 3));
    let area = |loops: &[Vec<DVec3>]| {
        loops
            .iter()
            .map(|l| Mesh::from_polygon(l).area())
            .sum::<f64>()
    };
    assert!((area(&below) - 8.0).abs() < 1e-12);
    assert!((area(&above) - 3.0).abs() < 1e-12);
    for piece in below.iter().chain(&above) {
        assert!(
            Mesh::from_polygon(piece)
                .face_normal(0)
                .abs_diff_eq(DVec3::Z, 1e-12)
        );
    }
    // Along the cut at the teeth's base, the pieces below and above meet at the reflex corners.
    let (below, above) = split_polygon(
        &comb,
        &Plane {
            normal: DVec3::Y,
            offset: 1.0,
        },
    );
    assert_eq!((below.len(), above.len()), (1, 3));
    assert!((area(&below) - 5.0).abs() < 1e-12);
}

#[test]
fn slabs_of_a_prism_share_the_volume() {
    let prism = cylinder(DVec3::new(4.0, 10.0, 4.0), 40);
    let offsets: Vec<f64> = (1..10).map(f64::from).collect();
    let slabs = split_slabs(&prism, DVec3::Y, &offsets);
    assert_eq!(slabs.len(), 10);
    let total = prism.signed_volume();
    for slab in &slabs {
        assert!(slab.is_watertight());
        assert!((slab.signed_volume() - total / 10.0).abs() < 1e-9);
        assert_eq!(slab.face_count(), 42);
    }
}

#[test]
fn slabs_accept_unsorted_duplicate_and_outside_offsets() {
    let b = cuboid(DVec3::new(1.0, 4.0, 1.0));
    let slabs = split_slabs(&b, DVec3::Y * 2.0, &[6.0, 2.0, 2.0, -4.0]);
    // A non-unit normal scales the offsets: planes at y = −2, 1, 1, 3.
    let volumes: Vec<f64> = slabs.iter().map(Mesh::signed_volume).collect();
    assert_eq!(volumes, [0.0, 1.0, 0.0, 2.0, 1.0]);
    assert!(
        split_slabs(&Mesh::new(), DVec3::Y, &[1.0])
            .iter()
            .all(Mesh::is_empty)
    );
}

#[test]
fn open_meshes_are_not_capped() {
    let b = cuboid(DVec3::ONE);
    let open = Mesh::from_faces(b.positions().to_vec(), b.faces().skip(1));
    let (below, above) = split(
        &open,
        &Plane {
            normal: DVec3::Y,
            offset: 0.5,
        },
    );
    // Three of the five faces cross the plane.
    assert_eq!(below.face_count() + above.face_count(), 5 + 3);
    assert!((below.area() + above.area() - 5.0).abs() < 1e-12);
}

#[test]
fn cuts_are_deterministic() {
    let tube = common::tube();
    let plane = Plane::from_point_normal(DVec3::new(0.1, 1.2, 0.3), DVec3::new(0.3, 1.0, -0.2));
    assert_eq!(split(&tube, &plane), split(&tube, &plane));
}

#[test]
fn degenerate_planes_cut_nothing() {
    let b = cuboid(DVec3::ONE);
    for normal in [DVec3::ZERO, DVec3::NAN, DVec3::INFINITY] {
        let slabs = split_slabs(&b, normal, &[0.5]);
        assert_eq!(slabs[0], b);
        assert!(slabs[1].is_empty());
    }
    let slabs = split_slabs(&b, DVec3::Y, &[f64::NAN, 0.5, f64::NEG_INFINITY]);
    let volumes: Vec<f64> = slabs.iter().map(Mesh::signed_volume).collect();
    assert_eq!(volumes, [0.0, 0.5, 0.5, 0.0]);
}

#[test]
fn slicing_keeps_one_closed_surface() {
    let b = cuboid(DVec3::new(2.0, 3.0, 4.0));
    let (sliced, sources) = slice_faces(&b, DVec3::Y, &[1.0, 2.0]);
    // The four walls in three pieces each, the ends whole; nothing capped, vertices shared.
    assert_eq!(sliced.face_count(), 4 * 3 + 2);
    assert_eq!(sliced.vertex_count(), 8 + 2 * 4);
    assert_eq!(&sliced.positions()[..8], b.positions());
    assert!(sliced.is_watertight());
    assert!((sliced.signed_volume() - 24.0).abs() < 1e-12);
    assert!((sliced.area() - b.area()).abs() < 1e-12);
    assert_eq!(sources.len(), sliced.face_count());
    for f in 0..b.face_count() {
        let pieces: f64 = (0..sliced.face_count())
            .filter(|&g| sources[g] as usize == f)
            .map(|g| sliced.face_area(g))
            .sum();
        assert!((pieces - b.face_area(f)).abs() < 1e-12);
    }
    // Planes outside the mesh or degenerate cut nothing.
    let (same, sources) = slice_faces(&b, DVec3::Y, &[-1.0, 3.0, 7.0]);
    assert_eq!(same, b);
    assert_eq!(sources, [0, 1, 2, 3, 4, 5]);
    assert_eq!(slice_faces(&b, DVec3::ZERO, &[1.0]).0, b);
    // Planes closer than the tolerance cut as one.
    let (once, _) = slice_faces(&b, DVec3::Y, &[1.0, 1.0 + 1e-9]);
    assert_eq!(once.face_count(), 4 * 2 + 2);
    assert!(once.is_watertight());
}

#[test]
fn slicing_a_tube_and_an_l_through_their_corners() {
    for mesh in [common::tube(), common::l_prism()] {
        let (sliced, _) = slice_faces(&mesh, DVec3::new(1.0, 0.5, 0.0), &[0.0, 1.0, 2.0]);
        assert!(sliced.is_watertight());
        assert!((sliced.signed_volume() - 36.0).abs() < 1e-9);
        assert!((sliced.area() - mesh.area()).abs() < 1e-9);
    }
}

#[test]
fn pieces_of_a_face_keep_its_first_edge() {
    // A 4 × 4 wall whose first edge runs along its foot, cut into three strips: every strip
    // starts with its own foot, running the same way, so its first edge (a component's x axis)
    // stays horizontal; the bottom strip from the wall's first corner.
    let wall = Mesh::from_faces(
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(4.0, 4.0, 0.0),
            DVec3::new(0.0, 4.0, 0.0),
        ],
        [vec![0, 1, 2, 3]],
    );
    let strips = split_slabs(&wall, DVec3::Y, &[1.0, 2.0]);
    assert_eq!(strips.len(), 3);
    for (k, (strip, (y, top))) in strips
        .iter()
        .zip([(0.0, 1.0), (1.0, 2.0), (2.0, 4.0)])
        .enumerate()
    {
        let corners: Vec<DVec3> = strip.face_points(0).collect();
        assert_eq!(
            corners,
            [
                DVec3::new(0.0, y, 0.0),
                DVec3::new(4.0, y, 0.0),
                DVec3::new(4.0, top, 0.0),
                DVec3::new(0.0, top, 0.0),
            ],
            "strip {k}"
        );
    }
}
