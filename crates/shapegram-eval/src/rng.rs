//! Deterministic random numbers: one stream per shape, seeded from its place in the derivation.
//!
//! A shape's seed is derived from its parent's seed and its birth order among the parent's
//! children, never from a global counter, so the same grammar, seed and attributes draw the same
//! numbers whatever the evaluation order or thread count.

/// SplitMix64: tiny, fast and statistically sound for this use; fully specified here so results
/// never change with a dependency upgrade.
///
/// The seed is mixed on the first draw, not when the stream is made: most shapes never draw.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rng {
    state: u64,
    mixed: bool,
}

const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// The SplitMix64 output function: a bijective mix of 64 bits.
pub const fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of the `ordinal`-th child (0-based) of a shape with seed `parent`.
pub fn child_seed(parent: u64, ordinal: u64) -> u64 {
    let key = match ORDINAL_KEYS.get(ordinal as usize) {
        Some(&key) if ordinal < ORDINAL_KEYS.len() as u64 => key,
        _ => ordinal_key(ordinal),
    };
    mix(parent ^ key)
}

/// What the seed of a shape's `ordinal`-th child mixes into the shape's seed.
const fn ordinal_key(ordinal: u64) -> u64 {
    mix(ordinal.wrapping_add(1).wrapping_mul(GOLDEN))
}

/// [`ordinal_key`] of the first children, worked out once.
const ORDINAL_KEYS: [u64; 64] = {
    let mut keys = [0; 64];
    let mut i = 0;
    while i < keys.len() {
        keys[i] = ordinal_key(i as u64);
        i += 1;
    }
    keys
};

impl Rng {
    /// A stream seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            state: seed,
            mixed: false,
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        if !self.mixed {
            self.state = mix(self.state);
            self.mixed = true;
        }
        self.state = self.state.wrapping_add(GOLDEN);
        mix(self.state)
    }

    /// A uniform number in `[0, 1)` with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform number in `[lo, hi)` (or `[hi, lo)` when reversed).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<u64> = (0..4).map(|_| Rng::new(7).next_u64()).collect();
        assert!(a.windows(2).all(|w| w[0] == w[1]));
        let mut r = Rng::new(7);
        let first = r.next_u64();
        assert_ne!(first, r.next_u64());
        assert_ne!(child_seed(7, 0), child_seed(7, 1));
        assert_ne!(child_seed(7, 0), child_seed(8, 0));
    }

    #[test]
    fn child_seeds_match_their_definition() {
        for parent in [0, 7, u64::MAX] {
            for ordinal in [0, 1, 63, 64, 65, 1000, u64::MAX] {
                let key = mix(ordinal.wrapping_add(1).wrapping_mul(GOLDEN));
                assert_eq!(child_seed(parent, ordinal), mix(parent ^ key));
            }
        }
        let mut lazy = Rng::new(42);
        let mut state = mix(42);
        for _ in 0..3 {
            state = state.wrapping_add(GOLDEN);
            assert_eq!(lazy.next_u64(), mix(state));
        }
    }

    #[test]
    fn floats_are_uniform_in_range() {
        let mut r = Rng::new(1);
        let draws: Vec<f64> = (0..10_000).map(|_| r.range(2.0, 4.0)).collect();
        assert!(draws.iter().all(|&d| (2.0..4.0).contains(&d)));
        let mean = draws.iter().sum::<f64>() / draws.len() as f64;
        assert!((mean - 3.0).abs() < 0.03, "{mean}");
    }
}
