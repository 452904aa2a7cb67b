//! Taper, twist and shear: volumes, bounds and vertex positions against exact values, and the
//! mesh staying closed, planar and facing out.

use crate::common;

use shapegram_geom::{
    Aabb, DAffine3, DQuat, DVec3, Mesh,
    deform::{Deformed, MAX_TWIST_SLICES, shear, taper, twist, twist_slices},
    primitives::{cuboid, cylinder},
    shape_metrics::is_planar,
};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn vclose(a: DVec3, b: DVec3) -> bool {
    a.abs_diff_eq(b, 1e-9)
}

/// Checks what every deformation keeps: a closed surface with faces facing out, planar faces
/// and a source for every face.
fn assert_sound(d: &Deformed, input: &Mesh) {
    let report = d.mesh.edge_report();
    assert!(report.is_watertight(), "{report:?}");
    assert!(d.mesh.signed_volume() > 0.0);
    assert!(flat_faces(&d.mesh), "a face is bent");
    assert_eq!(d.sources.len(), d.mesh.face_count());
    assert!(d.sources.iter().all(|&s| (s as usize) < input.face_count()));
}

/// Whether every face's corners lie within 10⁻⁹ of its size from its plane. (`is_planar`'s
/// corner angles read rounding errors as degrees where a corner is nearly straight.)
fn flat_faces(mesh: &Mesh) -> bool {
    (0..mesh.face_count()).all(|f| {
        let normal = mesh.face_normal(f);
        let size = Aabb::from_points(mesh.face_points(f)).unwrap().diagonal();
        let origin = mesh.face_points(f).next().unwrap();
        mesh.face_points(f)
            .all(|p| (p - origin).dot(normal).abs() <= 1e-9 * size)
    })
}

fn bounds_of(d: &Deformed) -> Aabb {
    d.mesh.bounds().unwrap()
}

/// The positions of the vertices at height `y`.
fn at_height(mesh: &Mesh, y: f64) -> Vec<DVec3> {
    let mut points: Vec<DVec3> = mesh
        .positions()
        .iter()
        .copied()
        .filter(|p| close(p.y, y, 1e-9))
        .collect();
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.z.total_cmp(&b.z)));
    points
}

#[test]
fn a_box_tapered_to_half_is_a_frustum() {
    let size = DVec3::new(4.0, 10.0, 6.0);
    let b = cuboid(size);
    let d = taper(&b, size, 1, 0.5).unwrap();
    assert_sound(&d, &b);
    // h/3 · (A₀ + A₁ + √(A₀A₁)) with A₀ = 24 and A₁ = 6: 10/3 · 42.
    assert!(close(d.mesh.signed_volume(), 140.0, 1e-9));
    // No face bends: the box keeps its six faces, and the bottom its corners.
    assert_eq!(d.mesh.face_count(), 6);
    assert_eq!(d.sources, [0, 1, 2, 3, 4, 5]);
    assert_eq!(at_height(&d.mesh, 0.0), at_height(&b, 0.0));
    let top = at_height(&d.mesh, 10.0);
    let expected = [
        DVec3::new(1.0, 10.0, 1.5),
        DVec3::new(1.0, 10.0, 4.5),
        DVec3::new(3.0, 10.0, 1.5),
        DVec3::new(3.0, 10.0, 4.5),
    ];
    assert!(
        top.iter().zip(&expected).all(|(a, b)| vclose(*a, *b)),
        "{top:?}"
    );
    let bounds = bounds_of(&d);
    assert!(vclose(bounds.min, DVec3::ZERO) && vclose(bounds.max, size));
}

#[test]
fn taper_along_x_and_z_and_growing() {
    let size = DVec3::new(4.0, 10.0, 6.0);
    let b = cuboid(size);
    // Along x, the 10 × 6 cross-section grows to 20 × 12 at x = 4.
    let d = taper(&b, size, 0, 2.0).unwrap();
    assert_sound(&d, &b);
    assert!(close(
        d.mesh.signed_volume(),
        4.0 / 3.0 * (60.0 + 240.0 + 120.0),
        1e-9
    ));
    let bounds = bounds_of(&d);
    assert!(
        vclose(bounds.min, DVec3::new(0.0, -5.0, -3.0)),
        "{bounds:?}"
    );
    assert!(vclose(bounds.max, DVec3::new(4.0, 15.0, 9.0)), "{bounds:?}");
    // Along z, to a quarter: the far end is 1 × 2.5 around (2, 5).
    let d = taper(&b, size, 2, 0.25).unwrap();
    assert_sound(&d, &b);
    let far: Vec<DVec3> = d
        .mesh
        .positions()
        .iter()
        .copied()
        .filter(|p| p.z == 6.0)
        .collect();
    assert_eq!(far.len(), 4);
    for p in far {
        assert!(close((p.x - 2.0).abs(), 0.5, 1e-12) && close((p.y - 5.0).abs(), 1.25, 1e-12));
    }
}

#[test]
fn tapering_to_zero_makes_a_pyramid_with_one_apex() {
    let size = DVec3::new(4.0, 10.0, 6.0);
    let b = cuboid(size);
    let d = taper(&b, size, 1, 0.0).unwrap();
    assert_sound(&d, &b);
    assert!(close(d.mesh.signed_volume(), 24.0 * 10.0 / 3.0, 1e-9));
    // The top collapsed and went; the four sides are triangles meeting at the apex.
    assert_eq!(d.mesh.face_count(), 5);
    assert!(!d.sources.contains(&3), "the top face is gone");
    assert_eq!(at_height(&d.mesh, 10.0), [DVec3::new(2.0, 10.0, 3.0)]);
    assert_eq!(d.mesh.faces().filter(|f| f.len() == 3).count(), 4);
    // A rectangle tapered across its height to 0 is a triangle: the wedge of a flat shape.
    let facade = Mesh::from_polygon(&[
        DVec3::ZERO,
        DVec3::new(6.0, 0.0, 0.0),
        DVec3::new(6.0, 3.0, 0.0),
        DVec3::new(0.0, 3.0, 0.0),
    ]);
    let d = taper(&facade, DVec3::new(6.0, 3.0, 0.0), 1, 0.0).unwrap();
    assert_eq!(d.mesh.face_count(), 1);
    assert_eq!(d.mesh.face(0).len(), 3);
    assert!(close(d.mesh.area(), 9.0, 1e-12));
    assert!(vclose(d.mesh.face_normal(0), DVec3::Z));
}

#[test]
fn a_crenel_drawn_into_the_apex_keeps_its_notch() {
    // A crenel wall: its outline reaches the top twice, so the apex pinches it; what is left is
    // the wall's triangle less the notch's, which meets it at the apex.
    let wall = Mesh::from_polygon(&[
        DVec3::ZERO,
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(3.0, 2.0, 0.0),
        DVec3::new(2.0, 2.0, 0.0),
        DVec3::new(2.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(0.0, 2.0, 0.0),
    ]);
    let d = taper(&wall, DVec3::new(3.0, 2.0, 0.0), 1, 0.0).unwrap();
    for f in 0..d.mesh.face_count() {
        assert!(d.mesh.face_normal(f).abs_diff_eq(DVec3::Z, 1e-12));
        assert!(d.mesh.face_area(f) > 0.0);
        assert!(d.mesh.face(f).len() == 3);
    }
    // The width at height y is 3(1 − y/2) below the notch and 2(1 − y/2) beside it.
    assert!(
        close(d.mesh.area(), 3.0 * 0.75 + 2.0 * 0.25, 1e-12),
        "{}",
        d.mesh.area()
    );
    // The flanks of the notch meet at the apex, and the boundary is whole.
    assert_eq!(d.mesh.boundary_edges().len(), 6);
    assert_eq!(at_height(&d.mesh, 2.0), [DVec3::new(1.5, 2.0, 0.0)]);
}

#[test]
fn taper_by_one_changes_nothing_and_bad_factors_are_refused() {
    let size = DVec3::new(2.0, 3.0, 4.0);
    let b = cuboid(size);
    assert_eq!(taper(&b, size, 1, 1.0).unwrap().mesh, b);
    assert!(taper(&b, size, 1, -0.5).is_none());
    assert!(taper(&b, size, 1, f64::NAN).is_none());
    assert!(taper(&b, size, 1, f64::INFINITY).is_none());
    assert!(taper(&b, size, 3, 0.5).is_none());
}

#[test]
fn bent_faces_are_triangulated_where_they_were_flat() {
    // A cube standing on a corner: each face is slanted against y, and a taper along y bends
    // every one of them (only faces along the axis or across it stay flat).
    let turn = DQuat::from_rotation_arc(DVec3::ONE.normalize(), DVec3::Y);
    let mut cube = cuboid(DVec3::splat(2.0));
    cube.transform(&DAffine3::from_quat(turn));
    let b = cube.bounds().unwrap();
    cube.transform(&DAffine3::from_translation(-b.min));
    let size = b.size();
    assert!(close(size.y, 2.0 * 3f64.sqrt(), 1e-12), "{size}");
    let d = taper(&cube, size, 1, 0.5).unwrap();
    assert_sound(&d, &cube);
    // Sliced into four (the scale changes by an eighth a slice at most), and every piece a fan
    // of triangles around its centre (or a triangle already).
    for f in 0..6 {
        let pieces = d.sources.iter().filter(|&&s| s == f);
        assert!(pieces.count() >= 6, "face {f}");
    }
    assert!(d.mesh.faces().all(|f| f.len() == 3));
    // The corners on the centre line stay: the lowest where it was, the highest over it.
    let lowest = at_height(&d.mesh, 0.0);
    let highest = at_height(&d.mesh, size.y);
    assert_eq!(lowest, at_height(&cube, 0.0));
    assert_eq!(highest.len(), 1);
    assert!(close(highest[0].x, lowest[0].x, 1e-9) && close(highest[0].z, lowest[0].z, 1e-9));
}

#[test]
fn shear_moves_the_far_end_and_keeps_the_volume() {
    let size = DVec3::new(4.0, 10.0, 6.0);
    let b = cuboid(size);
    let d = shear(&b, size, 1, 0, 3.0).unwrap();
    assert_sound(&d, &b);
    assert!(close(d.mesh.signed_volume(), 240.0, 1e-9));
    assert_eq!(d.mesh.face_count(), 6);
    assert_eq!(at_height(&d.mesh, 0.0), at_height(&b, 0.0));
    let moved: Vec<DVec3> = at_height(&b, 10.0)
        .iter()
        .map(|p| *p + DVec3::new(3.0, 0.0, 0.0))
        .collect();
    assert_eq!(at_height(&d.mesh, 10.0), moved);
    // Halfway up, halfway across.
    let mid = shear(
        &Mesh::from_polygon(&[DVec3::new(0.0, 5.0, 0.0); 3]),
        size,
        1,
        0,
        3.0,
    )
    .unwrap()
    .mesh
    .position(0);
    assert!(vclose(mid, DVec3::new(1.5, 5.0, 0.0)));
    let bounds = bounds_of(&d);
    assert!(vclose(bounds.min, DVec3::ZERO) && vclose(bounds.max, DVec3::new(7.0, 10.0, 6.0)));
    // Backwards along z, sheared along x.
    let d = shear(&b, size, 0, 2, -2.0).unwrap();
    assert_sound(&d, &b);
    assert!(close(d.mesh.signed_volume(), 240.0, 1e-9));
    let bounds = bounds_of(&d);
    assert!(vclose(bounds.min, DVec3::new(0.0, 0.0, -2.0)) && vclose(bounds.max, size));
}

#[test]
fn shear_refuses_its_own_axis() {
    let size = DVec3::ONE;
    let b = cuboid(size);
    assert!(shear(&b, size, 1, 1, 1.0).is_none());
    assert!(shear(&b, size, 1, 3, 1.0).is_none());
    assert!(shear(&b, size, 1, 0, f64::NAN).is_none());
    assert_eq!(shear(&b, size, 1, 0, 0.0).unwrap().mesh, b);
    // Geometry twice as tall as its scope, sheared by nearly the largest number: out of range.
    let tall = DVec3::new(1.0, 0.5, 1.0);
    assert!(shear(&b, tall, 1, 0, 1e308).is_none());
    assert!(twist(&b, tall, 1, 1e308).is_none());
    assert!(shear(&b, size, 1, 0, 1e308).is_some());
}

#[test]
fn twist_slices_turn_at_most_seven_and_a_half_degrees() {
    assert_eq!(twist_slices(0.0), 1);
    assert_eq!(twist_slices(7.5), 1);
    assert_eq!(twist_slices(8.0), 2);
    assert_eq!(twist_slices(-90.0), 12);
    assert_eq!(twist_slices(360.0), 48);
    assert_eq!(twist_slices(720.0), MAX_TWIST_SLICES);
    assert_eq!(twist_slices(f64::INFINITY), MAX_TWIST_SLICES);
}

#[test]
fn a_twisted_box_turns_its_top_and_keeps_its_volume() {
    let size = DVec3::new(4.0, 10.0, 4.0);
    let b = cuboid(size);
    let d = twist(&b, size, 1, 90.0).unwrap();
    assert_sound(&d, &b);
    // 12 slices of 7.5°: four walls of four triangles each per slice, and the two ends.
    assert_eq!(d.mesh.face_count(), 12 * 4 * 4 + 2);
    // The bottom stays; the top corner (0, 10, 0) turns a quarter about +y to (0, 10, 4).
    assert_eq!(at_height(&d.mesh, 0.0), at_height(&b, 0.0));
    let top_face = d.sources.iter().position(|&s| s == 3).unwrap();
    let top: Vec<DVec3> = d.mesh.face_points(top_face).collect();
    let original: Vec<DVec3> = b.face_points(3).collect();
    assert!(vclose(original[0], DVec3::new(0.0, 10.0, 0.0)));
    assert!(vclose(top[0], DVec3::new(0.0, 10.0, 4.0)), "{top:?}");
    assert!(vclose(d.mesh.face_normal(top_face), DVec3::Y));
    // The cross-section keeps its area; the walls run straight between slices and cut a little
    // off (−0.14 %).
    let volume = d.mesh.signed_volume();
    assert!(
        volume < 160.0 && close(volume, 160.0, 160.0 * 2e-3),
        "{volume}"
    );
    // Halfway up, the section has turned 45°: its corners reach 2√2 from the centre line.
    let mid = at_height(&d.mesh, 5.0);
    assert_eq!(mid.len(), 4);
    let reach = 2.0 * 2f64.sqrt();
    for p in mid {
        let r = DVec3::new(p.x - 2.0, 0.0, p.z - 2.0);
        assert!(close(r.length(), reach, 1e-9));
        assert!(close(r.x.abs(), reach, 1e-9) || close(r.z.abs(), reach, 1e-9));
    }
    assert!(close(bounds_of(&d).min.x, 2.0 - reach, 1e-9));
}

#[test]
fn a_twist_at_45_degrees_puts_the_corner_on_the_axis_line() {
    let size = DVec3::new(4.0, 10.0, 4.0);
    let b = cuboid(size);
    let d = twist(&b, size, 1, 45.0).unwrap();
    assert_sound(&d, &b);
    let top = d.sources.iter().position(|&s| s == 3).unwrap();
    let corner = d.mesh.face_points(top).next().unwrap();
    let reach = 2.0 * 2f64.sqrt();
    assert!(
        vclose(corner, DVec3::new(2.0 - reach, 10.0, 2.0)),
        "{corner}"
    );
    // Left-handed twists turn the other way.
    let d = twist(&b, size, 1, -45.0).unwrap();
    assert_sound(&d, &b);
    let corner = d.mesh.face_points(top).next().unwrap();
    assert!(
        vclose(corner, DVec3::new(2.0, 10.0, 2.0 - reach)),
        "{corner}"
    );
}

#[test]
fn twists_along_x_and_z_and_of_other_solids() {
    let size = DVec3::new(12.0, 2.0, 2.0);
    let b = cuboid(size);
    let d = twist(&b, size, 0, 180.0).unwrap();
    assert_sound(&d, &b);
    // Half a turn about x takes the far end's corner (12, 0, 0) to (12, 2, 2).
    assert!(
        d.mesh
            .positions()
            .iter()
            .any(|p| vclose(*p, DVec3::new(12.0, 2.0, 2.0)))
    );
    let v = d.mesh.signed_volume();
    assert!(close(v, 48.0, 48.0 * 2e-3), "{v}");
    let size = DVec3::new(3.0, 3.0, 9.0);
    let d = twist(&cuboid(size), size, 2, 30.0).unwrap();
    assert_sound(&d, &cuboid(size));
    // A cylinder's wall, an L-prism's reflex corner and a tube's hole twist just as well.
    let c = cylinder(DVec3::new(4.0, 6.0, 4.0), 24);
    let d = twist(&c, DVec3::new(4.0, 6.0, 4.0), 1, 60.0).unwrap();
    assert_sound(&d, &c);
    let (v, v0) = (d.mesh.signed_volume(), c.signed_volume());
    assert!(v < v0 && close(v, v0, v0 * 2e-3), "{v} {v0}");
    for (mesh, size) in [
        (common::l_prism(), DVec3::new(4.0, 3.0, 4.0)),
        (common::tube(), DVec3::new(4.0, 3.0, 4.0)),
    ] {
        let d = twist(&mesh, size, 1, 40.0).unwrap();
        assert_sound(&d, &mesh);
        let v = d.mesh.signed_volume();
        assert!(close(v, 36.0, 36.0 * 2e-3), "{v}");
    }
}

#[test]
fn faces_that_are_not_convex_are_sliced_at_their_reflex_corners() {
    // Twisted along x, the U's floor and top (in y = 0 and y = 2) bend; slices through the
    // inner corners of the notch (x = 2 and 4) leave only convex pieces, each a fan.
    let u = common::u_prism();
    let size = DVec3::new(6.0, 2.0, 4.0);
    let d = twist(&u, size, 0, 30.0).unwrap();
    assert_sound(&d, &u);
    let xs: Vec<f64> = d.mesh.positions().iter().map(|p| p.x).collect();
    for plane in [1.5, 2.0, 3.0, 4.0, 4.5] {
        assert!(xs.contains(&plane), "no slice at x = {plane}");
    }
    let v = d.mesh.signed_volume();
    assert!(v < 36.0 && close(v, 36.0, 36.0 * 2e-3), "{v}");
}

#[test]
fn a_box_thinner_than_the_tolerance_of_its_slices_stays_closed() {
    // 0.1 µm thick and 36 m across: the slices of a twist would lie closer to one another than
    // the cut's tolerance (10⁻⁹ of the diagonal), so they cut as one.
    let size = DVec3::new(20.0, 1e-7, 30.0);
    let b = cuboid(size);
    let d = twist(&b, size, 1, 45.0).unwrap();
    assert!(d.mesh.is_watertight(), "{:?}", d.mesh.edge_report());
    let d = taper(&d.mesh, size, 1, 0.0).unwrap();
    assert!(d.mesh.is_watertight(), "{:?}", d.mesh.edge_report());
}

#[test]
fn twist_by_nothing_and_of_flat_scopes() {
    let size = DVec3::new(2.0, 3.0, 4.0);
    let b = cuboid(size);
    assert_eq!(twist(&b, size, 1, 0.0).unwrap().mesh, b);
    assert!(twist(&b, size, 1, f64::NAN).is_none());
    assert!(twist(&b, size, 5, 10.0).is_none());
    // A lot has no height: twisting it along y moves nothing.
    let lot = shapegram_geom::primitives::quad(4.0, 3.0);
    let d = twist(&lot, DVec3::new(4.0, 0.0, 3.0), 1, 90.0).unwrap();
    assert_eq!(d.mesh, lot);
    // Twisted along x, the lot's far edge turns up out of the ground: two triangles.
    let d = twist(&lot, DVec3::new(4.0, 0.0, 3.0), 0, 30.0).unwrap();
    assert!(is_planar(&d.mesh, 1e-4));
    assert!(d.mesh.boundary_edges().len() > 4);
}

#[test]
fn a_twist_slice_through_a_face_and_its_edges() {
    // The L-prism on its side: its notch's floor lies at y = 2, where the one plane of a
    // twist by 15° slices it, through the floor's edges and corners.
    let mut l = common::l_prism();
    l.transform(&DAffine3::from_rotation_z(0.5 * std::f64::consts::PI));
    let b = l.bounds().unwrap();
    l.transform(&DAffine3::from_translation(-b.min));
    let size = b.size();
    assert!(vclose(size, DVec3::new(3.0, 4.0, 4.0)), "{size}");
    let d = twist(&l, size, 1, 15.0).unwrap();
    assert_sound(&d, &l);
    let v = d.mesh.signed_volume();
    assert!(v < 36.0 && close(v, 36.0, 36.0 * 2e-3), "{v}");
}

mod properties {
    use proptest::prelude::*;
    use shapegram_geom::{
        DAffine3, DQuat, DVec3, Mesh,
        deform::{shear, taper, twist},
        primitives::{cone, cuboid, cylinder, pyramid, sphere},
    };

    use super::{common, flat_faces};

    /// A solid from a small zoo, sometimes turned, moved to fill its scope `[0, size]`.
    fn solid() -> impl Strategy<Value = (Mesh, DVec3)> {
        let shape = (
            0..8usize,
            0.5..5.0f64,
            0.5..5.0f64,
            0.5..5.0f64,
            3..14u32,
            2..7u32,
        )
            .prop_map(|(kind, x, y, z, n, rings)| {
                let size = DVec3::new(x, y, z);
                match kind {
                    0 => cuboid(size),
                    1 => cylinder(size, n),
                    2 => sphere(size, n, rings),
                    3 => cone(size, n),
                    4 => pyramid(size),
                    5 => common::l_prism(),
                    6 => common::u_prism(),
                    _ => common::tube(),
                }
            });
        let turn = prop_oneof![Just(None), (-3.2..3.2f64, -3.2..3.2f64).prop_map(Some)];
        (shape, turn).prop_map(|(mut mesh, turn)| {
            if let Some((a, b)) = turn {
                mesh.transform(&DAffine3::from_quat(DQuat::from_euler(
                    glam::EulerRot::XYZ,
                    a,
                    b,
                    0.0,
                )));
            }
            let bounds = mesh.bounds().unwrap();
            mesh.transform(&DAffine3::from_translation(-bounds.min));
            (mesh, bounds.size())
        })
    }

    fn check(mesh: &Mesh) -> Result<(), TestCaseError> {
        let report = mesh.edge_report();
        prop_assert!(report.is_watertight(), "{:?}", report);
        prop_assert!(mesh.signed_volume() > 0.0);
        prop_assert!(flat_faces(mesh), "a face is bent");
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        #[test]
        fn deformed_solids_stay_closed_flat_faced_and_outward(
            (mesh, size) in solid(),
            axis in 0..3usize,
            other in 1..3usize,
            factor in prop_oneof![Just(0.0), 0.0..2.0f64],
            degrees in -400.0..400.0f64,
            amount in -5.0..5.0f64,
        ) {
            let volume = mesh.signed_volume();
            let tapered = taper(&mesh, size, axis, factor).unwrap();
            check(&tapered.mesh)?;
            let twisted = twist(&mesh, size, axis, degrees).unwrap();
            check(&twisted.mesh)?;
            // Boxes and prisms along the axis lose 0.14 %; slanted faces cut into pieces without
            // symmetry may bulge in or out by up to about 2 % (turned pyramids, mostly).
            let v = twisted.mesh.signed_volume();
            prop_assert!((v - volume).abs() < 3e-2 * volume, "{} of {}", v, volume);
            let sheared = shear(&mesh, size, axis, (axis + other) % 3, amount).unwrap();
            check(&sheared.mesh)?;
            let v = sheared.mesh.signed_volume();
            prop_assert!((v - volume).abs() < 1e-9 * volume.max(1.0), "{} of {}", v, volume);
        }
    }
}
