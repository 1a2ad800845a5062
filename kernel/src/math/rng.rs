//! SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators", 2014):
//! the kernel's one seeded generator — behind every stochastic choice of an L-system, so the same
//! seed gives the same plant on every platform, and behind the randomised tests.

/// A SplitMix64 stream: 64 bits of state, the same numbers from the same seed everywhere.
///
/// See also [`SplitMix64::new`], [`SplitMix64::next_u64`], [`SplitMix64::next_f64`],
/// [`SplitMix64::below`].
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A stream starting from `seed`.
    #[must_use]
    pub fn new(seed: u64) -> SplitMix64 {
        SplitMix64 { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in [0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A number in `0..n` (an index to pick): the remainder of [`SplitMix64::next_u64`] by `n`,
    /// biased by at most n / 2⁶⁴, which no choice among a few options can see. `n` = 0 counts
    /// as 1.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_reference_sequence() {
        // The reference implementation (Vigna's splitmix64.c) from seed 0 starts with these.
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    }

    #[test]
    fn below_is_the_remainder_of_the_next_number() {
        // `below` draws one number from the stream, so it stays in step with `next_u64`.
        let (mut a, mut b) = (SplitMix64::new(9), SplitMix64::new(9));
        for n in [1, 2, 7, 1000] {
            assert_eq!(a.below(n), (b.next_u64() % n as u64) as usize);
        }
        // 0 counts as 1, and still draws.
        assert_eq!(a.below(0), 0);
        b.next_u64();
        assert_eq!(a.next_u64(), b.next_u64());
    }

    #[test]
    fn uniform_numbers_stay_in_the_unit_interval_with_mean_one_half() {
        let mut r = SplitMix64::new(42);
        let n = 100_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let x = r.next_f64();
            assert!((0.0..1.0).contains(&x));
            sum += x;
        }
        // Standard error of the mean: sqrt(1/12 / n) ≈ 0.0009; allow 5 of them.
        let mean = sum / n as f64;
        assert!((mean - 0.5).abs() < 0.0045, "mean {mean}, off by {}", mean - 0.5);
    }
}
