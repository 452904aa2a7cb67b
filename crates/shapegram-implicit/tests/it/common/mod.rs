//! Helpers shared by the test files (each includes this with `mod common;`).
#![allow(dead_code)]

use shapegram_geom::Mesh;
use shapegram_implicit::{MeshOptions, Meshing, Solid, mesh};

/// Meshes `solid` with `cells` cells along the longest side of its bounds.
pub fn meshed(solid: &Solid, cells: usize) -> Meshing {
    mesh(solid, &MeshOptions::cells_along_longest(solid, cells)).unwrap()
}

/// Asserts the mesh is closed, manifold and consistently oriented with outward normals.
pub fn assert_closed_outward(mesh: &Mesh) {
    let report = mesh.edge_report();
    assert!(report.is_watertight(), "{report:?}");
    assert!(mesh.signed_volume() > 0.0, "normals point inward");
}

/// The smallest triangle area relative to the squared cell size.
pub fn smallest_relative_area(mesh: &Mesh, cell: f64) -> f64 {
    (0..mesh.face_count())
        .map(|f| mesh.face_area(f) / (cell * cell))
        .fold(f64::INFINITY, f64::min)
}

/// Relative error of `measured` against `exact`.
pub fn relative_error(measured: f64, exact: f64) -> f64 {
    (measured - exact).abs() / exact.abs()
}
