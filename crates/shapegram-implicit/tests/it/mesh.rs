//! Marching cubes: convergence on the sphere, exact counts on a box, closed and oriented output,
//! CSG identities, determinism across thread counts, sparse evaluation and limits.

use crate::common;

use std::f64::consts::PI;

use common::{assert_closed_outward, meshed, relative_error, smallest_relative_area};
use glam::DVec3;
use shapegram_implicit::metrics::{DEFAULT_FLAT_ANGLE, convexity, edge_analysis};
use shapegram_implicit::{MeshOptions, Metrics, Solid, mesh};

#[test]
fn sphere_area_and_volume_converge_with_stated_tolerances() {
    let r = 1.5;
    let sphere = Solid::sphere(r).unwrap();
    let (area, volume) = (4.0 * PI * r * r, 4.0 / 3.0 * PI * r.powi(3));
    // (cells along the diameter, area tolerance, mesh volume tolerance, voxel volume tolerance):
    // the mesh errors fall about 4× per halving of the cell (second order), the voxel count's 2×.
    let steps = [
        (16, 0.006, 0.011, 0.27),
        (32, 0.0015, 0.003, 0.14),
        (64, 0.0004, 0.0007, 0.07),
        (128, 0.0001, 0.0002, 0.035),
    ];
    let mut last = (f64::INFINITY, f64::INFINITY);
    for (cells, area_tol, volume_tol, voxel_tol) in steps {
        let m = meshed(&sphere, cells);
        assert_closed_outward(&m.mesh);
        let metrics = Metrics::measure(&m, 1);
        let errors = (
            relative_error(metrics.area, area),
            relative_error(metrics.mesh_volume, volume),
        );
        assert!(errors.0 < area_tol, "{cells}: area error {}", errors.0);
        assert!(errors.1 < volume_tol, "{cells}: volume error {}", errors.1);
        assert!(
            errors.0 < last.0 && errors.1 < last.1,
            "{cells}: no convergence"
        );
        let voxel = relative_error(metrics.voxel_volume, volume);
        assert!(
            metrics.voxel_volume < volume && voxel < voxel_tol,
            "{cells}: voxel {voxel}"
        );
        assert_eq!(metrics.convexity.concave, 0, "{cells}");
        last = errors;
    }
}

#[test]
fn box_metrics() {
    let size = DVec3::new(2.0, 1.0, 3.0);
    let m = mesh(
        &Solid::cuboid(size).unwrap(),
        &MeshOptions::with_cell_size(0.1),
    )
    .unwrap();
    assert_closed_outward(&m.mesh);
    // The grid is padded by 1.5 cells, so samples fall half a cell off the faces: 19 × 9 × 29
    // cells lie wholly inside.
    assert_eq!(m.grid.cells, [23, 13, 33]);
    assert_eq!(m.inside_cells, 19 * 9 * 29);
    assert!((m.voxel_volume() - 4.959).abs() < 1e-9);
    let metrics = Metrics::measure(&m, 1);
    // Marching cubes chamfers the edges by about half a cell: area and volume fall a little short.
    assert!(metrics.area < 22.0 && relative_error(metrics.area, 22.0) < 0.04);
    assert!(metrics.mesh_volume < 6.0 && relative_error(metrics.mesh_volume, 6.0) < 0.01);
    assert_eq!(metrics.convexity.factor(), 100.0);
    // Faces on the box's sides lie exactly in its planes: the field is linear there.
    let on_plane = m
        .mesh
        .positions()
        .iter()
        .filter(|p| (p.x.abs() - 1.0).abs() < 1e-12)
        .count();
    assert!(on_plane > 300, "{on_plane}");
    assert_eq!(metrics.triangles, m.mesh.face_count());
    assert_eq!(metrics.vertices, m.mesh.vertex_count());
    // Euler characteristic of a sphere-like surface: V − E + F = 2.
    let euler = metrics.vertices as i64 - metrics.edges.edges as i64 + metrics.triangles as i64;
    assert_eq!(euler, 2);
}

#[test]
fn primitives_enclose_their_exact_volumes() {
    let cases = [
        (Solid::cylinder(1.0, 2.0), PI * 2.0),
        (Solid::cone(1.0, 2.0), PI * 2.0 / 3.0),
        (
            Solid::pyramid(DVec3::new(2.0, 3.0, 1.5)),
            2.0 * 1.5 * 3.0 / 3.0,
        ),
        (Solid::torus(2.0, 0.5), 2.0 * PI * PI * 2.0 * 0.25),
        (
            Solid::capsule(0.5, 2.0),
            PI * 0.25 * (2.0 + 4.0 / 3.0 * 0.5),
        ),
    ];
    for (solid, exact) in cases {
        let solid = solid.unwrap();
        let m = meshed(&solid, 96);
        assert_closed_outward(&m.mesh);
        let volume = m.mesh.signed_volume();
        assert!(
            relative_error(volume, exact) < 0.01,
            "{solid:?}: {volume} vs {exact}"
        );
    }
}

#[test]
fn torus_has_genus_one() {
    let m = meshed(&Solid::torus(2.0, 0.6).unwrap(), 64);
    assert_closed_outward(&m.mesh);
    let report = m.mesh.edge_report();
    let euler = m.mesh.vertex_count() as i64 - report.edges as i64 + m.mesh.face_count() as i64;
    assert_eq!(euler, 0);
    // A torus has saddle regions: its inner half bends both ways.
    let c = convexity(&m.mesh, DEFAULT_FLAT_ANGLE);
    assert!(c.concave > 0 && c.factor() < 100.0, "{c:?}");
}

#[test]
fn transforms_move_scale_and_turn() {
    let sphere = Solid::sphere(1.0).unwrap();
    let moved = sphere.translate(DVec3::new(3.0, -1.0, 2.0)).unwrap();
    assert_eq!(moved.value(DVec3::new(3.0, -1.0, 2.0)), 1.0);
    let b = moved.bounds().unwrap();
    assert_eq!(
        (b.min, b.max),
        (DVec3::new(2.0, -2.0, 1.0), DVec3::new(4.0, 0.0, 3.0))
    );
    let ellipsoid = sphere.scale(DVec3::new(2.0, 1.0, 0.5)).unwrap();
    let m = meshed(&ellipsoid, 128);
    assert_closed_outward(&m.mesh);
    assert!(relative_error(m.mesh.signed_volume(), 4.0 / 3.0 * PI) < 0.002);
    // A mirror keeps the solid solid and the mesh outward.
    let mirrored = Solid::cone(1.0, 2.0)
        .unwrap()
        .scale(DVec3::new(1.0, -1.0, 1.0))
        .unwrap();
    assert!(mirrored.value(DVec3::new(0.3, 0.9, 0.0)) > 0.0);
    assert!(mirrored.value(DVec3::new(0.3, -0.9, 0.0)) < 0.0);
    assert_closed_outward(&meshed(&mirrored, 48).mesh);
    // A quarter turn about z takes the +x end of a long box to +y.
    let bar = Solid::cuboid(DVec3::new(4.0, 1.0, 1.0)).unwrap();
    let turned = bar.rotate(DVec3::Z, 90.0).unwrap();
    assert!(turned.value(DVec3::new(0.0, 1.9, 0.0)) > 0.0);
    assert!(turned.value(DVec3::new(1.9, 0.0, 0.0)) < 0.0);
    // Transforms fold into one node.
    let twice = bar
        .translate(DVec3::X)
        .unwrap()
        .translate(DVec3::Y)
        .unwrap();
    assert!(matches!(
        twice.node(),
        shapegram_implicit::Node::Transform { child, .. }
            if matches!(**child, shapegram_implicit::Node::Primitive(_))
    ));
    assert_eq!(twice.value(DVec3::new(1.0, 1.0, 0.0)), 0.5);
}

#[test]
fn csg_identities() {
    let a = Solid::cuboid(DVec3::new(2.0, 1.5, 1.0))
        .unwrap()
        .rotate(DVec3::new(1.0, 1.0, 0.0), 30.0)
        .unwrap();
    let b = Solid::sphere(1.0)
        .unwrap()
        .translate(DVec3::new(0.8, 0.0, 0.0))
        .unwrap();
    // A − A is empty: min(f, −f) is never positive.
    let nothing = mesh(&a.difference(&a), &MeshOptions::with_cell_size(0.05)).unwrap();
    assert!(nothing.mesh.is_empty());
    assert_eq!(nothing.inside_cells, 0);
    // A ∪ A = A and A ∩ A = A, down to the last vertex.
    let alone = meshed(&a, 40);
    let options = MeshOptions::with_cell_size(alone.grid.cell_size);
    assert_eq!(mesh(&a.union(&a), &options).unwrap().mesh, alone.mesh);
    assert_eq!(
        mesh(&a.intersection(&a), &options).unwrap().mesh,
        alone.mesh
    );
    // Morphing with a = 0 and a = 1 gives the inputs' fields exactly.
    let (m0, m1) = (a.morph(&b, 0.0).unwrap(), a.morph(&b, 1.0).unwrap());
    for i in 0..1000 {
        let t = i as f64;
        let p = DVec3::new((t * 0.37).sin(), (t * 0.71).cos(), (t * 0.13).sin()) * 2.0;
        assert_eq!(m0.value(p), a.value(p));
        assert_eq!(m1.value(p), b.value(p));
    }
    // Sum and intersection split the volume: |A ∪ B| + |A ∩ B| = |A| + |B|.
    let volume = |s: &Solid| mesh(s, &options).unwrap().mesh.signed_volume();
    let lhs = volume(&a.union(&b)) + volume(&a.intersection(&b));
    let rhs = volume(&a) + volume(&b);
    assert!(relative_error(lhs, rhs) < 0.005, "{lhs} vs {rhs}");
    // |A − B| = |A| − |A ∩ B|.
    let diff = volume(&a.difference(&b));
    let expected = volume(&a) - volume(&a.intersection(&b));
    assert!(
        relative_error(diff, expected) < 0.01,
        "{diff} vs {expected}"
    );
    // The empty solid is the identity of the sum.
    assert_eq!(
        Solid::empty().union(&a).value(DVec3::ZERO),
        a.value(DVec3::ZERO)
    );
    // Disjoint intersections have no bounds and mesh to nothing.
    let far = b.translate(DVec3::new(10.0, 0.0, 0.0)).unwrap();
    assert_eq!(a.intersection(&far).bounds(), None);
}

#[test]
fn morph_halfway_between_box_and_sphere() {
    let cube = Solid::cuboid(DVec3::splat(2.0)).unwrap();
    let ball = Solid::sphere(1.0).unwrap();
    let options = MeshOptions::with_cell_size(0.025);
    let volume = |s: &Solid| mesh(s, &options).unwrap().mesh.signed_volume();
    let half = volume(&cube.morph(&ball, 0.5).unwrap());
    assert!(half < volume(&cube) && half > volume(&ball), "{half}");
}

#[test]
fn smooth_union_fills_the_crease() {
    let a = Solid::sphere(1.0)
        .unwrap()
        .translate(-0.8 * DVec3::X)
        .unwrap();
    let b = Solid::sphere(1.0)
        .unwrap()
        .translate(0.8 * DVec3::X)
        .unwrap();
    let sharp = a.union(&b);
    let smooth = a.smooth_union(&b, 0.5).unwrap();
    let options = MeshOptions::with_cell_size(0.04);
    let ms = mesh(&smooth, &options).unwrap();
    assert_closed_outward(&ms.mesh);
    assert!(ms.mesh.signed_volume() > mesh(&sharp, &options).unwrap().mesh.signed_volume());
    // In the crease (x = 0, on the circle where the spheres meet) the smooth field is larger.
    let crease = DVec3::new(0.0, 0.6, 0.0);
    assert!(smooth.value(crease) > sharp.value(crease));
    let carved = a.smooth_difference(&b, 0.3).unwrap();
    assert_closed_outward(&mesh(&carved, &options).unwrap().mesh);
    let lens = a.smooth_intersection(&b, 0.3).unwrap();
    assert_closed_outward(&mesh(&lens, &options).unwrap().mesh);
}

/// Ten primitives with differences and a morph: the bench's scene, smaller.
fn busy_scene() -> Solid {
    let mut s = Solid::cuboid(DVec3::new(4.0, 2.0, 2.0)).unwrap();
    for i in 0..5 {
        let x = i as f64 - 2.0;
        let hole = Solid::cylinder(0.3, 3.0)
            .unwrap()
            .rotate(DVec3::X, 90.0)
            .unwrap()
            .translate(DVec3::new(x, 0.3, 0.0))
            .unwrap();
        s = s.difference(&hole);
        let bump = Solid::sphere(0.5)
            .unwrap()
            .translate(DVec3::new(x, 1.0, 0.0))
            .unwrap();
        s = s.union(&bump);
    }
    let ring = Solid::torus(1.5, 0.4).unwrap();
    s.morph(&s.union(&ring), 0.5).unwrap()
}

#[test]
fn busy_scene_is_closed_without_degenerate_triangles() {
    let m = meshed(&busy_scene(), 100);
    assert_closed_outward(&m.mesh);
    let smallest = smallest_relative_area(&m.mesh, m.grid.cell_size);
    assert!(smallest > 1e-7, "{smallest}");
}

#[test]
fn work_follows_the_surface() {
    // Doubling the resolution quadruples the surface cells but octuples the grid: the samples
    // evaluated must grow like the surface.
    let sphere = Solid::sphere(1.0).unwrap();
    let (coarse, fine) = (meshed(&sphere, 128), meshed(&sphere, 256));
    let grid = |m: &shapegram_implicit::Meshing| {
        m.grid.cells.iter().map(|&c| c as u64 + 1).product::<u64>()
    };
    let growth = fine.evaluated_samples as f64 / coarse.evaluated_samples as f64;
    assert!(growth < 4.5, "{growth}");
    assert!(
        fine.evaluated_samples * 3 < grid(&fine),
        "{}",
        fine.evaluated_samples
    );
}

#[test]
fn output_does_not_depend_on_thread_count() {
    let solid = busy_scene();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| meshed(&solid, 80).mesh)
    };
    let one = run(1);
    assert_eq!(run(3), one);
    assert_eq!(run(2), one);
}

#[test]
fn sparse_and_dense_meshing_agree() {
    // Blocks of 2 cells classify far more finely than blocks of 32; the mesh must not change
    // except for vertex order, so compare the sorted triangle corner positions.
    let solid = busy_scene();
    let sorted = |block: usize| {
        let mut options = MeshOptions::cells_along_longest(&solid, 60);
        options.block = block;
        let m = mesh(&solid, &options).unwrap();
        let mut tris: Vec<[[u64; 3]; 3]> = m
            .mesh
            .faces()
            .map(|f| {
                let mut t = [0, 1, 2].map(|i| m.mesh.position(f[i]).to_array().map(f64::to_bits));
                let first = (0..3).min_by_key(|&i| t[i]).unwrap();
                t.rotate_left(first);
                t
            })
            .collect();
        tris.sort();
        (tris, m.inside_cells)
    };
    assert_eq!(sorted(2), sorted(32));
}

#[test]
fn bad_parameters_are_errors() {
    let cases = [
        (
            Solid::sphere(0.0),
            "invalid sphere radius 0: expected a finite number greater than 0",
        ),
        (
            Solid::sphere(-1.0),
            "invalid sphere radius -1: expected a finite number greater than 0",
        ),
        (
            Solid::sphere(f64::NAN),
            "invalid sphere radius NaN: expected a finite number greater than 0",
        ),
        (
            Solid::cuboid(DVec3::new(1.0, 0.0, 1.0)),
            "invalid box size y 0: expected a finite number greater than 0",
        ),
        (
            Solid::cylinder(1.0, f64::INFINITY),
            "invalid cylinder height inf: expected a finite number greater than 0",
        ),
        (
            Solid::torus(1.0, 1.0),
            "invalid torus: the minor radius 1 must be less than the major radius 1",
        ),
        (
            Solid::capsule(1.0, -0.5),
            "invalid capsule length -0.5: expected a finite number of at least 0",
        ),
    ];
    for (result, message) in cases {
        assert_eq!(result.unwrap_err().to_string(), message);
    }
    let s = Solid::sphere(1.0).unwrap();
    assert_eq!(
        s.scale(DVec3::new(1.0, 0.0, 1.0)).unwrap_err().to_string(),
        "invalid scale y 0: expected a finite non-zero number"
    );
    assert_eq!(
        s.translate(DVec3::new(f64::NAN, 0.0, 0.0))
            .unwrap_err()
            .to_string(),
        "invalid translation x NaN: expected a finite number"
    );
    assert_eq!(
        s.rotate(DVec3::ZERO, 10.0).unwrap_err().to_string(),
        "invalid rotation axis [0, 0, 0]: expected a finite non-zero vector"
    );
    assert_eq!(
        s.morph(&s, 1.5).unwrap_err().to_string(),
        "invalid morphing parameter 1.5: expected 0 to 1 (0 % to 100 %)"
    );
    assert_eq!(
        s.smooth_union(&s, 0.0).unwrap_err().to_string(),
        "invalid smoothing radius 0: expected a finite number greater than 0"
    );
    assert_eq!(
        mesh(&s, &MeshOptions::with_cell_size(f64::NAN))
            .unwrap_err()
            .to_string(),
        "invalid cell size NaN: expected a finite number greater than 0"
    );
}

#[test]
fn limits_are_errors() {
    let s = Solid::sphere(1.0).unwrap();
    assert_eq!(
        mesh(&s, &MeshOptions::with_cell_size(1e-4))
            .unwrap_err()
            .to_string(),
        "a grid of 20003 × 20003 × 20003 cells exceeds the limit of 8589934592 cells: use larger \
         cells (a lower level of detail)"
    );
    assert_eq!(
        mesh(
            &Solid::sphere(1e300).unwrap(),
            &MeshOptions::with_cell_size(0.1)
        )
        .unwrap_err()
        .to_string(),
        "a grid of 2.000e301 × 2.000e301 × 2.000e301 cells exceeds the limit of 8589934592 \
         cells: use larger cells (a lower level of detail)"
    );
    // So far from the origin, samples a cell apart round to the same point: no mesh, an error.
    for far in [1e300, 1e12] {
        let moved = s.translate(DVec3::new(far, 0.0, -1.0)).unwrap();
        let err = mesh(&moved, &MeshOptions::with_cell_size(0.1)).unwrap_err();
        assert!(
            err.to_string()
                .contains("units from the origin, too far for cells of 0.1"),
            "{err}"
        );
    }
    // Nearer, the same sphere meshes as it does at the origin.
    let at_origin = mesh(&s, &MeshOptions::with_cell_size(0.1)).unwrap();
    let moved = s.translate(DVec3::new(1e6, 0.0, -1.0)).unwrap();
    let near = mesh(&moved, &MeshOptions::with_cell_size(0.1)).unwrap();
    assert_eq!(near.mesh.face_count(), at_origin.mesh.face_count());
    let mut options = MeshOptions::cells_along_longest(&s, 64);
    options.max_triangles = 1000;
    assert_eq!(
        mesh(&s, &options).unwrap_err().to_string(),
        "the mesh would have more than 1000 triangles: use larger cells (a lower level of detail)"
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]

    /// Random unions and differences of small balls and boxes at a coarse grid: every ambiguous
    /// face and cell configuration turns up, and the mesh must stay closed and outward.
    #[test]
    fn random_scenes_mesh_closed(
        parts in proptest::collection::vec(
            (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, 0.15..0.6f64, 0..3u8),
            2..16,
        ),
        cells in 6..30usize,
    ) {
        let mut scene = Solid::sphere(0.8).unwrap();
        for (x, y, z, r, kind) in parts {
            let part = if kind == 2 {
                Solid::cuboid(DVec3::splat(r * 1.5)).unwrap().rotate(DVec3::new(x, y, 1.0), 40.0 * z).unwrap()
            } else {
                Solid::sphere(r).unwrap()
            };
            let part = part.translate(DVec3::new(x, y, z)).unwrap();
            scene = if kind == 1 { scene.difference(&part) } else { scene.union(&part) };
        }
        let m = meshed(&scene, cells);
        if !m.mesh.is_empty() {
            let report = m.mesh.edge_report();
            // The metrics' own edge pass agrees with the kernel's.
            proptest::prop_assert_eq!(edge_analysis(&m.mesh, 3.0).1, report);
            proptest::prop_assert!(report.is_watertight(), "{:?}", report);
            proptest::prop_assert!(m.mesh.signed_volume() > 0.0);
            proptest::prop_assert!(smallest_relative_area(&m.mesh, m.grid.cell_size) > 1e-9);
        }
    }
}

#[test]
fn convexity_of_exact_polyhedra_and_broken_meshes() {
    use shapegram_geom::primitives;
    // Exact convex polyhedra from the kernel: every bent edge is convex.
    for m in [
        primitives::cuboid(DVec3::new(1.0, 2.0, 3.0)),
        primitives::cylinder(DVec3::ONE, 24),
        primitives::sphere(DVec3::ONE, 24, 12),
    ] {
        let (bends, report) = edge_analysis(&m, DEFAULT_FLAT_ANGLE);
        assert_eq!(bends.factor(), 100.0);
        assert!(bends.convex > 0 && bends.concave == 0);
        assert_eq!(report, m.edge_report());
    }
    // An L-shaped prism has exactly one concave edge (the inner corner's vertical edge).
    let l = [
        (0.0, 0.0),
        (0.0, 2.0),
        (1.0, 2.0),
        (1.0, 1.0),
        (2.0, 1.0),
        (2.0, 0.0),
    ]
    .map(|(x, z)| DVec3::new(x, 0.0, z));
    let prism = shapegram_geom::extrude::extrude_polygon(&l, 1.0).unwrap();
    let (bends, report) = edge_analysis(&prism, DEFAULT_FLAT_ANGLE);
    assert!(report.is_watertight(), "{report:?}");
    assert_eq!((bends.convex, bends.concave), (17, 1));
    assert!((bends.factor() - 100.0 * 17.0 / 18.0).abs() < 1e-12);
    // A flipped face and a missing face are reported like the kernel does.
    let cube = primitives::cuboid(DVec3::ONE);
    let faces: Vec<Vec<u32>> = cube.faces().map(<[u32]>::to_vec).collect();
    let mut flipped = faces.clone();
    flipped[0].reverse();
    let flipped = shapegram_geom::Mesh::from_faces(cube.positions().to_vec(), flipped);
    let open = shapegram_geom::Mesh::from_faces(cube.positions().to_vec(), &faces[1..]);
    for m in [flipped, open] {
        assert_eq!(edge_analysis(&m, DEFAULT_FLAT_ANGLE).1, m.edge_report());
        assert!(!m.edge_report().is_watertight());
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// A tape pruned to a ball gives exactly the full tape's values everywhere in the ball.
    #[test]
    fn pruned_tapes_agree_inside_their_ball(
        parts in proptest::collection::vec(
            (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64, 0.2..1.5f64, 0..6u8),
            1..24,
        ),
        centre in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
        radius in 0.05..2.0f64,
    ) {
        use shapegram_implicit::tape::Tape;
        let mut scene = Solid::empty();
        for (i, (x, y, z, r, kind)) in parts.into_iter().enumerate() {
            let part = Solid::sphere(r).unwrap()
                .scale(DVec3::new(1.0, 0.5 + r, 1.0)).unwrap()
                .translate(DVec3::new(x, y, z)).unwrap();
            scene = match kind {
                0 | 1 => scene.union(&part),
                2 => scene.difference(&part),
                3 => scene.intersection(&part.scale(DVec3::splat(3.0)).unwrap()),
                4 => scene.morph(&scene.union(&part), 0.4).unwrap(),
                _ if i % 2 == 0 => part.union(&scene),
                _ => scene.smooth_union(&part, 0.3).unwrap(),
            };
        }
        let tape = Tape::new(&scene);
        let mut ws = tape.workspace(64);
        let c = DVec3::new(centre.0, centre.1, centre.2);
        let pruned = tape.pruned(&mut ws, c, radius);
        proptest::prop_assert!(pruned.len() <= tape.len());
        for i in 0..64 {
            let t = f64::from(i);
            let dir = DVec3::new((t * 1.7).sin(), (t * 2.3).cos(), (t * 0.9).sin()).normalize();
            let p = c + dir * radius * ((t * 0.37).sin().abs());
            let full = tape.value(&mut ws, p);
            let part = pruned.value(&mut ws, p);
            proptest::prop_assert!(full == part || (full.is_infinite() && part.is_infinite()), "{} vs {}", full, part);
        }
    }
}

#[test]
fn any_affine_map_keeps_the_field_a_distance_bound() {
    use glam::{DAffine3, DMat3, DQuat};
    let ball = Solid::sphere(1.0).unwrap();
    // A scope-like map: rotate, scale unevenly, shear a little, move.
    let map = DAffine3::from_translation(DVec3::new(2.0, -1.0, 0.5))
        * DAffine3::from_quat(DQuat::from_axis_angle(
            DVec3::new(1.0, 2.0, 3.0).normalize(),
            0.7,
        ))
        * DAffine3::from_mat3(DMat3::from_cols(
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.3, 0.5, 0.0),
            DVec3::new(0.0, 0.0, 1.2),
        ));
    let moved = ball.transform(&map).unwrap();
    // Inside where the preimage is inside; the field never changes faster than the distance.
    assert!(moved.value(map.transform_point3(DVec3::new(0.5, 0.2, 0.1))) > 0.0);
    assert!(moved.value(map.transform_point3(DVec3::new(0.9, 0.5, 0.3))) < 0.0);
    let points: Vec<DVec3> = (0..400)
        .map(|i| {
            let t = f64::from(i);
            DVec3::new((t * 0.31).sin(), (t * 0.17).cos(), (t * 0.73).sin()) * 3.0
        })
        .collect();
    let mut steepest: f64 = 0.0;
    for w in points.windows(2) {
        let step = (w[1] - w[0]).normalize() * 1e-3;
        let slope = (moved.value(w[0] + step) - moved.value(w[0])).abs() / 1e-3;
        assert!(slope <= 1.0 + 1e-6, "{slope}");
        steepest = steepest.max(slope);
    }
    // Not flattened more than needed: somewhere the field is nearly as steep as allowed.
    assert!(steepest > 0.8, "{steepest}");
    // The mesh encloses |det| times the ball's volume.
    let m = meshed(&moved, 120);
    assert_closed_outward(&m.mesh);
    let exact = 4.0 / 3.0 * PI * map.matrix3.determinant().abs();
    assert!(relative_error(m.mesh.signed_volume(), exact) < 0.005);
    // A rotation keeps the field exactly a distance (factor 1, up to rounding).
    let turned = ball
        .transform(&DAffine3::from_quat(DQuat::from_rotation_y(1.0)))
        .unwrap();
    assert!((turned.value(DVec3::ZERO) - 1.0).abs() < 1e-8);
    assert_eq!(
        ball.transform(&DAffine3::from_mat3(DMat3::from_diagonal(DVec3::new(
            1.0, 0.0, 1.0
        ))))
        .unwrap_err()
        .to_string(),
        "invalid transform: expected a finite map that can be inverted"
    );
}

#[test]
fn a_deadline_that_has_passed_stops_meshing_with_an_error() {
    let ball = Solid::sphere(1.0).unwrap();
    let options = MeshOptions {
        deadline: Some(std::time::Instant::now()),
        ..MeshOptions::with_cell_size(0.01)
    };
    let e = shapegram_implicit::mesh(&ball, &options).unwrap_err();
    assert!(
        e.message()
            .starts_with("meshing took longer than the time allowed"),
        "{}",
        e.message()
    );
    assert!(shapegram_implicit::mesh(&ball, &MeshOptions::with_cell_size(0.1)).is_ok());
}
