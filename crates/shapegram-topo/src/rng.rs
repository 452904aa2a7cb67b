//! Deterministic random numbers for rule choice: SplitMix64, one stream per shape.
//!
//! A shape's seed comes from its parent's seed and its position among the parent's sub-shapes,
//! so the same grammar, seed and initial shape choose the same rules whatever order shapes are
//! processed in.

const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// The SplitMix64 finaliser: a bijective mix of 64 bits.
pub const fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of the `ordinal`-th sub-shape of a shape with seed `parent`.
pub fn child_seed(parent: u64, ordinal: u32) -> u64 {
    mix(parent ^ mix(u64::from(ordinal).wrapping_add(1).wrapping_mul(GOLDEN)))
}

/// A uniform number in `[0, 1)` drawn from `seed` (53 random bits).
pub fn unit(seed: u64) -> f64 {
    (mix(seed.wrapping_add(GOLDEN)) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn children_get_distinct_seeds_and_draws_stay_in_range() {
        let seeds: Vec<u64> = (0..100).map(|k| child_seed(42, k)).collect();
        let mut sorted = seeds.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), 100);
        assert!(seeds.iter().all(|&s| (0.0..1.0).contains(&unit(s))));
        // Fixed values: a change here changes every generated model.
        assert_eq!(mix(0), 0);
        assert_eq!(mix(1), 0x5692_161D_100B_05E5);
    }
}
