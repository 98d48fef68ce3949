//! A small reproducible random stream for surface sampling.
//!
//! This is the one generator of the metrics library ([`SurfaceIndex::sample_surface`]
//! draws from it). It is the same algorithm as `beltrami_testkit::SplitMix64`, which the
//! tests, benches and examples use, with the same outputs (both check the published
//! stream); the library keeps its own few lines because test support is not a dependency
//! of the library.
//!
//! [`SurfaceIndex::sample_surface`]: super::SurfaceIndex::sample_surface

/// SplitMix64 (Steele, Lea, Flood 2014): a 64-bit state advanced by a Weyl increment and
/// scrambled by two multiply–xorshift rounds. Fast, reproducible on every platform, and
/// good enough for sample positions (it passes BigCrush).
#[derive(Clone, Debug)]
pub(crate) struct SplitMix64(u64);

impl SplitMix64 {
    /// A stream starting from `seed`.
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in `[0, 1)` with 53 random bits.
    pub(crate) fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::SplitMix64;

    #[test]
    fn matches_the_reference_stream() {
        // First outputs of the reference C implementation for seed 1234567.
        let mut rng = SplitMix64::new(1_234_567);
        assert_eq!(rng.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(rng.next_u64(), 3_203_168_211_198_807_973);
        let x = rng.next_f64();
        assert!((0.0..1.0).contains(&x));
    }
}
