//! The random draw of stochastic productions.
//!
//! Each module's draw is a pure function of the seed, the derivation step and the module's
//! position in the word it is rewritten from, so a word never depends on evaluation order,
//! on thread count or on how many draws other modules made.

const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// The SplitMix64 output function: a bijective mix of 64 bits.
const fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// What all draws of one step share: the seed mixed with the step number.
pub(crate) fn step_key(seed: u64, step: u32) -> u64 {
    mix(mix(seed ^ GOLDEN).wrapping_add(u64::from(step).wrapping_mul(GOLDEN)))
}

/// A uniform number in `[0, 1)` for the module at `position` of the step with key `key`.
#[inline]
pub(crate) fn draw(key: u64, position: usize) -> f64 {
    let bits = mix(key ^ (position as u64).wrapping_add(1).wrapping_mul(GOLDEN));
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_are_uniform_and_vary_with_every_input() {
        let key = step_key(7, 3);
        let n = 100_000;
        let mean = (0..n).map(|i| draw(key, i)).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.01, "mean {mean}");
        assert!((0..n).all(|i| (0.0..1.0).contains(&draw(key, i))));
        assert_ne!(draw(key, 5), draw(step_key(7, 4), 5));
        assert_ne!(draw(key, 5), draw(step_key(8, 3), 5));
        assert_ne!(draw(key, 5), draw(key, 6));
    }
}
