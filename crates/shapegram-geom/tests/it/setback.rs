//! CGA's setback: some edges of a polygon move in, the others stay; strips and remainder tile
//! the polygon, with areas by formula.

use crate::common;

use common::{footprint_loop, l_footprint, polygon_area, polyomino};
use proptest::prelude::*;
use shapegram_geom::DVec3;
use shapegram_geom::offset::{Setback, setback};

fn assert_close(a: f64, b: f64) {
    assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{a} != {b}");
}

/// The 10 × 6 lot (x by z) at the origin.
fn lot() -> Vec<DVec3> {
    footprint_loop(&[(0.0, 0.0), (10.0, 0.0), (10.0, 6.0), (0.0, 6.0)])
}

/// Distance `d` for edges whose midpoint satisfies `test`, 0 for the others.
fn at(d: f64, test: impl Fn(DVec3) -> bool) -> impl Fn(usize, DVec3, DVec3) -> f64 {
    move |_, a, b| if test((a + b) / 2.0) { d } else { 0.0 }
}

/// Distance `d` for every edge.
fn all(d: f64) -> impl Fn(usize, DVec3, DVec3) -> f64 {
    move |_, _, _| d
}

fn areas(cut: &Setback) -> (Vec<f64>, f64) {
    let strips = cut
        .strips
        .iter()
        .map(|s| polygon_area(&s.polygon))
        .collect();
    let rest = cut.remainder.iter().map(|r| polygon_area(r)).sum();
    (strips, rest)
}

#[test]
fn one_edge_cuts_a_rectangular_strip() {
    let cut = setback(&lot(), at(2.0, |m| m.z == 0.0)).unwrap();
    let (strips, rest) = areas(&cut);
    assert_eq!(strips.len(), 1);
    assert_close(strips[0], 20.0);
    assert_close(rest, 40.0);
    // The strip starts with its edge.
    let strip = &cut.strips[0];
    assert_eq!(&strip.polygon[..2], &strip.ends[..]);
    assert!(strip.ends.iter().all(|p| p.z == 0.0));
    // The remainder keeps the corners of the edges that stayed.
    assert!(cut.remainder[0].contains(&DVec3::new(10.0, 0.0, 6.0)));
}

#[test]
fn neighbouring_edges_meet_in_a_mitre() {
    let cut = setback(&lot(), at(2.0, |m| m.z == 0.0 || m.x == 10.0)).unwrap();
    let (strips, rest) = areas(&cut);
    // The corner strip is split along the mitre: each trapezoid is its edge times 2 less 2·2/2.
    assert_eq!(strips.len(), 2);
    let mut sorted = strips.clone();
    sorted.sort_by(f64::total_cmp);
    assert_close(sorted[0], 6.0 * 2.0 - 2.0);
    assert_close(sorted[1], 10.0 * 2.0 - 2.0);
    assert_close(rest, 8.0 * 4.0);
}

#[test]
fn every_edge_is_an_inset_and_too_deep_leaves_nothing() {
    let (strips, rest) = areas(&setback(&lot(), all(1.0)).unwrap());
    assert_eq!(strips.len(), 4);
    assert_close(rest, 8.0 * 4.0);
    assert_close(strips.iter().sum::<f64>(), 60.0 - 32.0);
    let deep = setback(&lot(), at(100.0, |m| m.z == 0.0)).unwrap();
    assert!(deep.remainder.is_empty());
    assert_close(polygon_area(&deep.strips[0].polygon), 60.0);
}

#[test]
fn different_distances_make_an_l() {
    // CGA's shapeL(3, 2) on the 10 × 6 lot: the front edge (z = 0 here) set back 3, the left
    // (x = 0) 2; the strips join into one L-shaped outline of 10·3 + 2·3 = 36.
    let cut = setback(&lot(), |_, a, b| {
        let m = (a + b) / 2.0;
        if m.z == 0.0 {
            3.0
        } else if m.x == 0.0 {
            2.0
        } else {
            0.0
        }
    })
    .unwrap();
    let (strips, rest) = areas(&cut);
    assert_close(strips.iter().sum::<f64>(), 36.0);
    assert_close(rest, 8.0 * 3.0);
    assert_eq!(cut.outline.len(), 1);
    assert_eq!(cut.outline[0].len(), 6);
    assert_close(polygon_area(&cut.outline[0]), 36.0);
    assert!(cut.remainder[0].contains(&DVec3::new(2.0, 0.0, 3.0)));
}

#[test]
fn zero_distance_or_no_edge_leaves_the_polygon() {
    for cut in [
        setback(&lot(), all(0.0)).unwrap(),
        setback(&lot(), at(3.0, |_| false)).unwrap(),
    ] {
        assert!(cut.strips.is_empty());
        assert_eq!(cut.remainder.len(), 1);
        assert_close(polygon_area(&cut.remainder[0]), 60.0);
    }
    assert_eq!(setback(&lot(), all(-1.0)), None);
    assert_eq!(setback(&lot(), all(f64::NAN)), None);
    assert_eq!(setback(&[DVec3::ZERO, DVec3::X], all(1.0)), None);
}

#[test]
fn a_moving_edge_running_onto_one_that_stays_is_refused() {
    // A plus-like tetromino whose right arm (1 long) is set back 1.5: its end edge reaches the
    // column's side edges, which stay, and no weighted skeleton goes on from there.
    let outline = polyomino(&[(0, 2), (0, 0), (3, 3)]).unwrap();
    assert_eq!(setback(&outline, at(1.5, |m| m.x == 2.0)), None);
    // Less deep, it is fine: the arm loses half its length.
    let cut = setback(&outline, at(0.5, |m| m.x == 2.0)).unwrap();
    let (strips, rest) = areas(&cut);
    assert_close(strips[0], 0.5);
    assert_close(rest, 3.5);
}

#[test]
fn a_non_convex_lot_is_cut_only_near_its_edge() {
    // The L (4 × 4 less a 2 × 2 corner): setting back its long bottom edge by 1 cuts a 4 × 1
    // strip and leaves the rest, including the arm far from that edge.
    let cut = setback(&l_footprint(), at(1.0, |m| m.z == 0.0)).unwrap();
    let (strips, rest) = areas(&cut);
    assert_close(strips[0], 4.0);
    assert_close(rest, 8.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Whatever the footprint and the edges, strips and remainder tile it, for setbacks less
    /// deep than the unit cells (deeper ones may run a moving edge onto one that stays).
    #[test]
    fn strips_and_remainder_tile_the_polygon(
        choices in prop::collection::vec((0usize..16, 0u8..4), 1..8),
        distance in 0.05f64..0.95,
        mask in 1u32..u32::MAX,
    ) {
        let Some(outline) = polyomino(&choices) else { return Ok(()); };
        let cut = setback(&outline, |i, _, _| if mask >> (i % 32) & 1 == 1 { distance } else { 0.0 });
        prop_assert!(cut.is_some(), "no setback of {:?}", outline);
        let cut = cut.unwrap();
        let (strips, rest) = areas(&cut);
        let total: f64 = strips.iter().sum::<f64>() + rest;
        // Holes of the outline (a ring of strips round the whole polygon) run clockwise.
        let up = |l: &[DVec3]| shapegram_geom::mesh::newell(l.iter().copied()).y / 2.0;
        let joined: f64 = cut.outline.iter().map(|l| up(l)).sum();
        prop_assert!((joined - strips.iter().sum::<f64>()).abs() < 1e-6);
        prop_assert!((total - polygon_area(&outline)).abs() < 1e-6, "{} != {}", total, polygon_area(&outline));
    }
}
