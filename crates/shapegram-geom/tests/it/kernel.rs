//! Scopes, extrusion, offsets, components, triangulation, welding and colours.

use crate::common;

use shapegram_geom::{
    Color, ComponentKind, DMat3, DQuat, DVec3, FaceClass, Mesh, Pivot, Scope, component,
    extrude::{extrude_face, extrude_polygon},
    offset::offset_convex,
    primitives::{cuboid, quad},
    triangulate::Triangulator,
};

fn close(a: DVec3, b: DVec3) -> bool {
    a.abs_diff_eq(b, 1e-9)
}

#[test]
fn scope_round_trips_points() {
    let mut s = Scope::axis_aligned(DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 6.0));
    s.rotate_euler_degrees(DVec3::new(10.0, 20.0, 30.0), Pivot::Origin);
    let p = DVec3::new(0.3, -2.0, 7.5);
    assert!(close(s.to_local(s.to_world(p)), p));
    assert!(close(s.world_to_local().transform_point3(s.to_world(p)), p));
    assert!((s.axes.determinant() - 1.0).abs() < 1e-12);
}

#[test]
fn scope_rotation_about_centre_keeps_centre() {
    let mut s = Scope::axis_aligned(DVec3::ZERO, DVec3::new(4.0, 2.0, 2.0));
    let center = s.center();
    s.rotate_euler_degrees(DVec3::new(0.0, 90.0, 0.0), Pivot::Center);
    assert!(close(s.center(), center));
    // Turning 90° about y takes x to −z.
    assert!(close(s.x_axis(), -DVec3::Z));
    assert!(close(s.z_axis(), DVec3::X));
    let mut t = Scope::axis_aligned(DVec3::ZERO, DVec3::ONE);
    t.rotate_euler_degrees(DVec3::new(0.0, 90.0, 0.0), Pivot::Origin);
    assert!(close(t.origin, DVec3::ZERO));
}

#[test]
fn scope_rotations_are_intrinsic() {
    // r(90, 90, 0): after turning about x, the y turn is about the new y axis (old z).
    let mut s = Scope::axis_aligned(DVec3::ZERO, DVec3::ONE);
    s.rotate_euler_degrees(DVec3::new(90.0, 90.0, 0.0), Pivot::Origin);
    let expected = DMat3::from_quat(DQuat::from_rotation_x(90f64.to_radians()))
        * DMat3::from_quat(DQuat::from_rotation_y(90f64.to_radians()));
    assert!(s.axes.abs_diff_eq(expected, 1e-12));
}

#[test]
fn scope_translate_scale_and_centre() {
    let mut s = Scope::axis_aligned(DVec3::ZERO, DVec3::new(2.0, 2.0, 2.0));
    s.rotate_euler_degrees(DVec3::new(0.0, 90.0, 0.0), Pivot::Origin);
    s.translate(DVec3::new(1.0, 0.0, 0.0));
    assert!(close(s.origin, DVec3::new(0.0, 0.0, -1.0)));
    s.scale(DVec3::new(0.5, 1.0, 1.0), Pivot::Center);
    assert!(close(s.size, DVec3::new(1.0, 2.0, 2.0)));
    assert!(close(s.origin, DVec3::new(0.0, 0.0, -1.5)));
    s.center_on(DVec3::new(10.0, 10.0, 10.0), [true, false, false]);
    assert!((s.center().z - 10.0).abs() < 1e-9);
    assert!((s.center().y - 1.0).abs() < 1e-9);
    assert_eq!(s.volume(), 4.0);
    let corners = s.corners();
    assert!(corners.iter().all(|&c| s.contains(c, 1e-9)));
    assert!(!s.contains(DVec3::new(100.0, 0.0, 0.0), 1e-9));
}

#[test]
fn scope_fit_and_world_alignment() {
    let axes = DMat3::from_cols(DVec3::Z, DVec3::Y, -DVec3::X);
    let points = [DVec3::new(0.0, 0.0, 0.0), DVec3::new(-3.0, 2.0, 5.0)];
    let s = Scope::fit(axes, points);
    assert!(close(s.size, DVec3::new(5.0, 2.0, 3.0)));
    assert!(points.iter().all(|&p| s.contains(p, 1e-9)));
    let w = s.aligned_to_world();
    assert_eq!(w.axes, DMat3::IDENTITY);
    assert!(close(w.origin, DVec3::new(-3.0, 0.0, 0.0)));
    assert!(close(w.size, DVec3::new(3.0, 2.0, 5.0)));
    let unit = s.unit_cube_to_world();
    assert!(close(unit.transform_point3(DVec3::ONE), s.to_world(s.size)));
}

#[test]
fn extruded_polygon_is_a_closed_prism() {
    let points: Vec<DVec3> = quad(2.0, 3.0).face_points(0).collect();
    let up = extrude_polygon(&points, 4.0).unwrap();
    assert!(up.is_watertight());
    assert_eq!(up.signed_volume(), 24.0);
    assert_eq!(up.bounds().unwrap().max, DVec3::new(2.0, 4.0, 3.0));
    let down = extrude_polygon(&points, -4.0).unwrap();
    assert!(down.is_watertight());
    assert_eq!(down.signed_volume(), 24.0);
    assert_eq!(down.bounds().unwrap().min, DVec3::new(0.0, -4.0, 0.0));
    assert!(extrude_polygon(&points, 0.0).is_none());
    assert!(extrude_polygon(&points, f64::NAN).is_none());
    let l = common::l_prism();
    assert!(l.is_watertight());
    assert_eq!(l.signed_volume(), 36.0);
}

#[test]
fn extruding_a_face_keeps_the_mesh_closed() {
    let b = cuboid(DVec3::ONE);
    let top = (0..6).find(|&f| b.face_normal(f) == DVec3::Y).unwrap();
    let taller = extrude_face(&b, top, 2.0);
    assert!(taller.is_watertight());
    assert!((taller.signed_volume() - 3.0).abs() < 1e-12);
    let dented = extrude_face(&b, top, -0.25);
    assert!(dented.is_watertight());
    assert!((dented.signed_volume() - 0.75).abs() < 1e-12);
}

#[test]
fn inset_and_outset_of_convex_polygons() {
    let square: Vec<DVec3> = quad(10.0, 10.0).face_points(0).collect();
    let inset = offset_convex(&square, -1.0).unwrap();
    assert_eq!(Mesh::from_polygon(&inset).area(), 64.0);
    assert_eq!(Mesh::from_polygon(&inset).face_normal(0), DVec3::Y);
    let outset = offset_convex(&square, 1.0).unwrap();
    assert_eq!(outset.len(), 4);
    assert!((Mesh::from_polygon(&outset).area() - 144.0).abs() < 1e-9);
    assert!(offset_convex(&square, -5.0).is_none());
    assert!(offset_convex(&square, -6.0).is_none());
    // A thin rectangle insets to a point-free nothing before the square does.
    let thin: Vec<DVec3> = quad(10.0, 2.0).face_points(0).collect();
    assert!(offset_convex(&thin, -1.5).is_none());
    let strip = offset_convex(&thin, -0.5).unwrap();
    assert!((Mesh::from_polygon(&strip).area() - 9.0).abs() < 1e-12);
    // Collinear corners do not add corners to the result.
    let with_midpoint = [
        DVec3::ZERO,
        DVec3::new(0.0, 0.0, 4.0),
        DVec3::new(2.0, 0.0, 4.0),
        DVec3::new(4.0, 0.0, 4.0),
        DVec3::new(4.0, 0.0, 0.0),
    ];
    assert_eq!(offset_convex(&with_midpoint, 1.0).unwrap().len(), 4);
}

#[test]
fn box_faces_classify_once_each_with_right_handed_frames() {
    let b = cuboid(DVec3::new(2.0, 3.0, 4.0));
    let reference = Scope::axis_aligned(DVec3::ZERO, DVec3::new(2.0, 3.0, 4.0));
    let faces = component::faces(&b);
    assert_eq!(faces.len(), 6);
    let mut names: Vec<&str> = faces
        .iter()
        .map(|c| FaceClass::of(c.normal, &reference).name())
        .collect();
    names.sort();
    assert_eq!(names, ["back", "bottom", "front", "left", "right", "top"]);
    for c in &faces {
        assert_eq!(c.kind, ComponentKind::Face);
        assert!((c.scope.axes.determinant() - 1.0).abs() < 1e-12);
        assert!(close(c.scope.z_axis(), c.normal));
        assert_eq!(c.scope.size.z, 0.0);
        assert!(c.points.iter().all(|&p| c.scope.contains(p, 1e-9)));
        assert!(
            (c.scope.size.x * c.scope.size.y - Mesh::from_polygon(&c.points).area()).abs() < 1e-12
        );
    }
    let front = faces
        .iter()
        .find(|c| FaceClass::of(c.normal, &reference) == FaceClass::Front);
    // The front face's first edge runs along the ground, so its y axis is world up.
    assert!(close(front.unwrap().scope.y_axis(), DVec3::Y));
    assert!(FaceClass::Front.is_side() && !FaceClass::Top.is_side());
}

#[test]
fn classification_follows_the_reference_scope_and_breaks_ties_towards_y() {
    let mut turned = Scope::axis_aligned(DVec3::ZERO, DVec3::ONE);
    turned.rotate_euler_degrees(DVec3::new(0.0, 90.0, 0.0), Pivot::Origin);
    assert_eq!(FaceClass::of(DVec3::X, &turned), FaceClass::Front);
    assert_eq!(FaceClass::of(-DVec3::Z, &turned), FaceClass::Right);
    let world = Scope::default();
    assert_eq!(
        FaceClass::of(DVec3::new(1.0, 1.0, 0.0), &world),
        FaceClass::Top
    );
    assert_eq!(
        FaceClass::of(DVec3::new(1.0, 0.0, -1.0), &world),
        FaceClass::Back
    );
    assert_eq!(
        FaceClass::of(DVec3::new(-1.0, 0.2, 0.1), &world),
        FaceClass::Left
    );
}

#[test]
fn edges_and_vertices_of_a_box() {
    let b = cuboid(DVec3::ONE);
    let edges = component::edges(&b);
    assert_eq!(edges.len(), 12);
    for e in &edges {
        assert_eq!(e.kind, ComponentKind::Edge);
        assert!(close(e.scope.size, DVec3::new(1.0, 0.0, 0.0)));
        assert!(close(e.scope.to_world(DVec3::ZERO), e.points[0]));
        // The mean normal of two perpendicular faces leans out at 45°.
        assert!((e.normal.length() - 1.0).abs() < 1e-12);
        assert!(e.scope.x_axis().dot(e.normal).abs() < 1e-12);
    }
    let vertices = component::vertices(&b);
    assert_eq!(vertices.len(), 8);
    for v in &vertices {
        let outward = (v.points[0] - DVec3::splat(0.5)).normalize();
        assert!(close(v.normal, outward));
        assert!(close(v.scope.z_axis(), outward));
        assert!((v.scope.axes.determinant() - 1.0).abs() < 1e-12);
    }
}

#[test]
fn triangulates_non_convex_polygons_and_holes() {
    let l = common::l_prism();
    let triangles = l.triangulate();
    let area: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| l.position(i));
            (b - a).cross(c - a).length() * 0.5
        })
        .sum();
    assert!((area - l.area()).abs() < 1e-12);
    assert_eq!(l.degenerate_triangle_count(1e-12), 0);
    let square = |r: f64| [(-r, -r), (r, -r), (r, r), (-r, r)].map(|(x, y)| DVec3::new(x, y, 0.0));
    let mut points = square(2.0).to_vec();
    points.extend(square(1.0).iter().rev());
    let t = Triangulator::new().triangulate(&points, &[4]);
    assert_eq!(t.len(), 8);
    for tri in t {
        let [a, b, c] = tri.map(|i| points[i as usize]);
        assert!(
            (b - a).cross(c - a).z > 0.0,
            "triangles wind like the outer loop"
        );
    }
}

#[test]
fn welding_recovers_a_watertight_mesh_from_a_triangle_soup() {
    let b = cuboid(DVec3::new(1.0, 2.0, 3.0));
    let mut soup = Mesh::new();
    for t in b.triangulate() {
        let ids = t.map(|i| soup.add_vertex(b.position(i) + DVec3::splat(1e-12)));
        soup.add_face(&ids);
    }
    assert_eq!(soup.vertex_count(), 36);
    assert_eq!(soup.edge_report().boundary, 36);
    let welded = soup.welded(1e-6);
    assert_eq!(welded.vertex_count(), 8);
    assert!(welded.is_watertight());
    assert!((welded.signed_volume() - 6.0).abs() < 1e-9);
}

#[test]
fn mirroring_transform_keeps_normals_outward() {
    let b = cuboid(DVec3::ONE);
    let mirrored = b.transformed(&shapegram_geom::DAffine3::from_scale(DVec3::new(
        -1.0, 1.0, 1.0,
    )));
    assert_eq!(mirrored.signed_volume(), 1.0);
    assert!(mirrored.is_watertight());
}

#[test]
fn colours_parse_and_print_as_hex() {
    assert_eq!(Color::from_hex("#3a6ea5").unwrap().to_hex(), "#3a6ea5");
    assert_eq!(Color::from_hex("fff").unwrap(), Color::rgb(1.0, 1.0, 1.0));
    assert_eq!(Color::from_hex("#00000080").unwrap().to_hex(), "#00000080");
    let c = Color::from_hex("#3a6ea5").unwrap();
    let linear = c.to_linear();
    // sRGB 0x3a = 58/255 is about 0.0423 in linear light; mid grey 0.5 is about 0.214.
    assert!((linear[0] - 0.042311).abs() < 1e-5, "{linear:?}");
    assert!((Color::rgb(0.5, 0.5, 0.5).to_linear()[1] - 0.214041).abs() < 1e-5);
    assert_eq!(Color::from_linear(linear).to_hex(), "#3a6ea5");
    for bad in ["", "#12", "#ggg", "#12345", "#ééé"] {
        assert_eq!(Color::from_hex(bad), None, "{bad}");
    }
}

#[test]
fn fine_circles_triangulate_without_holes() {
    let disc = shapegram_geom::primitives::cylinder(DVec3::new(2.0, 1.0, 2.0), 100_000);
    let top = (0..2).find(|&f| disc.face_normal(f) == DVec3::Y).unwrap();
    let cap = Mesh::from_faces(disc.positions().to_vec(), [disc.face(top)]);
    let triangles = cap.triangulate();
    assert_eq!(triangles.len(), 100_000 - 2);
    let area: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| cap.position(i));
            (b - a).cross(c - a).length() * 0.5
        })
        .sum();
    assert!((area - cap.area()).abs() < 1e-9 * cap.area());
}

#[test]
fn welding_with_zero_or_tiny_tolerance_merges_only_equal_positions() {
    let far = DVec3::splat(1e12);
    let points = [
        far,
        far,
        far + DVec3::X * 1e-3,
        DVec3::ZERO,
        DVec3::new(-0.0, 0.0, 0.0),
    ];
    let mut soup = Mesh::new();
    for p in points {
        soup.add_vertex(p);
    }
    assert_eq!(soup.welded(0.0).vertex_count(), 3);
    soup.add_face(&[0, 1, 2]);
    soup.add_face(&[3, 4, 2]);
    let welded = soup.welded(1e-300);
    // 0 and 1 merge, 3 and 4 (zero and negative zero) merge; the faces collapse to edges.
    assert_eq!(welded.face_count(), 0);
    assert_eq!(welded.vertex_count(), 3);
}

#[test]
fn an_empty_mesh_has_no_area_and_no_volume() {
    let empty = Mesh::new();
    // Positive zero: JSON reports and text output print "-0" otherwise.
    assert!(empty.area() == 0.0 && empty.area().is_sign_positive());
    assert!(empty.signed_volume() == 0.0 && empty.signed_volume().is_sign_positive());
}

#[test]
fn concave_polygons_fall_into_convex_pieces() {
    use shapegram_geom::{DVec3, Mesh, convex::convex_pieces, triangulate::is_convex};
    let at = |x: f64, z: f64| DVec3::new(x, 0.0, z);
    // An L, counter-clockwise seen from above (+y): one reflex corner at (1, 1).
    let l = [
        at(0.0, 0.0),
        at(0.0, 2.0),
        at(2.0, 2.0),
        at(2.0, 1.0),
        at(1.0, 1.0),
        at(1.0, 0.0),
    ];
    assert!(Mesh::from_polygon(&l).face_normal(0).y > 0.0);
    let pieces = convex_pieces(&l, None);
    assert_eq!(pieces.len(), 2, "{pieces:?}");
    let areas: Vec<f64> = pieces
        .iter()
        .map(|p| Mesh::from_polygon(p).area())
        .collect();
    assert!((areas.iter().sum::<f64>() - 3.0).abs() < 1e-12, "{areas:?}");
    for piece in &pieces {
        assert!(is_convex(piece), "{piece:?}");
        assert!(Mesh::from_polygon(piece).face_normal(0).y > 0.0);
        // Only the polygon's own corners.
        assert!(piece.iter().all(|p| l.contains(p)));
    }
    // A convex polygon stays whole, its corner on a straight line dropped.
    let square = [
        at(0.0, 0.0),
        at(0.0, 2.0),
        at(1.0, 2.0),
        at(2.0, 2.0),
        at(2.0, 0.0),
    ];
    assert_eq!(
        convex_pieces(&square, None),
        vec![vec![at(0.0, 0.0), at(0.0, 2.0), at(2.0, 2.0), at(2.0, 0.0)]]
    );
    // A cut no shorter than 1 m is not made: the L stays whole.
    assert_eq!(convex_pieces(&l, Some(1.0)).len(), 1);
    assert_eq!(convex_pieces(&l, Some(1.5)).len(), 2);
    // A comb with three teeth has four reflex corners and needs three convex pieces at least.
    let comb = [
        at(0.0, 0.0),
        at(0.0, 3.0),
        at(1.0, 3.0),
        at(1.0, 1.0),
        at(2.0, 1.0),
        at(2.0, 3.0),
        at(3.0, 3.0),
        at(3.0, 1.0),
        at(4.0, 1.0),
        at(4.0, 3.0),
        at(5.0, 3.0),
        at(5.0, 0.0),
    ];
    let pieces = convex_pieces(&comb, None);
    let total: f64 = pieces.iter().map(|p| Mesh::from_polygon(p).area()).sum();
    assert!((total - 11.0).abs() < 1e-12);
    assert!(pieces.iter().all(|p| is_convex(p)));
    assert!((3..=5).contains(&pieces.len()), "{}", pieces.len());
}

#[test]
fn the_largest_inner_rectangle_and_what_is_around_it() {
    use shapegram_geom::{
        DVec3, Mesh,
        inner_rectangle::{around_rectangle, inner_rectangle},
    };
    let at = |x: f64, z: f64| DVec3::new(x, 0.0, z);
    let area = |p: &[DVec3]| Mesh::from_polygon(p).area();
    // A right triangle with legs of 20 m along x and 30 m along z: the rectangle sits in the
    // right angle, half of each leg long, half the triangle's area.
    let triangle = [at(0.0, 0.0), at(0.0, 30.0), at(20.0, 0.0)];
    let rectangle = inner_rectangle(&triangle, DVec3::X).unwrap();
    let (lo, hi) = rectangle.iter().fold(
        (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    assert!(
        lo.abs_diff_eq(at(0.0, 0.0), 1e-9) && hi.abs_diff_eq(at(10.0, 15.0), 1e-9),
        "{rectangle:?}"
    );
    let around = around_rectangle(&triangle, &rectangle);
    let rest: f64 = around.iter().map(|p| area(p)).sum();
    assert!((rest - (300.0 - 150.0)).abs() < 1e-9, "{around:?}");
    // An L of 20 × 10 and 10 × 20 m: the 10 × 30 m wing with the corner under it.
    let l = [
        at(0.0, 0.0),
        at(0.0, 30.0),
        at(10.0, 30.0),
        at(10.0, 10.0),
        at(20.0, 10.0),
        at(20.0, 0.0),
    ];
    let rectangle = inner_rectangle(&l, DVec3::X).unwrap();
    assert!((area(&rectangle) - 300.0).abs() < 1e-9, "{rectangle:?}");
    let around = around_rectangle(&l, &rectangle);
    assert_eq!(around.len(), 1);
    assert!((area(&around[0]) - 100.0).abs() < 1e-9);
    // In a square turned 45°, the largest rectangle along x is a square of half its area; along
    // an edge, it is the square itself.
    let diamond = [at(0.0, -1.0), at(-1.0, 0.0), at(0.0, 1.0), at(1.0, 0.0)];
    let rectangle = inner_rectangle(&diamond, DVec3::X).unwrap();
    assert!(
        (area(&rectangle) - 1.0).abs() < 1e-9,
        "{}",
        area(&rectangle)
    );
    let along_edge = inner_rectangle(&diamond, DVec3::new(1.0, 0.0, 1.0)).unwrap();
    assert!(
        (area(&along_edge) - 2.0).abs() < 1e-9,
        "{}",
        area(&along_edge)
    );
}
