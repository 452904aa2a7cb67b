//! Gradient normals of meshed CSG: unit, outward, equal to the field's gradient worked out point
//! by point, and the same whatever the thread count.

use crate::common;

use std::sync::atomic::{AtomicUsize, Ordering};

use common::meshed;
use glam::DVec3;
use shapegram_geom::Mesh;
use shapegram_implicit::{
    CaveParams, Solid, generate, surface_normals, surface_normals_with_progress,
};

/// A box with holes drilled through, bumps on top and a ball scooped out, morphed halfway
/// into its union with a ring: differences, unions, transforms and a morph.
fn scene() -> Solid {
    let mut s = Solid::cuboid(DVec3::new(4.0, 2.0, 2.0)).unwrap();
    for i in 0..4 {
        let x = i as f64 - 1.5;
        let hole = Solid::cylinder(0.3, 3.0)
            .unwrap()
            .rotate(DVec3::X, 90.0)
            .unwrap()
            .translate(DVec3::new(x, 0.3, 0.0))
            .unwrap();
        let bump = Solid::sphere(0.5)
            .unwrap()
            .translate(DVec3::new(x, 1.0, 0.0))
            .unwrap();
        s = s.difference(&hole).union(&bump);
    }
    let scoop = Solid::sphere(0.8)
        .unwrap()
        .translate(DVec3::new(2.0, -1.0, 1.0))
        .unwrap();
    s = s.difference(&scoop);
    let ring = Solid::torus(1.5, 0.4).unwrap();
    s.morph(&s.union(&ring), 0.5).unwrap()
}

/// The outward unit gradient at `p` by central differences over `h`, walking the solid's tree
/// (no tape, no pruning): what the normals must equal.
fn reference(solid: &Solid, p: DVec3, h: f64) -> DVec3 {
    let d = |axis: DVec3| solid.value(p + axis * h) - solid.value(p - axis * h);
    -DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z)).normalize()
}

/// Checks `normals` of `mesh` against [`reference`]; returns how many were compared.
fn assert_gradients(solid: &Solid, mesh: &Mesh, normals: &[DVec3], h: f64) -> usize {
    assert_eq!(normals.len(), mesh.vertex_count());
    for (p, n) in mesh.positions().iter().zip(normals) {
        let expected = reference(solid, *p, h);
        assert!((*n - expected).length() < 1e-9, "{p}: {n} vs {expected}");
    }
    normals.len()
}

#[test]
fn normals_are_the_fields_gradient_at_every_vertex() {
    let solid = scene();
    let m = meshed(&solid, 80);
    let h = m.grid.cell_size / 2.0;
    let normals = surface_normals(&solid, &m.mesh, h);
    assert!(assert_gradients(&solid, &m.mesh, &normals, h) > 20_000);
}

#[test]
fn normals_of_a_cave_are_the_fields_gradient() {
    // Forty-eight primitives spread along the cave: here pruning the tape matters.
    let cave = generate(&CaveParams {
        lod: 8,
        ..CaveParams::default()
    })
    .unwrap();
    let solid = cave.builder.solid();
    let m = shapegram_implicit::mesh(
        solid,
        &shapegram_implicit::MeshOptions::with_cell_size(1.0 / 8.0),
    )
    .unwrap();
    let h = m.grid.cell_size / 2.0;
    let normals = surface_normals(solid, &m.mesh, h);
    assert!(assert_gradients(solid, &m.mesh, &normals, h) > 5_000);
}

#[test]
fn normals_are_unit_and_point_out_of_a_box_and_ball_csg() {
    let cube = Solid::cuboid(DVec3::splat(2.0)).unwrap();
    let ball = Solid::sphere(1.3).unwrap();
    let pole = Solid::cylinder(0.4, 3.0).unwrap();
    for solid in [
        cube.intersection(&ball),
        cube.difference(&ball.translate(DVec3::splat(1.0)).unwrap()),
        cube.union(&pole)
            .difference(&ball.scale(DVec3::splat(0.5)).unwrap()),
    ] {
        let m = meshed(&solid, 60);
        let normals = surface_normals(&solid, &m.mesh, m.grid.cell_size / 2.0);
        let faces = m.mesh.vertex_normals();
        let mut aligned = 0;
        for ((p, n), f) in m.mesh.positions().iter().zip(&normals).zip(&faces) {
            assert!((n.length() - 1.0).abs() < 1e-12, "{p}: {n}");
            // Outward everywhere; at a right-angled crease the gradient follows one side while
            // the faces' mean leans between the two (cos 45°, less where the bevel tilts it).
            let dot = n.dot(*f);
            assert!(dot > 0.3, "{p}: {n} against faces {f}");
            aligned += usize::from(dot > 0.99);
        }
        assert!(
            aligned * 10 > normals.len() * 9,
            "{aligned} of {}",
            normals.len()
        );
    }
}

#[test]
fn normals_do_not_depend_on_thread_count() {
    let solid = scene();
    let m = meshed(&solid, 60);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| surface_normals(&solid, &m.mesh, m.grid.cell_size / 2.0))
    };
    let one = run(1);
    assert_eq!(run(2), one);
    assert_eq!(run(3), one);
}

#[test]
fn progress_counts_every_group() {
    let solid = scene();
    let m = meshed(&solid, 40);
    let (calls, last) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let total = AtomicUsize::new(0);
    let normals = surface_normals_with_progress(&solid, &m.mesh, 0.01, &|done, of| {
        calls.fetch_add(1, Ordering::Relaxed);
        last.fetch_max(done, Ordering::Relaxed);
        total.store(of, Ordering::Relaxed);
    });
    assert_eq!(normals.len(), m.mesh.vertex_count());
    let (calls, last, total) = (calls.into_inner(), last.into_inner(), total.into_inner());
    // Groups hold at most 256 vertices.
    assert!(total * 256 >= m.mesh.vertex_count(), "{total}");
    assert_eq!((calls, last), (total, total));
}
