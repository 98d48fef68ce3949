//! Tiny seeded generators whose integer output is the same on every platform.

use glam::DVec3;

/// SplitMix64 (Steele, Lea, Flood 2014): a 64-bit generator with one word of state.
///
/// Only integer arithmetic and one exact conversion are involved, so a seed gives the
/// same numbers on every platform, compiler and optimisation level — which the
/// deterministic fixtures of [`fixtures`](crate::fixtures) rely on. It is not
/// cryptographic and not meant for statistics beyond jittering test meshes.
///
/// # Examples
/// ```
/// use beltrami_testkit::SplitMix64;
/// let mut a = SplitMix64::new(7);
/// let mut b = SplitMix64::new(7);
/// assert_eq!(a.next_u64(), b.next_u64());
/// let u = a.next_symmetric();
/// assert!((-1.0..1.0).contains(&u));
/// ```
///
/// # References
/// G. L. Steele, D. Lea, C. H. Flood: *Fast splittable pseudorandom number generators*.
/// OOPSLA 2014.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator started from `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform number in `[0, 1)`: the top 53 bits over 2⁵³ (exact).
    pub fn next_unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform number in `[-1, 1)` (exact: `2u − 1`).
    pub fn next_symmetric(&mut self) -> f64 {
        2.0 * self.next_unit() - 1.0
    }

    /// A uniform number in `[lo, hi)`: `lo + (hi − lo) u` with `u` from
    /// [`next_unit`](Self::next_unit) (rounded, so `hi` itself can come out when the
    /// interval is wide compared with `lo`).
    pub fn next_range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_unit()
    }

    /// Three numbers of [`next_symmetric`](Self::next_symmetric), drawn in the order x,
    /// y, z: a point of the cube `[-1, 1)³`.
    pub fn next_symmetric_vector(&mut self) -> DVec3 {
        let x = self.next_symmetric();
        let y = self.next_symmetric();
        let z = self.next_symmetric();
        DVec3::new(x, y, z)
    }

    /// A standard normal number by the Box–Muller transform: two uniform numbers `u`,
    /// `v` from [`next_unit`](Self::next_unit) give `√(−2 ln(1 − u)) cos(2π v)` (the
    /// sine half of the pair is discarded).
    ///
    /// The integer part is the same on every platform; `ln` and `cos` come from the
    /// platform's math library, so the last bits may differ between platforms.
    ///
    /// # References
    /// G. E. P. Box, M. E. Muller: *A note on the generation of random normal deviates*.
    /// Annals of Mathematical Statistics 29, 1958.
    pub fn next_normal(&mut self) -> f64 {
        let u = 1.0 - self.next_unit();
        let v = self.next_unit();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// A 64-bit linear congruential generator with Knuth's MMIX constants
/// (`s ← 6364136223846793005 s + 1442695040888963407` mod 2⁶⁴), whose numbers are the
/// top 53 bits of the state.
///
/// Weaker than [`SplitMix64`] (the low bits of the state are periodic, and only the top
/// ones are used), but some test and bench meshes were jittered with it; it keeps them
/// the same to the last bit. Prefer [`SplitMix64`] for new fixtures.
///
/// # Examples
/// ```
/// use beltrami_testkit::Lcg64;
/// let mut g = Lcg64::new(1);
/// let u = g.next_symmetric();
/// assert!((-1.0..1.0).contains(&u));
/// ```
///
/// # References
/// D. E. Knuth: *The Art of Computer Programming*, vol. 2, 3rd ed., §3.3.4 (MMIX).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lcg64 {
    state: u64,
}

impl Lcg64 {
    /// A generator whose state starts at `state` (used as given: the first number comes
    /// from the state after one step).
    #[must_use]
    pub fn new(state: u64) -> Self {
        Self { state }
    }

    /// A uniform number in `[-1, 1)`: the next state's top 53 bits over 2⁵³, times 2,
    /// minus 1 (exact).
    pub fn next_symmetric(&mut self) -> f64 {
        self.state = self
            .state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Three numbers of [`next_symmetric`](Self::next_symmetric), drawn in the order x,
    /// y, z: a point of the cube `[-1, 1)³`.
    pub fn next_symmetric_vector(&mut self) -> DVec3 {
        let x = self.next_symmetric();
        let y = self.next_symmetric();
        let z = self.next_symmetric();
        DVec3::new(x, y, z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_published_sequence() {
        // First outputs for seed 0 from the reference implementation.
        let mut g = SplitMix64::new(0);
        assert_eq!(g.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(g.next_u64(), 0x6e78_9e6a_a1b9_65f4);
        // The stream `beltrami-metrics`' surface sampler checks for its own copy.
        let mut g = SplitMix64::new(1_234_567);
        assert_eq!(g.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(g.next_u64(), 3_203_168_211_198_807_973);
    }

    #[test]
    fn ranges_and_vectors_are_made_of_the_same_stream() {
        let (mut a, mut b) = (SplitMix64::new(3), SplitMix64::new(3));
        assert_eq!(a.next_range(-0.5, 1.5), -0.5 + 2.0 * b.next_unit());
        let v = a.next_symmetric_vector();
        assert_eq!(
            v,
            DVec3::new(b.next_symmetric(), b.next_symmetric(), b.next_symmetric())
        );
    }

    #[test]
    fn normal_numbers_have_unit_variance() {
        let mut g = SplitMix64::new(9);
        let xs: Vec<f64> = (0..20_000).map(|_| g.next_normal()).collect();
        assert!(xs.iter().all(|x| x.is_finite()));
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / xs.len() as f64;
        assert!(mean.abs() < 0.03, "{mean}");
        assert!((var - 1.0).abs() < 0.05, "{var}");
    }

    #[test]
    fn the_lcg_steps_with_the_mmix_constants() {
        let mut g = Lcg64::new(0);
        let state = 1_442_695_040_888_963_407_u64;
        assert_eq!(
            g.next_symmetric(),
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        );
        let xs: Vec<f64> = (0..1000).map(|_| g.next_symmetric()).collect();
        assert!(xs.iter().all(|x| (-1.0..1.0).contains(x)));
    }

    #[test]
    fn symmetric_numbers_stay_in_range_and_average_near_zero() {
        let mut g = SplitMix64::new(42);
        let xs: Vec<f64> = (0..10_000).map(|_| g.next_symmetric()).collect();
        assert!(xs.iter().all(|x| (-1.0..1.0).contains(x)));
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!(mean.abs() < 0.03, "{mean}");
    }
}
