//! Property tests of plane cuts: random solids (convex and not, with and without holes) in random
//! poses, cut by random planes, must keep volume and surface, give closed parts, and keep normals
//! pointing outward.

use crate::common;

use proptest::prelude::*;
use shapegram_geom::{
    DAffine3, DQuat, DVec3, Mesh, Plane,
    primitives::{cone, cuboid, cylinder, pyramid, sphere},
    split::{slice_faces, split, split_polygon, split_slabs},
};

fn vec3(range: std::ops::Range<f64>) -> impl Strategy<Value = DVec3> {
    (range.clone(), range.clone(), range).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn direction() -> impl Strategy<Value = DVec3> {
    vec3(-1.0..1.0).prop_filter_map("direction too short", |v| {
        (v.length() > 0.1).then(|| v.normalize())
    })
}

/// A solid from a small zoo, scaled, turned and moved.
fn solid() -> impl Strategy<Value = Mesh> {
    let shape = (0..8usize, vec3(0.5..5.0), 3..14u32, 2..7u32).prop_map(
        |(kind, size, n, rings)| match kind {
            0 => cuboid(size),
            1 => cylinder(size, n),
            2 => sphere(size, n, rings),
            3 => cone(size, n),
            4 => pyramid(size),
            5 => common::l_prism(),
            6 => common::u_prism(),
            _ => common::tube(),
        },
    );
    (shape, vec3(-3.2..3.2), vec3(-50.0..50.0)).prop_map(|(mesh, angles, shift)| {
        let turn = DQuat::from_euler(glam::EulerRot::XYZ, angles.x, angles.y, angles.z);
        mesh.transformed(&DAffine3::from_rotation_translation(turn, shift))
    })
}

/// A plane with the given normal placed somewhere across the mesh (now and then through a vertex).
fn plane_across(mesh: &Mesh, normal: DVec3, t: f64, through_vertex: Option<usize>) -> Plane {
    if let Some(i) = through_vertex {
        return Plane::from_point_normal(mesh.positions()[i % mesh.vertex_count()], normal);
    }
    let heights = mesh.positions().iter().map(|p| p.dot(normal));
    let lo = heights.clone().fold(f64::INFINITY, f64::min);
    let hi = heights.fold(f64::NEG_INFINITY, f64::max);
    Plane {
        normal,
        offset: lo + (hi - lo) * t,
    }
}

/// Total area of the faces not lying in the plane.
fn area_off_plane(mesh: &Mesh, plane: &Plane, eps: f64) -> f64 {
    (0..mesh.face_count())
        .filter(|&f| {
            !mesh
                .face_points(f)
                .all(|p| plane.signed_distance(p).abs() <= eps)
        })
        .map(|f| mesh.face_area(f))
        .sum()
}

fn check_part(part: &Mesh, total: f64, tol: f64) -> Result<(), TestCaseError> {
    if part.is_empty() {
        return Ok(());
    }
    let report = part.edge_report();
    prop_assert!(report.is_watertight(), "part not closed: {:?}", report);
    let v = part.signed_volume();
    prop_assert!(
        v > -tol && v < total + tol,
        "part volume {} of {}",
        v,
        total
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn one_cut_keeps_volume_surface_and_closure(
        mesh in solid(),
        normal in direction(),
        t in -0.1..1.1f64,
        through in prop::option::weighted(0.25, 0..64usize),
    ) {
        let plane = plane_across(&mesh, normal, t, through);
        let diag = mesh.bounds().unwrap().diagonal();
        let (vol_tol, area_tol, eps) = (1e-9 * diag.powi(3), 1e-9 * diag.powi(2), 1e-7 * diag);
        let total = mesh.signed_volume();
        let (below, above) = split(&mesh, &plane);
        prop_assert!((below.signed_volume() + above.signed_volume() - total).abs() < vol_tol);
        check_part(&below, total, vol_tol)?;
        check_part(&above, total, vol_tol)?;
        let kept = area_off_plane(&below, &plane, eps) + area_off_plane(&above, &plane, eps);
        prop_assert!((kept - area_off_plane(&mesh, &plane, eps)).abs() < area_tol);
        // Both caps cover the same section of the solid.
        let cap = |m: &Mesh| m.area() - area_off_plane(m, &plane, eps);
        let on_plane = mesh.area() - area_off_plane(&mesh, &plane, eps);
        if on_plane == 0.0 {
            prop_assert!((cap(&below) - cap(&above)).abs() < area_tol);
        }
        for p in below.positions() {
            prop_assert!(plane.signed_distance(*p) <= eps);
        }
        for p in above.positions() {
            prop_assert!(plane.signed_distance(*p) >= -eps);
        }
    }

    #[test]
    fn parallel_cuts_keep_volume_and_closure(
        mesh in solid(),
        normal in direction(),
        ts in prop::collection::vec(-0.1..1.1f64, 1..7),
    ) {
        let offsets: Vec<f64> = ts.iter().map(|&t| plane_across(&mesh, normal, t, None).offset).collect();
        let diag = mesh.bounds().unwrap().diagonal();
        let vol_tol = 1e-9 * diag.powi(3);
        let total = mesh.signed_volume();
        let slabs = split_slabs(&mesh, normal, &offsets);
        prop_assert_eq!(slabs.len(), offsets.len() + 1);
        let sum: f64 = slabs.iter().map(Mesh::signed_volume).sum();
        prop_assert!((sum - total).abs() < vol_tol);
        for slab in &slabs {
            check_part(slab, total, vol_tol)?;
        }
    }

    #[test]
    fn slicing_keeps_volume_surface_and_closure(
        mesh in solid(),
        normal in direction(),
        ts in prop::collection::vec(-0.1..1.1f64, 1..7),
        through in prop::collection::vec(0..64usize, 0..3),
    ) {
        // Planes across the solid, and some through its vertices (along its edges, even).
        let mut offsets: Vec<f64> = ts.iter().map(|&t| plane_across(&mesh, normal, t, None).offset).collect();
        offsets.extend(through.iter().map(|&v| plane_across(&mesh, normal, 0.0, Some(v)).offset));
        let diag = mesh.bounds().unwrap().diagonal();
        let (sliced, sources) = slice_faces(&mesh, normal, &offsets);
        let report = sliced.edge_report();
        prop_assert!(report.is_watertight(), "{:?}", report);
        prop_assert!((sliced.signed_volume() - mesh.signed_volume()).abs() < 1e-9 * diag.powi(3));
        prop_assert!((sliced.area() - mesh.area()).abs() < 1e-9 * diag.powi(2));
        prop_assert_eq!(sources.len(), sliced.face_count());
        for (g, &source) in sources.iter().enumerate() {
            let normal_before = mesh.face_normal(source as usize);
            prop_assert!(sliced.face_normal(g).dot(normal_before) > 0.999);
        }
    }

    #[test]
    fn polygon_cut_keeps_area_and_facing(
        radii in prop::collection::vec(0.3..3.0f64, 3..14),
        turn in vec3(-3.2..3.2),
        normal in direction(),
        t in -0.1..1.1f64,
    ) {
        // A star-shaped polygon: non-convex in general, always simple.
        let n = radii.len() as f64;
        let rotation = DQuat::from_euler(glam::EulerRot::XYZ, turn.x, turn.y, turn.z);
        let points: Vec<DVec3> = radii.iter().enumerate().map(|(i, r)| {
            let a = std::f64::consts::TAU * i as f64 / n;
            rotation * DVec3::new(r * a.cos(), r * a.sin(), 0.0)
        }).collect();
        let polygon = Mesh::from_polygon(&points);
        let facing = polygon.face_normal(0);
        let plane = plane_across(&polygon, normal, t, None);
        let (below, above) = split_polygon(&points, &plane);
        let mut area = 0.0;
        for piece in below.iter().chain(&above) {
            let m = Mesh::from_polygon(piece);
            area += m.area();
            prop_assert!(m.face_normal(0).abs_diff_eq(facing, 1e-6) || m.area() < 1e-12);
        }
        prop_assert!((area - polygon.area()).abs() < 1e-9);
    }
}
