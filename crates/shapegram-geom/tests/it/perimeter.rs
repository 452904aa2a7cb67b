//! CGA's splitAndSetbackPerimeter on one polygon: stretches of its boundary set back by their
//! own depths, the deeper keeping overlaps, and the remainder tile the polygon.

use crate::common;

use common::{polygon_area, polyomino};
use proptest::prelude::*;
use shapegram_geom::perimeter::{EdgePiece, Stretch, split_setback_perimeter};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Whatever the footprint and the stretches (less deep than half a unit cell), the
    /// stretches and the remainder tile it, and no stretch gains area from the others.
    #[test]
    fn stretches_and_remainder_tile_the_polygon(
        choices in prop::collection::vec((0usize..16, 0u8..4), 1..8),
        picks in prop::collection::vec((0usize..64, 0usize..3, 0.0f64..1.0, 0.0f64..1.0, 0.05f64..0.45), 1..5),
    ) {
        let Some(outline) = polyomino(&choices) else { return Ok(()); };
        let n = outline.len();
        let long = |e: usize| outline[e].distance(outline[(e + 1) % n]);
        // From `a` along one edge round `more` corners to `b` along the last edge.
        let stretches: Vec<Stretch> = picks
            .iter()
            .map(|&(edge, more, a, b, depth)| {
                let edges: Vec<usize> = (0..=more.min(n - 1)).map(|k| (edge + k) % n).collect();
                let last = edges.len() - 1;
                let pieces = edges
                    .iter()
                    .enumerate()
                    .map(|(k, &e)| {
                        let from = if k == 0 { a * long(e) } else { 0.0 };
                        let to = if k == last { b * long(e) } else { long(e) };
                        let (from, to) = if last == 0 { (from.min(to), from.max(to)) } else { (from, to) };
                        EdgePiece { edge: e, from, to }
                    })
                    .collect();
                Stretch { depth, pieces }
            })
            .collect();
        let cut = split_setback_perimeter(&outline, &stretches);
        prop_assert!(cut.is_some(), "no cut of {:?}", outline);
        let cut = cut.unwrap();
        let area = |loops: &[Vec<shapegram_geom::DVec3>]| loops.iter().map(|l| polygon_area(l)).sum::<f64>();
        let total: f64 = cut.stretches.iter().map(|s| area(s)).sum::<f64>() + area(&cut.remainder);
        prop_assert!((total - polygon_area(&outline)).abs() < 1e-6, "{} != {}", total, polygon_area(&outline));
        for (stretch, kept) in stretches.iter().zip(&cut.stretches) {
            let alone = split_setback_perimeter(&outline, std::slice::from_ref(stretch)).unwrap();
            prop_assert!(area(kept) <= area(&alone.stretches[0]) + 1e-9);
        }
    }
}
