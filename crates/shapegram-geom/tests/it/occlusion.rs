//! Occlusion tests of the kernel: inside / overlaps / touches of boxes, rectangles and
//! non-convex solids, convex decomposition, and the bounding-volume hierarchy.

use crate::common;

use shapegram_geom::occlusion::{Contact, ConvexSolid, Probe, contact, convex_pieces};
use shapegram_geom::{Aabb, Bvh, DMat3, DVec3, Scope};

const EPS: f64 = 1e-6;

fn cube(min: [f64; 3], max: [f64; 3]) -> Scope {
    let min = DVec3::from(min);
    Scope::axis_aligned(min, DVec3::from(max) - min)
}

fn solid(min: [f64; 3], max: [f64; 3]) -> Vec<ConvexSolid> {
    vec![ConvexSolid::from_scope(&cube(min, max)).unwrap()]
}

fn probe(min: [f64; 3], max: [f64; 3]) -> Probe {
    Probe::from_scope(&cube(min, max)).unwrap()
}

const NONE: Contact = Contact {
    inside: false,
    overlaps: false,
    touches: false,
};
const TOUCHES: Contact = Contact {
    inside: false,
    overlaps: false,
    touches: true,
};
const OVERLAPS: Contact = Contact {
    inside: false,
    overlaps: true,
    touches: true,
};
const INSIDE: Contact = Contact {
    inside: true,
    overlaps: true,
    touches: true,
};
const ON_SURFACE: Contact = Contact {
    inside: true,
    overlaps: false,
    touches: true,
};

#[test]
fn boxes_against_boxes() {
    let unit = probe([0.0; 3], [1.0; 3]);
    let cases = [
        (solid([-1.0; 3], [2.0; 3]), INSIDE, "inside a larger box"),
        (solid([0.0; 3], [1.0; 3]), INSIDE, "the same box"),
        (solid([0.5, 0.0, 0.0], [1.5, 1.0, 1.0]), OVERLAPS, "half in"),
        (solid([0.25; 3], [0.75; 3]), OVERLAPS, "holds a smaller box"),
        (
            solid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
            TOUCHES,
            "face to face",
        ),
        (
            solid([1.0, 0.5, 0.5], [2.0, 3.0, 3.0]),
            TOUCHES,
            "part of a face",
        ),
        (
            solid([1.0, 1.0, 0.0], [2.0, 2.0, 1.0]),
            NONE,
            "edge to edge",
        ),
        (solid([1.0; 3], [2.0; 3]), NONE, "corner to corner"),
        (solid([3.0; 3], [4.0; 3]), NONE, "apart"),
        (
            solid([1.0 + 1e-3, 0.0, 0.0], [2.0, 1.0, 1.0]),
            NONE,
            "a millimetre apart",
        ),
    ];
    for (occluder, expected, what) in cases {
        assert_eq!(contact(&unit, &occluder, EPS), expected, "{what}");
    }
}

#[test]
fn rectangles_against_boxes() {
    let wall = solid([0.0, 0.0, -1.0], [2.0, 2.0, 0.0]);
    // A facade rectangle facing +z at z = 0, flat along z.
    let facade = |x0: f64, x1: f64, z: f64| {
        Probe::from_scope(&Scope::axis_aligned(
            DVec3::new(x0, 0.0, z),
            DVec3::new(x1 - x0, 1.0, 0.0),
        ))
        .unwrap()
    };
    assert_eq!(contact(&facade(0.0, 1.0, 0.0), &wall, EPS), ON_SURFACE);
    assert_eq!(contact(&facade(0.0, 1.0, -0.5), &wall, EPS), INSIDE);
    assert_eq!(contact(&facade(1.0, 3.0, 0.0), &wall, EPS), TOUCHES);
    assert_eq!(contact(&facade(1.0, 3.0, -0.5), &wall, EPS), OVERLAPS);
    assert_eq!(contact(&facade(2.0, 3.0, -0.5), &wall, EPS), NONE);
    assert_eq!(contact(&facade(0.0, 1.0, 0.1), &wall, EPS), NONE);
    // A side wall meeting the box along an edge only.
    let side = Probe::from_scope(&Scope::new(
        DVec3::new(2.0, 0.0, 0.0),
        DMat3::from_cols(DVec3::Z, DVec3::Y, -DVec3::X),
        DVec3::new(1.0, 1.0, 0.0),
    ))
    .unwrap();
    assert_eq!(contact(&side, &wall, EPS), NONE);
    // A line has no area to occlude.
    assert!(Probe::from_scope(&Scope::axis_aligned(DVec3::ZERO, DVec3::X)).is_none());
}

#[test]
fn non_convex_solids_are_cut_into_convex_pieces() {
    let l = common::l_prism();
    let pieces = convex_pieces(&l, 16).unwrap();
    assert_eq!(pieces.len(), 2);
    let volume: f64 = pieces.iter().map(ConvexSolid::volume).sum();
    assert!((volume - 36.0).abs() < 1e-9, "{volume}");
    let u = convex_pieces(&common::u_prism(), 16).unwrap();
    let volume: f64 = u.iter().map(ConvexSolid::volume).sum();
    assert!((volume - 36.0).abs() < 1e-9, "{volume}");
    assert!(u.len() >= 3);
    // Too many pieces for the budget, and open meshes, are not solids.
    assert!(convex_pieces(&common::u_prism(), 2).is_none());
    let mut open = common::l_prism();
    open = shapegram_geom::Mesh::from_faces(
        open.positions().to_vec(),
        open.faces()
            .skip(1)
            .map(<[u32]>::to_vec)
            .collect::<Vec<_>>(),
    );
    assert!(convex_pieces(&open, 16).is_none());
}

#[test]
fn probes_against_an_l_shaped_solid() {
    // The L covers [0,4]×[0,2] ∪ [0,2]×[2,4] in x and z, from y = 0 to 3.
    let l = convex_pieces(&common::l_prism(), 16).unwrap();
    let slab = |x0: f64, x1: f64, z0: f64, z1: f64| {
        Probe::from_scope(&Scope::axis_aligned(
            DVec3::new(x0, 1.5, z0),
            DVec3::new(x1 - x0, 0.0, z1 - z0),
        ))
        .unwrap()
    };
    // Across both pieces of the L, wholly inside it.
    assert_eq!(contact(&slab(0.5, 3.5, 0.5, 1.5), &l, EPS), INSIDE);
    // Reaching into the notch.
    assert_eq!(contact(&slab(0.5, 3.5, 1.5, 2.5), &l, EPS), OVERLAPS);
    // In the notch.
    assert_eq!(
        contact(&probe([2.5, 0.0, 2.5], [3.5, 1.0, 3.5]), &l, EPS),
        NONE
    );
    assert_eq!(
        contact(&probe([0.5, 0.5, 2.5], [1.5, 1.0, 3.5]), &l, EPS),
        INSIDE
    );
    // Against the notch's walls from inside the notch.
    assert_eq!(
        contact(&probe([2.0, 0.0, 2.0], [3.0, 1.0, 3.0]), &l, EPS),
        TOUCHES
    );
    // A closed mesh probe: the L itself inside a big box, and the L against a box in its notch.
    let l_probe = Probe::from_mesh(&common::l_prism(), 16).unwrap();
    assert_eq!(contact(&l_probe, &solid([-1.0; 3], [5.0; 3]), EPS), INSIDE);
    assert_eq!(
        contact(&l_probe, &solid([2.0, 0.0, 2.0], [4.0, 3.0, 4.0]), EPS),
        TOUCHES
    );
}

#[test]
fn bvh_finds_exactly_the_boxes_that_meet_a_query() {
    // A fixed pseudo-random scatter of boxes, checked against brute force.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut random_box = |extent: f64| {
        let min = DVec3::new(next(), next(), next()) * 100.0;
        let size = DVec3::new(next(), next(), next()) * extent;
        Aabb::new(min, min + size)
    };
    let boxes: Vec<Aabb> = (0..2000).map(|_| random_box(5.0)).collect();
    let bvh = Bvh::new(&boxes);
    assert_eq!(bvh.len(), 2000);
    for _ in 0..200 {
        let query = random_box(10.0);
        let mut found = Vec::new();
        bvh.query(&query, |i| {
            found.push(i);
            true
        });
        found.sort_unstable();
        let expected: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| {
                let b = boxes[i as usize];
                b.min.cmple(query.max).all() && query.min.cmple(b.max).all()
            })
            .collect();
        assert_eq!(found, expected);
    }
    assert!(Bvh::new(&[]).is_empty());
}
