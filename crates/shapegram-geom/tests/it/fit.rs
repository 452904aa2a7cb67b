//! Fitting assets into scopes (CGA `i()`): stretching onto the box, orientation, mirrored scopes,
//! flat and point-like scopes, flat assets.

use shapegram_geom::{
    DAffine3, DMat3, DVec3, Mesh, Scope, component,
    fit::{fit_into_scope, fit_proportionally_into_scope, mesh_in_scope},
    primitives::{cuboid, quad},
};

const EPS: f64 = 1e-9;

/// A turned scope at (1, 2, 3).
fn turned(size: DVec3) -> Scope {
    let axes = DMat3::from_rotation_y(0.6) * DMat3::from_rotation_x(-0.3);
    Scope::new(DVec3::new(1.0, 2.0, 3.0), axes, size)
}

/// An asset away from the origin: a 1 × 2 × 4 box with its minimum corner at (5, −7, 2).
fn asset() -> Mesh {
    cuboid(DVec3::new(1.0, 2.0, 4.0))
        .transformed(&DAffine3::from_translation(DVec3::new(5.0, -7.0, 2.0)))
}

/// Bounds of a mesh in a scope's local coordinates.
fn local_bounds(mesh: &Mesh, scope: &Scope) -> (DVec3, DVec3) {
    let local = mesh.transformed(&scope.world_to_local());
    let b = local.bounds().unwrap();
    (b.min, b.max)
}

fn assert_vec_close(a: DVec3, b: DVec3) {
    assert!(a.distance(b) < EPS, "{a} != {b}");
}

#[test]
fn the_asset_box_fills_the_scope() {
    let scope = turned(DVec3::new(2.0, 3.0, 4.0));
    let fitted = fit_into_scope(&asset(), &scope);
    let (min, max) = local_bounds(&fitted, &scope);
    assert_vec_close(min, DVec3::ZERO);
    assert_vec_close(max, scope.size);
    assert!((fitted.signed_volume() - 24.0).abs() < EPS);
    assert!(fitted.is_watertight());
    // Corners map to corners: the asset's minimum corner lands on the scope's origin.
    assert!(
        fitted
            .positions()
            .iter()
            .any(|p| p.distance(scope.origin) < EPS)
    );
}

#[test]
fn a_mirrored_scope_keeps_normals_outward() {
    let mut scope = turned(DVec3::new(2.0, 3.0, 4.0));
    scope.size.x = -2.0;
    let fitted = fit_into_scope(&asset(), &scope);
    assert!((fitted.signed_volume() - 24.0).abs() < EPS);
    let (min, max) = local_bounds(&fitted, &scope);
    assert_vec_close(min, DVec3::new(-2.0, 0.0, 0.0));
    assert_vec_close(max, DVec3::new(0.0, 3.0, 4.0));
}

#[test]
fn zero_scope_sizes_keep_proportions() {
    // Flat scope (no height): y is scaled by the mean of the x and z factors, (2 + 1) / 2.
    let scope = turned(DVec3::new(2.0, 0.0, 4.0));
    let (min, max) = local_bounds(&fit_into_scope(&asset(), &scope), &scope);
    assert_vec_close(min, DVec3::ZERO);
    assert_vec_close(max, DVec3::new(2.0, 3.0, 4.0));
    // Line-like scope: uniform scaling to its one length (factor 3 / 2 along y).
    let scope = turned(DVec3::new(0.0, 3.0, 0.0));
    let (_, max) = local_bounds(&fit_into_scope(&asset(), &scope), &scope);
    assert_vec_close(max, DVec3::new(1.5, 3.0, 6.0));
    // A face scope has rounding noise for its depth; it still counts as flat.
    let wall = cuboid(DVec3::new(4.0, 3.0, 2.0)).transformed(&DAffine3::from_rotation_y(0.7));
    let face = &component::faces(&wall)[0];
    let (_, max) = local_bounds(&fit_into_scope(&asset(), &face.scope), &face.scope);
    assert!(max.z > 1.0, "depth {}", max.z);
}

#[test]
fn a_point_scope_keeps_the_asset_as_it_is() {
    let scope = turned(DVec3::ZERO);
    let fitted = fit_into_scope(&asset(), &scope);
    assert_eq!(fitted, mesh_in_scope(&asset(), &scope));
    for (p, q) in fitted.positions().iter().zip(asset().positions()) {
        assert_vec_close(*p, scope.to_world(*q));
    }
}

#[test]
fn flat_assets_stay_flat_without_dividing_by_zero() {
    // A 2 × 3 lot (flat along y) into a box: stretched in x and z, flat at the scope's floor.
    let scope = turned(DVec3::new(4.0, 5.0, 6.0));
    let fitted = fit_into_scope(&quad(2.0, 3.0), &scope);
    assert!(fitted.positions().iter().all(|p| p.is_finite()));
    let (min, max) = local_bounds(&fitted, &scope);
    assert_vec_close(min, DVec3::ZERO);
    assert_vec_close(max, DVec3::new(4.0, 0.0, 6.0));
    assert!((fitted.area() - 24.0).abs() < EPS);
    // A single point asset and an empty one.
    let point = Mesh::from_faces(vec![DVec3::ONE], std::iter::empty::<[u32; 0]>());
    let placed = fit_into_scope(&point, &scope);
    assert_vec_close(placed.positions()[0], scope.origin);
    assert!(fit_into_scope(&Mesh::new(), &scope).is_empty());
}

#[test]
fn mesh_in_scope_maps_local_to_world() {
    let scope = turned(DVec3::new(2.0, 3.0, 4.0));
    let placed = mesh_in_scope(&cuboid(scope.size), &scope);
    for corner in scope.corners() {
        assert!(placed.positions().iter().any(|p| p.distance(corner) < EPS));
    }
    assert!((placed.signed_volume() - scope.volume()).abs() < EPS);
}

#[test]
fn proportional_fits_keep_the_shape_centred_on_the_floor() {
    // The 1 × 2 × 4 asset in a 6 × 3 × 6 scope: z limits the scale to 1.5, so the asset is
    // 1.5 × 3 × 6, centred in x (2.25 on either side) and standing on y = 0.
    let scope = turned(DVec3::new(6.0, 3.0, 6.0));
    let fitted = fit_proportionally_into_scope(&asset(), &scope);
    let (min, max) = local_bounds(&fitted, &scope);
    assert_vec_close(min, DVec3::new(2.25, 0.0, 0.0));
    assert_vec_close(max, DVec3::new(3.75, 3.0, 6.0));
    // A flat scope axis does not limit the scale: y alone does (2 → 1).
    let flat = turned(DVec3::new(5.0, 1.0, 0.0));
    let (min, max) = local_bounds(&fit_proportionally_into_scope(&asset(), &flat), &flat);
    assert_vec_close(min, DVec3::new(2.25, 0.0, -1.0));
    assert_vec_close(max, DVec3::new(2.75, 1.0, 1.0));
    assert!(fit_proportionally_into_scope(&Mesh::new(), &scope).is_empty());
}
