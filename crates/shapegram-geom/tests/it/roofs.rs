//! Roofs: exact volumes and shapes on rectangles, squares and L-shapes, closedness and outward
//! normals, footprints in other planes, overhangs, invalid input, and property tests on random
//! convex, star-shaped and rectilinear footprints.

use crate::common;

use common::{footprint_loop, l_footprint, polygon_area, polyomino, star_footprint, u_footprint};
use proptest::prelude::*;
use shapegram_geom::{
    DAffine3, DQuat, DVec3, Mesh, Plane,
    extrude::extrude_polygon,
    mesh::newell,
    roof::{roof_gable, roof_hip, roof_pyramid, roof_shed},
    split::split,
};

const EPS: f64 = 1e-9;

/// The rectangle `[0, w] × [0, d]` in x and z, facing up.
fn rectangle(w: f64, d: f64) -> Vec<DVec3> {
    footprint_loop(&[(0.0, 0.0), (w, 0.0), (w, d), (0.0, d)])
}

fn tan(deg: f64) -> f64 {
    deg.to_radians().tan()
}

/// Closed, consistently oriented, positive volume, no face without area, every face planar (to
/// the skeleton's coincidence tolerance of 1e-8 of the size: nearly simultaneous events merge),
/// no triangle of the triangulation under the workspace's degenerate area of 1e-12 · diagonal².
fn assert_solid(mesh: &Mesh) {
    assert!(
        mesh.is_watertight(),
        "not watertight: {:?}",
        mesh.edge_report()
    );
    assert!(
        mesh.signed_volume() > 0.0,
        "volume {}",
        mesh.signed_volume()
    );
    let size = mesh.bounds().unwrap().diagonal();
    for f in 0..mesh.face_count() {
        assert!(
            mesh.face_area(f) > 1e-12 * size * size,
            "face {f} has no area: {}",
            mesh.face_area(f)
        );
        let normal = mesh.face_normal(f);
        let first = mesh.face_points(f).next().unwrap();
        for p in mesh.face_points(f) {
            assert!(
                (p - first).dot(normal).abs() < 1e-8 * size,
                "face {f} is not planar"
            );
        }
    }
    assert_eq!(mesh.degenerate_triangle_count(1e-12 * size * size), 0);
}

/// For a convex solid: every face normal points away from the mean of the vertices.
fn assert_convex_outward(mesh: &Mesh) {
    let inside = mesh.positions().iter().sum::<DVec3>() / mesh.vertex_count() as f64;
    for f in 0..mesh.face_count() {
        let away = mesh.face_centroid(f) - inside;
        assert!(
            mesh.face_normal(f).dot(away) > 0.0,
            "face {f} points inward"
        );
    }
}

fn max_y(mesh: &Mesh) -> f64 {
    mesh.bounds().unwrap().max.y
}

/// Face sizes (corner counts), sorted.
fn face_sizes(mesh: &Mesh) -> Vec<usize> {
    let mut sizes: Vec<usize> = mesh.faces().map(<[u32]>::len).collect();
    sizes.sort_unstable();
    sizes
}

fn assert_close(a: f64, b: f64, tolerance: f64) {
    assert!((a - b).abs() <= tolerance * b.abs().max(1.0), "{a} != {b}");
}

#[test]
fn gable_on_a_rectangle_has_its_ridge_along_the_long_axis() {
    // 10 along x, 4 along z: the ridge runs along x at z = 2.
    let roof = roof_gable(&rectangle(10.0, 4.0), 30.0, 0.0).unwrap();
    assert_solid(&roof);
    assert_convex_outward(&roof);
    let ridge = 2.0 * tan(30.0);
    // Cross-section: a triangle of base 4 and height 2·tan(a), i.e. area w²/4·tan(a), along 10.
    assert_close(roof.signed_volume(), 16.0 / 4.0 * tan(30.0) * 10.0, EPS);
    assert_close(max_y(&roof), ridge, EPS);
    assert_eq!(face_sizes(&roof), vec![3, 3, 4, 4, 4]);
    let top: Vec<DVec3> = roof
        .positions()
        .iter()
        .copied()
        .filter(|p| (p.y - ridge).abs() < EPS)
        .collect();
    assert_eq!(top.len(), 2);
    for p in top {
        assert_close(p.z, 2.0, EPS);
        assert!(p.x.abs() < EPS || (p.x - 10.0).abs() < EPS);
    }
    // The gable ends are upright.
    let upright = (0..roof.face_count())
        .filter(|&f| roof.face(f).len() == 3)
        .all(|f| roof.face_normal(f).y.abs() < EPS);
    assert!(upright);
}

#[test]
fn gable_on_a_deep_rectangle_turns_with_it() {
    // 4 along x, 10 along z: now the ridge runs along z at x = 2.
    let roof = roof_gable(&rectangle(4.0, 10.0), 45.0, 0.0).unwrap();
    assert_solid(&roof);
    assert_close(roof.signed_volume(), 16.0 / 4.0 * 10.0, EPS);
    for p in roof.positions().iter().filter(|p| p.y > 1.0) {
        assert_close(p.x, 2.0, EPS);
    }
}

#[test]
fn gable_on_a_square_and_a_trapezoid() {
    let square = roof_gable(&rectangle(4.0, 4.0), 45.0, 0.0).unwrap();
    assert_solid(&square);
    assert_close(square.signed_volume(), 16.0, EPS);
    assert_eq!(square.face_count(), 5);
    // A trapezoid with parallel sides 8 and 4, 3 apart: the ridge is parallel to them, halfway.
    let trapezoid = footprint_loop(&[(0.0, 0.0), (8.0, 0.0), (6.0, 3.0), (2.0, 3.0)]);
    let roof = roof_gable(&trapezoid, 45.0, 0.0).unwrap();
    assert_solid(&roof);
    assert_convex_outward(&roof);
    assert_close(max_y(&roof), 1.5, EPS);
    // Height min(z, 3 − z) over the trapezoid of width 8 − 4z/3 at depth z.
    let volume = {
        let lower = 4.0 * 1.5 * 1.5 - 4.0 / 9.0 * 1.5f64.powi(3); // ∫₀^1.5 z(8 − 4z/3) dz
        let upper = {
            // ∫_{1.5}^3 (3 − z)(8 − 4z/3) dz, with u = 3 − z: ∫₀^1.5 u(4 + 4u/3) du
            2.0 * 1.5 * 1.5 + 4.0 / 9.0 * 1.5f64.powi(3)
        };
        lower + upper
    };
    assert_close(roof.signed_volume(), volume, EPS);
}

#[test]
fn hip_on_a_rectangle_has_two_trapezoids_and_two_triangles() {
    let roof = roof_hip(&rectangle(10.0, 4.0), 30.0, 0.0).unwrap();
    assert_solid(&roof);
    assert_convex_outward(&roof);
    assert_eq!(face_sizes(&roof), vec![3, 3, 4, 4, 4]);
    let t = tan(30.0);
    // ∫ distance to the boundary over a w × l rectangle (w ≤ l) is w²l/4 − w³/12.
    assert_close(
        roof.signed_volume(),
        t * (16.0 * 10.0 / 4.0 - 64.0 / 12.0),
        EPS,
    );
    assert_close(max_y(&roof), 2.0 * t, EPS);
    let mut ridge: Vec<f64> = roof
        .positions()
        .iter()
        .filter(|p| p.y > 1.0)
        .map(|p| p.x)
        .collect();
    ridge.sort_by(f64::total_cmp);
    assert_eq!(ridge.len(), 2);
    assert_close(ridge[0], 2.0, EPS);
    assert_close(ridge[1], 8.0, EPS);
}

#[test]
fn hip_on_a_square_is_a_pyramid() {
    let roof = roof_hip(&rectangle(6.0, 6.0), 40.0, 0.0).unwrap();
    assert_solid(&roof);
    assert_convex_outward(&roof);
    assert_eq!(face_sizes(&roof), vec![3, 3, 3, 3, 4]);
    let height = 3.0 * tan(40.0);
    assert_close(roof.signed_volume(), 36.0 * height / 3.0, EPS);
    assert_eq!(roof.vertex_count(), 5);
    let pyramid = roof_pyramid(&rectangle(6.0, 6.0), 40.0).unwrap();
    assert_close(pyramid.signed_volume(), roof.signed_volume(), EPS);
}

#[test]
fn hip_on_an_l_follows_the_straight_skeleton() {
    let t = tan(35.0);
    let roof = roof_hip(&l_footprint(), 35.0, 0.0).unwrap();
    assert_solid(&roof);
    // Six faces over the six edges and the bottom; ridge (3,1)–(1,1)–(1,3) at height tan(a).
    assert_eq!(roof.face_count(), 7);
    assert_close(roof.signed_volume(), 16.0 / 3.0 * t, EPS);
    let mut ridge: Vec<(i64, i64)> = roof
        .positions()
        .iter()
        .filter(|p| p.y > 0.5 * t)
        .map(|p| {
            assert_close(p.y, t, EPS);
            ((p.x * 1e6).round() as i64, (p.z * 1e6).round() as i64)
        })
        .collect();
    ridge.sort_unstable();
    assert_eq!(
        ridge,
        vec![
            (1_000_000, 1_000_000),
            (1_000_000, 3_000_000),
            (3_000_000, 1_000_000)
        ]
    );
    assert_faces_on_slopes(&roof, &l_footprint(), t);
}

#[test]
fn gable_on_an_l_runs_both_ridges_out_to_gables() {
    let t = tan(35.0);
    let roof = roof_gable(&l_footprint(), 35.0, 0.0).unwrap();
    assert_solid(&roof);
    assert_eq!(face_sizes(&roof), vec![3, 3, 4, 4, 4, 4, 6]);
    // The hip roof (16/3) plus the two tetrahedra under the former hip ends (1/3 each).
    assert_close(roof.signed_volume(), 6.0 * t, EPS);
    let gables: Vec<usize> = (0..roof.face_count())
        .filter(|&f| roof.face(f).len() == 3)
        .collect();
    for f in gables {
        assert!(
            roof.face_normal(f).y.abs() < EPS,
            "gable {f} is not upright"
        );
    }
}

#[test]
fn pyramid_and_shed_on_a_rectangle() {
    let t = tan(25.0);
    let pyramid = roof_pyramid(&rectangle(10.0, 4.0), 25.0).unwrap();
    assert_solid(&pyramid);
    assert_convex_outward(&pyramid);
    // Apex over the centre, 2 from the nearest edges.
    assert_close(max_y(&pyramid), 2.0 * t, EPS);
    assert_close(pyramid.signed_volume(), 40.0 * 2.0 * t / 3.0, EPS);
    assert_eq!(face_sizes(&pyramid), vec![3, 3, 3, 3, 4]);

    let footprint = rectangle(10.0, 4.0);
    // The edge along z = 0 (length 10): the plane rises 4·tan(a) across the depth.
    let edge = (0..4)
        .find(|&i| footprint[i].z.abs() < EPS && footprint[(i + 1) % 4].z.abs() < EPS)
        .unwrap();
    let shed = roof_shed(&footprint, 25.0, edge).unwrap();
    assert_solid(&shed);
    assert_convex_outward(&shed);
    // A triangular prism: cross-section 4 · 4·tan(a) / 2, length 10.
    assert_close(shed.signed_volume(), 10.0 * 16.0 * t / 2.0, EPS);
    assert_close(max_y(&shed), 4.0 * t, EPS);
    assert_eq!(face_sizes(&shed), vec![3, 3, 4, 4, 4]);
    // From a short edge the prism is longer and lower.
    let short = roof_shed(&footprint, 25.0, (edge + 1) % 4).unwrap();
    assert_solid(&short);
    assert_close(short.signed_volume(), 4.0 * 100.0 * t / 2.0, EPS);
}

#[test]
fn shed_on_a_trapezoid_from_its_long_side() {
    let t = tan(20.0);
    let trapezoid = footprint_loop(&[(0.0, 0.0), (8.0, 0.0), (6.0, 3.0), (2.0, 3.0)]);
    let edge = (0..4)
        .find(|&i| trapezoid[i].z.abs() < EPS && trapezoid[(i + 1) % 4].z.abs() < EPS)
        .unwrap();
    let shed = roof_shed(&trapezoid, 20.0, edge).unwrap();
    assert_solid(&shed);
    // ∫ z·tan(a) over the trapezoid: ∫₀³ z (8 − 4z/3) dz = 36 − 12 = 24.
    assert_close(shed.signed_volume(), 24.0 * t, EPS);
}

#[test]
fn roofs_work_in_any_plane() {
    let t = tan(30.0);
    let turns = [
        // Onto a wall facing +z: the roof grows along +z.
        DAffine3::from_rotation_x(std::f64::consts::FRAC_PI_2),
        DAffine3::from_rotation_translation(
            DQuat::from_euler(glam::EulerRot::XYZ, 0.7, -1.9, 2.4),
            DVec3::new(120.0, -40.0, 75.0),
        ),
    ];
    let flat = rectangle(10.0, 4.0);
    let expected = [
        t * 16.0 / 4.0 * 10.0,
        t * (40.0 - 64.0 / 12.0),
        40.0 * 2.0 * t / 3.0,
        10.0 * 16.0 * t / 2.0,
        16.0 / 3.0 * t,
    ];
    for turn in turns {
        let moved: Vec<DVec3> = flat.iter().map(|&p| turn.transform_point3(p)).collect();
        let l: Vec<DVec3> = l_footprint()
            .iter()
            .map(|&p| turn.transform_point3(p))
            .collect();
        let edge = (0..4)
            .find(|&i| flat[i].z.abs() < EPS && flat[(i + 1) % 4].z.abs() < EPS)
            .unwrap();
        let roofs = [
            roof_gable(&moved, 30.0, 0.0).unwrap(),
            roof_hip(&moved, 30.0, 0.0).unwrap(),
            roof_pyramid(&moved, 30.0).unwrap(),
            roof_shed(&moved, 30.0, edge).unwrap(),
            roof_hip(&l, 30.0, 0.0).unwrap(),
        ];
        let up = turn.transform_vector3(DVec3::Y);
        for (roof, volume) in roofs.iter().zip(expected) {
            assert_solid(roof);
            assert_close(roof.signed_volume(), volume, 1e-8);
            // Everything lies on the footprint's upper side.
            let base = moved[0].dot(up);
            assert!(roof.positions().iter().all(|p| p.dot(up) >= base - 1e-9));
        }
    }
}

#[test]
fn overhang_grows_the_eaves_and_keeps_the_ridge() {
    let t = tan(30.0);
    let (w, l, o) = (4.0, 10.0, 0.5);
    let hip = roof_hip(&rectangle(l, w), 30.0, o).unwrap();
    assert_solid(&hip);
    assert_convex_outward(&hip);
    // The hip roof of the grown rectangle, lowered by o·tan(a).
    let (gw, gl) = (w + 2.0 * o, l + 2.0 * o);
    assert_close(
        hip.signed_volume(),
        t * (gw * gw * gl / 4.0 - gw.powi(3) / 12.0),
        EPS,
    );
    assert_close(max_y(&hip), w / 2.0 * t, EPS);
    assert_close(hip.bounds().unwrap().min.y, -o * t, EPS);
    assert_close(hip.bounds().unwrap().min.x, -o, EPS);

    let gable = roof_gable(&rectangle(l, w), 30.0, o).unwrap();
    assert_solid(&gable);
    assert_close(gable.signed_volume(), gw * gw / 4.0 * t * gl, EPS);
    assert_close(max_y(&gable), w / 2.0 * t, EPS);

    // A non-convex footprint grows with mitred corners: the L becomes the L of arms 3 wide.
    let l_hip = roof_hip(&l_footprint(), 30.0, o).unwrap();
    assert_solid(&l_hip);
    assert_close(max_y(&l_hip), t, EPS);
    let l_gable = roof_gable(&l_footprint(), 30.0, o).unwrap();
    assert_solid(&l_gable);
    assert_close(max_y(&l_gable), t, EPS);
    assert!(l_gable.signed_volume() > l_hip.signed_volume());
}

#[test]
fn invalid_input_gives_none() {
    let r = rectangle(4.0, 3.0);
    for angle in [0.0, 90.0, -10.0, 95.0, f64::NAN, f64::INFINITY] {
        assert!(roof_hip(&r, angle, 0.0).is_none(), "angle {angle}");
        assert!(roof_gable(&r, angle, 0.0).is_none());
        assert!(roof_pyramid(&r, angle).is_none());
        assert!(roof_shed(&r, angle, 0).is_none());
    }
    for overhang in [-0.1, f64::NAN, f64::INFINITY] {
        assert!(roof_hip(&r, 30.0, overhang).is_none());
        assert!(roof_gable(&r, 30.0, overhang).is_none());
    }
    let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
    let bow_tie = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 2.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 2.0),
    ];
    let bent = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 2.0),
        DVec3::new(2.0, 0.5, 2.0),
        DVec3::new(2.0, 0.0, 0.0),
    ];
    for bad in [&line[..], &bow_tie[..], &bent[..], &r[..2]] {
        assert!(roof_hip(bad, 30.0, 0.0).is_none());
        assert!(roof_gable(bad, 30.0, 0.0).is_none());
        assert!(roof_pyramid(bad, 30.0).is_none());
        assert!(roof_shed(bad, 30.0, 0).is_none());
    }
    assert!(roof_shed(&r, 30.0, 4).is_none());
    // A shed rising from the inner edges of an L would dip below the other arm.
    let l = l_footprint();
    let inner = (0..6).filter(|&i| roof_shed(&l, 30.0, i).is_none()).count();
    assert_eq!(inner, 2);
    // A U is not star-shaped about its centroid (which lies in the notch).
    let u = u_footprint();
    assert!(roof_pyramid(&u, 30.0).is_none());
    assert!(roof_pyramid(&l, 30.0).is_some());
}

#[test]
fn repeated_and_straight_corners_add_no_faces() {
    let noisy = footprint_loop(&[
        (0.0, 0.0),
        (5.0, 0.0),
        (10.0, 0.0),
        (10.0, 0.0),
        (10.0, 4.0),
        (0.0, 4.0),
    ]);
    for roof in [
        roof_hip(&noisy, 30.0, 0.0).unwrap(),
        roof_gable(&noisy, 30.0, 0.0).unwrap(),
        roof_pyramid(&noisy, 30.0).unwrap(),
        roof_shed(&noisy, 30.0, 0).unwrap(),
    ] {
        assert_solid(&roof);
        assert_eq!(roof.face_count(), 5);
    }
}

#[test]
fn hip_on_a_u_and_a_plus() {
    let t = tan(45.0);
    let u = footprint_loop(&[
        (0.0, 0.0),
        (6.0, 0.0),
        (6.0, 4.0),
        (4.0, 4.0),
        (4.0, 2.0),
        (2.0, 2.0),
        (2.0, 4.0),
        (0.0, 4.0),
    ]);
    let plus = footprint_loop(&[
        (2.0, 0.0),
        (4.0, 0.0),
        (4.0, 2.0),
        (6.0, 2.0),
        (6.0, 4.0),
        (4.0, 4.0),
        (4.0, 6.0),
        (2.0, 6.0),
        (2.0, 4.0),
        (0.0, 4.0),
        (0.0, 2.0),
        (2.0, 2.0),
    ]);
    for footprint in [u, plus] {
        for roof in [
            roof_hip(&footprint, 45.0, 0.0).unwrap(),
            roof_gable(&footprint, 45.0, 0.0).unwrap(),
        ] {
            assert_solid(&roof);
            // Every arm is 2 wide: the ridges are at height 1.
            assert_close(max_y(&roof), t, EPS);
        }
        assert_faces_on_slopes(&roof_hip(&footprint, 45.0, 0.0).unwrap(), &footprint, t);
    }
}

/// Checks a hip roof against its footprint: apart from the bottom, every face starts with a
/// footprint edge and lies in the plane rising from it at the slope, and the faces' shadows on the
/// footprint are counter-clockwise and add up to the footprint's area (they tile it).
fn assert_faces_on_slopes(roof: &Mesh, footprint: &[DVec3], slope: f64) {
    let normal = newell(footprint.iter().copied()).normalize();
    let size = roof.bounds().unwrap().diagonal();
    let mut shadow = 0.0;
    let mut roof_faces = 0;
    for f in 0..roof.face_count() {
        let points: Vec<DVec3> = roof.face_points(f).collect();
        if roof.face_normal(f).dot(normal) < -0.999_999 {
            continue;
        }
        roof_faces += 1;
        let (a, b) = (points[0], points[1]);
        let out = (b - a).normalize().cross(normal);
        for p in &points {
            let height = (*p - a).dot(normal);
            let inward = -(*p - a).dot(out);
            // Distance from the slope plane; steep roofs magnify rounding in height.
            let off = (height - slope * inward) / (1.0 + slope * slope).sqrt();
            assert!(
                off.abs() < 1e-8 * size,
                "face {f}: {p} is off its slope by {:e} (size {size})",
                height - slope * inward
            );
        }
        let area = newell(points.iter().copied()).dot(normal) * 0.5;
        assert!(area > 0.0, "face {f} folds over");
        shadow += area;
    }
    assert!(roof_faces >= 3);
    assert_close(shadow, polygon_area(footprint), 1e-9);
}

/// The roof as the intersection of the footprint's prism with the half-spaces under every edge's
/// slope plane: the hip roof of a convex footprint by plane cuts, an independent check.
fn hip_by_cuts(footprint: &[DVec3], slope: f64) -> Mesh {
    let normal = newell(footprint.iter().copied()).normalize();
    let size = shapegram_geom::Aabb::from_points(footprint.iter().copied())
        .unwrap()
        .diagonal();
    let mut solid = extrude_polygon(footprint, 2.0 * slope * size).unwrap();
    let n = footprint.len();
    for i in 0..n {
        let (a, b) = (footprint[i], footprint[(i + 1) % n]);
        let out = (b - a).normalize().cross(normal);
        solid = split(&solid, &Plane::from_point_normal(a, normal + out * slope)).0;
    }
    solid
}

/// A convex polygon: corners on an ellipse at sorted random angles, turned and moved.
fn convex_footprint() -> impl Strategy<Value = Vec<DVec3>> {
    (
        prop::collection::vec(0.0..1.0f64, 3..12),
        1.0..20.0f64,
        1.0..20.0f64,
        any::<bool>(),
    )
        .prop_filter_map("too thin", |(mut angles, rx, rz, flip)| {
            angles.sort_by(f64::total_cmp);
            let mut points: Vec<DVec3> = angles
                .iter()
                .map(|a| {
                    let a = a * std::f64::consts::TAU;
                    DVec3::new(rx * a.cos(), 0.0, -rz * a.sin())
                })
                .collect();
            points.dedup_by(|a, b| a.distance(*b) < 1e-3);
            if flip {
                points = points.iter().map(|p| DVec3::new(p.x, -p.z, 0.0)).collect();
                points.reverse();
            }
            (points.len() >= 3 && polygon_area(&points) > 0.5).then_some(points)
        })
}

/// A rectilinear "skyline": columns of random widths and heights on a common base, with the
/// many simultaneous events rectilinear footprints bring (equal heights are common).
fn skyline_footprint() -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec((1..4u8, 1..5u8), 1..7).prop_map(|columns| {
        let mut outline = vec![(0.0, 0.0)];
        let mut x = 0.0;
        let mut top = Vec::new();
        for (width, height) in columns {
            top.push((x, f64::from(height)));
            x += f64::from(width);
            top.push((x, f64::from(height)));
        }
        outline.push((x, 0.0));
        outline.extend(top.iter().rev());
        // Neighbouring columns of equal height leave corners on a straight line; roofs drop them.
        let points: Vec<(f64, f64)> = outline;
        footprint_loop(&points)
    })
}

/// A random polyomino outline (see [`common::polyomino`]).
fn polyomino_footprint() -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec((0..64usize, 0..4u8), 1..24)
        .prop_filter_map("holes or corner contacts", |choices| polyomino(&choices))
}

fn posed(points: &[DVec3], angles: DVec3, shift: DVec3) -> Vec<DVec3> {
    let turn = DAffine3::from_rotation_translation(
        DQuat::from_euler(glam::EulerRot::XYZ, angles.x, angles.y, angles.z),
        shift,
    );
    points.iter().map(|&p| turn.transform_point3(p)).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn hip_and_gable_of_polyominoes(
        footprint in polyomino_footprint(),
        angle in 5.0..85.0f64,
        overhang in 0.0..0.7f64,
        angles in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
    ) {
        let footprint = posed(&footprint, angles.into(), DVec3::new(-30.0, 12.0, 5.0));
        let hip = roof_hip(&footprint, angle, 0.0).unwrap();
        assert_solid(&hip);
        assert_faces_on_slopes(&hip, &footprint, tan(angle));
        assert_solid(&roof_gable(&footprint, angle, 0.0).unwrap());
        assert_solid(&roof_hip(&footprint, angle, overhang).unwrap());
        assert_solid(&roof_gable(&footprint, angle, overhang).unwrap());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn hip_of_convex_footprints_is_the_intersection_of_slopes(
        footprint in convex_footprint(),
        angle in 5.0..85.0f64,
        angles in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
        shift in (-50.0..50.0f64, -50.0..50.0f64, -50.0..50.0f64),
    ) {
        let footprint = posed(&footprint, angles.into(), shift.into());
        let slope = tan(angle);
        let roof = roof_hip(&footprint, angle, 0.0).unwrap();
        assert_solid(&roof);
        assert_convex_outward(&roof);
        assert_faces_on_slopes(&roof, &footprint, slope);
        let cut = hip_by_cuts(&footprint, slope);
        assert_close(roof.signed_volume(), cut.signed_volume(), 1e-7);
        // Every vertex stands over the footprint, on its upper side.
        let normal = newell(footprint.iter().copied()).normalize();
        let n = footprint.len();
        let size = roof.bounds().unwrap().diagonal();
        for p in roof.positions() {
            prop_assert!((*p - footprint[0]).dot(normal) >= -1e-9 * size);
            for i in 0..n {
                let (a, b) = (footprint[i], footprint[(i + 1) % n]);
                let out = (b - a).normalize().cross(normal);
                prop_assert!((*p - a).dot(out) <= 1e-9 * size);
            }
        }
    }

    #[test]
    fn other_roofs_of_convex_footprints_are_closed(
        footprint in convex_footprint(),
        angle in 5.0..85.0f64,
        overhang in 0.0..2.0f64,
        edge in 0..12usize,
    ) {
        let gable = roof_gable(&footprint, angle, 0.0).unwrap();
        assert_solid(&gable);
        assert_convex_outward(&gable);
        let pyramid = roof_pyramid(&footprint, angle).unwrap();
        assert_solid(&pyramid);
        assert_convex_outward(&pyramid);
        let shed = roof_shed(&footprint, angle, edge % footprint.len()).unwrap();
        assert_solid(&shed);
        assert_convex_outward(&shed);
        for roof in [
            roof_hip(&footprint, angle, overhang).unwrap(),
            roof_gable(&footprint, angle, overhang).unwrap(),
        ] {
            assert_solid(&roof);
            assert_convex_outward(&roof);
        }
    }

    #[test]
    fn hip_and_gable_of_star_shaped_footprints(
        footprint in star_footprint(),
        angle in 5.0..85.0f64,
        overhang in 0.0..1.0f64,
    ) {
        let slope = tan(angle);
        let hip = roof_hip(&footprint, angle, 0.0).unwrap();
        assert_solid(&hip);
        assert_faces_on_slopes(&hip, &footprint, slope);
        assert_solid(&roof_gable(&footprint, angle, 0.0).unwrap());
        // Star-shaped about some point, not necessarily about the centroid.
        if let Some(pyramid) = roof_pyramid(&footprint, angle) {
            assert_solid(&pyramid);
        }
        if let Some(roof) = roof_hip(&footprint, angle, overhang) {
            assert_solid(&roof);
        }
    }

    #[test]
    fn hip_and_gable_of_rectilinear_footprints(
        footprint in skyline_footprint(),
        angle in 5.0..85.0f64,
        overhang in 0.0..1.0f64,
        angles in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
    ) {
        let footprint = posed(&footprint, angles.into(), DVec3::new(3.0, -7.0, 11.0));
        let slope = tan(angle);
        let hip = roof_hip(&footprint, angle, 0.0).unwrap();
        assert_solid(&hip);
        assert_faces_on_slopes(&hip, &footprint, slope);
        assert_solid(&roof_gable(&footprint, angle, 0.0).unwrap());
        assert_solid(&roof_hip(&footprint, angle, overhang).unwrap());
        assert_solid(&roof_gable(&footprint, angle, overhang).unwrap());
    }
}

/// A sliver of a footprint found by the convex property test: three corners a few millimetres
/// apart, almost on a line. The base must not be fanned from one of them into a needle.
#[test]
fn hip_over_corners_almost_on_a_line_has_no_needles() {
    let footprint = [
        DVec3::new(18.889268016327282, 0.0, 0.0),
        DVec3::new(15.985431771436359, 0.0, -0.5327533275181169),
        DVec3::new(-14.689572887081614, 0.0, 0.62867559849551),
        DVec3::new(-14.686822132740451, 0.0, 0.628855693326597),
        DVec3::new(-14.684456323711773, 0.0, 0.629010517163806),
    ];
    let roof = roof_hip(&footprint, 5.0, 0.0).unwrap();
    assert_solid(&roof);
    assert_convex_outward(&roof);
    assert_faces_on_slopes(&roof, &footprint, tan(5.0));
    assert_eq!(roof.face_count(), 6);
}

#[test]
fn roof_runs_relate_height_and_angle() {
    use shapegram_geom::roof::{Gable, RoofShape, roof_gable_with, roof_run};
    let rect = rectangle(10.0, 4.0);
    let run = |shape| roof_run(&rect, shape).unwrap();
    assert!((run(RoofShape::Hip) - 2.0).abs() < 1e-12);
    assert!((run(RoofShape::Gable(None)) - 2.0).abs() < 1e-12);
    assert!((run(RoofShape::Gable(Some(1))) - 5.0).abs() < 1e-12);
    assert!((run(RoofShape::Pyramid) - 2.0).abs() < 1e-12);
    assert!((run(RoofShape::Shed(0)) - 4.0).abs() < 1e-12);
    assert!((run(RoofShape::Shed(1)) - 10.0).abs() < 1e-12);
    // Separate overhangs: 1 m at the eaves, 2 m at the gable ends, over a 10 × 4 m rectangle.
    let roof = roof_gable_with(
        &rect,
        45.0,
        &Gable {
            overhang_x: 1.0,
            overhang_y: 2.0,
            ridge_edge: None,
        },
    )
    .unwrap();
    let bounds = roof.bounds().unwrap();
    assert!((bounds.max - bounds.min - DVec3::new(14.0, 3.0, 6.0)).length() < 1e-9);
    assert!(roof.is_watertight());
}
