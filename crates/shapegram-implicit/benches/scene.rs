//! The benchmark scene, shared by `benches/mesh.rs`, `examples/bench_scene.rs` and (re-written in
//! NumPy) `bench/compare.py`: a slab with two round ends, four bored holes, a ring, a cone, a
//! capsule-shaped groove and a dimple, morphed 30 % towards a ball. Twelve primitives.

use glam::DVec3;
use shapegram_implicit::Solid;

/// Builds the scene.
pub fn scene() -> Solid {
    let at = |s: Solid, x: f64, y: f64, z: f64| s.translate(DVec3::new(x, y, z)).unwrap();
    let mut s = Solid::cuboid(DVec3::new(3.0, 2.0, 2.0)).unwrap();
    for x in [-1.5, 1.5] {
        s = s.union(&at(Solid::sphere(0.9).unwrap(), x, 0.0, 0.0));
    }
    for x in [-1.2, -0.4, 0.4, 1.2] {
        let bore = Solid::cylinder(0.35, 3.0)
            .unwrap()
            .rotate(DVec3::X, 90.0)
            .unwrap();
        s = s.difference(&at(bore, x, 0.0, 0.0));
    }
    s = s.union(&at(Solid::torus(1.2, 0.3).unwrap(), 0.0, 1.0, 0.0));
    let groove = Solid::capsule(0.4, 2.5)
        .unwrap()
        .rotate(DVec3::Z, 90.0)
        .unwrap();
    s = s.difference(&at(groove, 0.0, -0.6, 0.0));
    s = s.union(&at(Solid::cone(0.8, 1.5).unwrap(), 0.0, 1.6, 0.0));
    s = s.difference(&at(Solid::sphere(0.5).unwrap(), 0.0, 0.0, 1.0));
    s.morph(&Solid::sphere(2.0).unwrap(), 0.3).unwrap()
}
