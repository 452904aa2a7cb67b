//! Bounds hold the whole solid, also where smooth sums swell fields that fall behind the
//! distance (non-uniform scales, the cone's and pyramid's plane distances), so the mesher never
//! clips a solid silently.

use crate::common;

use common::assert_closed_outward;
use glam::{DAffine3, DQuat, DVec3};
use shapegram_implicit::{MeshOptions, Solid, mesh};

/// The largest coordinate along `axis` of the points where `solid` is positive, searched on a
/// `step`-spaced grid over the plane through the origin spanned by `axis` and `across` within
/// `reach` of the origin (the solids below are symmetric about that plane, so their extreme
/// points lie on it).
fn true_extent(solid: &Solid, axis: DVec3, across: DVec3, reach: f64, step: f64) -> f64 {
    let n = (reach / step).ceil() as i64;
    let mut best = f64::NEG_INFINITY;
    for i in -n..=n {
        for j in -n..=n {
            let (a, b) = (i as f64 * step, j as f64 * step);
            if a > best && solid.value(axis * a + across * b) > 0.0 {
                best = a;
            }
        }
    }
    best
}

/// Meshes `solid` with cells of `h` and returns its largest coordinate along `axis`.
fn meshed_extent(solid: &Solid, axis: DVec3, h: f64) -> f64 {
    let m = mesh(solid, &MeshOptions::with_cell_size(h)).unwrap();
    assert_closed_outward(&m.mesh);
    m.mesh
        .positions()
        .iter()
        .map(|p| p.dot(axis))
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn smooth_sum_of_a_stretched_ball_reaches_its_true_tip() {
    // The field of a ball stretched 3× along y is min(sᵢ) · f(p / s) = 1 − |(x, y/3, z)|, a third
    // of the distance at the tips. Summed smoothly with itself it is that plus k/4, so the solid
    // is the ellipsoid |(x, y/3, z)| < 1 + k/4: with k = 1 its tip is at y = 3.75, where bounds
    // padded by k/4 ended at 3.25.
    let ellipsoid = Solid::sphere(1.0)
        .unwrap()
        .scale(DVec3::new(1.0, 3.0, 1.0))
        .unwrap();
    let swollen = ellipsoid.smooth_union(&ellipsoid, 1.0).unwrap();
    assert!(
        swollen.bounds().unwrap().max.y >= 3.75,
        "{:?}",
        swollen.bounds()
    );
    let h = 0.05;
    let top = meshed_extent(&swollen, DVec3::Y, h);
    assert!((top - 3.75).abs() < h, "mesh top {top}");
    let side = meshed_extent(&swollen, DVec3::X, h);
    assert!((side - 1.25).abs() < h, "mesh side {side}");
}

#[test]
fn smooth_sum_under_a_scope_map_reaches_its_true_extent() {
    // As the grammar engine joins solids with a fillet: each member under its scope's
    // local-to-world map (here stretched 4× along x and turned 30° about z), whose field is
    // scaled by the map's smallest singular value.
    let map = DAffine3::from_quat(DQuat::from_rotation_z(30f64.to_radians()))
        * DAffine3::from_scale(DVec3::new(4.0, 1.0, 1.0));
    let member = Solid::sphere(0.5).unwrap().transform(&map).unwrap();
    let shifted = member.translate(DVec3::new(0.0, 0.02, 0.0)).unwrap();
    let fillet = member.smooth_union(&shifted, 1.0).unwrap();
    let h = 0.05;
    let truth = true_extent(&fillet, DVec3::X, DVec3::Y, 3.5, 0.005);
    // About the ellipsoid of semi-axes (3, 0.75, 0.75) turned 30°: √((3 cos 30°)² + (0.75 sin
    // 30°)²) ≈ 2.62; bounds padded by k/4 ended at 2.23.
    assert!((truth - 2.62).abs() < 0.05, "{truth}");
    assert!(fillet.bounds().unwrap().max.x >= truth);
    let right = meshed_extent(&fillet, DVec3::X, h);
    assert!((right - truth).abs() < h, "mesh {right}, solid {truth}");
}

#[test]
fn smooth_sum_of_cones_reaches_past_their_apex_and_base() {
    // The cone's field is the distance to its planes, which falls behind the true distance
    // above the apex: summed with a copy moved by 0.01 the solid is about the cone with its
    // planes moved out by k/4, whose apex is up to k/4 · √(r² + h²)/r ≈ 0.56 higher (bounds
    // padded by k/4 stopped 0.3 short of it) and whose base is wider by k/4 · (√(r² + h²) + r)/h
    // ≈ 0.40.
    let cone = Solid::cone(1.0, 2.0).unwrap();
    let pair = cone
        .smooth_union(&cone.translate(DVec3::new(0.01, 0.0, 0.0)).unwrap(), 1.0)
        .unwrap();
    let h = 0.02;
    let top = true_extent(&pair, DVec3::Y, DVec3::X, 1.8, 0.002);
    assert!((top - 1.55).abs() < 0.01, "{top}");
    let rim = true_extent(&pair, DVec3::X, DVec3::Y, 1.8, 0.002);
    assert!((rim - 1.41).abs() < 0.01, "{rim}");
    let b = pair.bounds().unwrap();
    assert!(b.max.y >= top && b.max.x >= rim, "{b:?}");
    let meshed_top = meshed_extent(&pair, DVec3::Y, h);
    assert!(
        (meshed_top - top).abs() < 2.0 * h,
        "mesh {meshed_top}, solid {top}"
    );
    let meshed_rim = meshed_extent(&pair, DVec3::X, h);
    assert!(
        (meshed_rim - rim).abs() < 2.0 * h,
        "mesh {meshed_rim}, solid {rim}"
    );
}

#[test]
fn smooth_sum_of_a_disjoint_intersection_is_not_empty() {
    // Two unit balls 0.2 apart have no common point, but both fields exceed −0.25 in a lens
    // between them; the smooth sum of their intersection with itself is that lens, |y| up to
    // √(1.25² − 1.1²) ≈ 0.594 (bounds taken from the empty intersection had none).
    let ball = Solid::sphere(1.0).unwrap();
    let left = ball.translate(DVec3::new(-1.1, 0.0, 0.0)).unwrap();
    let right = ball.translate(DVec3::new(1.1, 0.0, 0.0)).unwrap();
    let gap = left.intersection(&right);
    assert_eq!(gap.bounds(), None);
    let lens = gap.smooth_union(&gap, 1.0).unwrap();
    let h = 0.02;
    let top = meshed_extent(&lens, DVec3::Y, h);
    assert!(
        (top - (1.25f64.powi(2) - 1.1f64.powi(2)).sqrt()).abs() < h,
        "{top}"
    );
}

#[test]
fn nested_smooth_operations_stay_within_their_bounds() {
    // Smooth sums of smooth sums of stretched, turned pyramids, cones and balls, carved and
    // trimmed smoothly and morphed: no sample in a shell around the bounds may be inside.
    let turn = |s: Solid, deg: f64| s.rotate(DVec3::new(1.0, 2.0, 0.5), deg).unwrap();
    let a = turn(
        Solid::pyramid(DVec3::new(1.0, 2.5, 0.8))
            .unwrap()
            .scale(DVec3::new(1.0, 2.0, 0.5))
            .unwrap(),
        25.0,
    );
    let b = turn(
        Solid::cone(0.4, 2.0)
            .unwrap()
            .scale(DVec3::new(3.0, 1.0, 1.0))
            .unwrap(),
        -40.0,
    );
    let c = Solid::sphere(0.6)
        .unwrap()
        .scale(DVec3::new(1.0, 1.0, 5.0))
        .unwrap();
    let inner = a
        .smooth_union(&b, 0.8)
        .unwrap()
        .smooth_union(&a, 0.6)
        .unwrap();
    let solid = inner
        .smooth_union(&c, 1.2)
        .unwrap()
        .smooth_difference(&Solid::sphere(0.3).unwrap(), 0.2)
        .unwrap()
        .smooth_intersection(&Solid::sphere(6.0).unwrap(), 0.5)
        .unwrap()
        .morph(&inner.smooth_union(&inner, 1.0).unwrap(), 0.5)
        .unwrap();
    let b = solid.bounds().unwrap();
    let (lo, hi) = (b.min - 0.5, b.max + 0.5);
    let n = 60;
    let mut outside = 0;
    for i in 0..=n {
        for j in 0..=n {
            for k in 0..=n {
                let t = DVec3::new(i as f64, j as f64, k as f64) / n as f64;
                let p = lo + (hi - lo) * t;
                let beyond = p.cmplt(b.min).any() || p.cmpgt(b.max).any();
                if beyond {
                    outside += 1;
                    assert!(solid.value(p) <= 0.0, "{p} is inside, outside {b:?}");
                }
            }
        }
    }
    assert!(outside > 40_000, "{outside}");
}

/// A primitive of kind `kind`, stretched by `stretch`, turned by `degrees` about `axis` and moved
/// by `offset`.
fn member(kind: usize, stretch: DVec3, axis: DVec3, degrees: f64, offset: DVec3) -> Solid {
    let base = match kind {
        0 => Solid::sphere(0.8),
        1 => Solid::cuboid(DVec3::new(1.2, 0.6, 0.9)),
        2 => Solid::cylinder(0.5, 1.4),
        3 => Solid::cone(0.5, 1.6),
        4 => Solid::pyramid(DVec3::new(1.0, 1.5, 0.7)),
        5 => Solid::torus(0.8, 0.25),
        _ => Solid::capsule(0.4, 0.8),
    };
    base.unwrap()
        .scale(stretch)
        .unwrap()
        .rotate(axis, degrees)
        .unwrap()
        .translate(offset)
        .unwrap()
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]

    /// Whatever the operations, smooth or not, and however the members are stretched, no point
    /// outside a solid's bounds is inside it.
    #[test]
    fn no_point_outside_the_bounds_is_inside(
        steps in proptest::collection::vec(
            (0..7usize, 0..7usize, (0.3..3.0f64, 0.3..3.0f64, 0.3..3.0f64),
             (-1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64), 0.0..360.0f64,
             (-1.5..1.5f64, -1.5..1.5f64, -1.5..1.5f64), 0.05..1.5f64),
            1..6,
        ),
    ) {
        let mut solid = Solid::empty();
        for (op, kind, s, a, degrees, o, k) in steps {
            let part = member(
                kind,
                DVec3::new(s.0, s.1, s.2),
                DVec3::new(a.0, a.1, a.2),
                degrees,
                DVec3::new(o.0, o.1, o.2),
            );
            solid = match op {
                _ if solid.is_empty() => part,
                0 => solid.union(&part),
                1 => solid.difference(&part),
                2 => solid.intersection(&part).smooth_union(&part, k).unwrap(),
                3 => solid.morph(&part, 0.5).unwrap(),
                4 => solid.smooth_union(&part, k).unwrap(),
                5 => solid.smooth_difference(&part, k).unwrap(),
                _ => solid.smooth_union(&solid, k).unwrap().smooth_intersection(&part, k).unwrap(),
            };
        }
        // Sample a box well beyond the bounds (or round the origin when there are none).
        let (lo, hi) = solid.bounds().map_or((DVec3::splat(-8.0), DVec3::splat(8.0)), |b| {
            (b.min - 0.3 * b.size() - 0.5, b.max + 0.3 * b.size() + 0.5)
        });
        let n = 24;
        for i in 0..=n {
            for j in 0..=n {
                for l in 0..=n {
                    let t = DVec3::new(i as f64, j as f64, l as f64) / n as f64;
                    let p = lo + (hi - lo) * t;
                    let inside_bounds = solid.bounds().is_some_and(|b| b.contains(p, 0.0));
                    if !inside_bounds {
                        let v = solid.value(p);
                        proptest::prop_assert!(v <= 0.0, "{p} has {v}, bounds {:?}", solid.bounds());
                    }
                }
            }
        }
    }
}
