//! Primitives are closed, outward-facing and have the volumes and areas their docs promise.

use std::f64::consts::PI;

use shapegram_geom::{DVec2, DVec3, Mesh, primitives::*};

/// Every face normal points away from the solid's centre (true for the convex primitives).
fn faces_point_outward(mesh: &Mesh) -> bool {
    let center = mesh.bounds().unwrap().center();
    (0..mesh.face_count()).all(|f| mesh.face_normal(f).dot(mesh.face_centroid(f) - center) > 0.0)
}

fn assert_closed_solid(mesh: &Mesh) {
    let report = mesh.edge_report();
    assert!(report.is_watertight(), "{report:?}");
    assert!(faces_point_outward(mesh));
    assert_eq!(mesh.degenerate_triangle_count(1e-12), 0);
}

#[test]
fn cuboid_is_exact() {
    let m = cuboid(DVec3::new(10.0, 20.0, 5.0));
    assert_closed_solid(&m);
    assert_eq!((m.vertex_count(), m.face_count()), (8, 6));
    assert_eq!(m.signed_volume(), 1000.0);
    assert_eq!(m.area(), 700.0);
    let b = m.bounds().unwrap();
    assert_eq!((b.min, b.max), (DVec3::ZERO, DVec3::new(10.0, 20.0, 5.0)));
    assert_eq!(m.triangulate().len(), 12);
}

#[test]
fn cylinder_volume_matches_formula_and_converges() {
    let size = DVec3::new(2.0, 5.0, 2.0);
    for sides in [3, 8, 64] {
        let m = cylinder(size, sides);
        assert_closed_solid(&m);
        assert_eq!(m.face_count(), sides as usize + 2);
        let exact = cylinder_volume(size, sides);
        assert!((m.signed_volume() - exact).abs() < 1e-12 * exact);
    }
    let smooth = PI * 5.0;
    let relative = 1.0 - cylinder_volume(size, 64) / smooth;
    assert!(relative > 0.0 && relative < 0.0017, "{relative}");
}

#[test]
fn elliptic_cylinder_fills_its_box() {
    let m = cylinder(DVec3::new(4.0, 1.0, 2.0), 4);
    let b = m.bounds().unwrap();
    assert_eq!((b.min, b.max), (DVec3::ZERO, DVec3::new(4.0, 1.0, 2.0)));
    // A 4-sided "cylinder" is the rhombus through the edge midpoints: half the box.
    assert!((m.signed_volume() - 4.0).abs() < 1e-12);
}

#[test]
fn sphere_volume_matches_formula_and_converges() {
    let size = DVec3::splat(2.0);
    for (s, r) in [(3, 2), (8, 4), (32, 16)] {
        let m = sphere(size, s, r);
        assert_closed_solid(&m);
        assert_eq!(m.vertex_count(), (s * (r - 1) + 2) as usize);
        let exact = sphere_volume(size, s, r);
        assert!((m.signed_volume() - exact).abs() < 1e-12, "{s}x{r}");
    }
    let relative = 1.0 - sphere_volume(size, 32, 16) / (4.0 / 3.0 * PI);
    assert!(relative > 0.0 && relative < 0.02, "{relative}");
}

#[test]
fn cone_and_pyramid_are_a_third_of_their_prisms() {
    let size = DVec3::new(3.0, 6.0, 3.0);
    let c = cone(size, 16);
    assert_closed_solid(&c);
    assert!((c.signed_volume() - cylinder_volume(size, 16) / 3.0).abs() < 1e-12);
    let p = pyramid(size);
    assert_closed_solid(&p);
    assert!((p.signed_volume() - 18.0).abs() < 1e-12);
}

#[test]
fn quads_and_footprints_face_up() {
    let q = quad(4.0, 3.0);
    assert_eq!(q.face_normal(0), DVec3::Y);
    assert_eq!(q.area(), 12.0);
    assert_eq!(q.edge_report().boundary, 4);
    assert!(!q.is_watertight());
    // Clockwise seen from above: reversed to face up.
    let l = [
        (0.0, 0.0),
        (0.0, 4.0),
        (2.0, 4.0),
        (2.0, 2.0),
        (4.0, 2.0),
        (4.0, 0.0),
    ];
    let f = footprint(&l.map(|(x, z)| DVec2::new(x, z))).unwrap();
    assert_eq!(f.face_normal(0), DVec3::Y);
    assert_eq!(f.area(), 12.0);
    assert_eq!(f.triangulate().len(), 4);
    let collinear = [DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)];
    assert!(footprint(&collinear).is_none());
    assert!(footprint(&collinear[..2]).is_none());
}
