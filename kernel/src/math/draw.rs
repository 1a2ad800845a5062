//! Draws from distributions on the kernel's seeded stream ([`SplitMix64`]): uniform integers
//! in a closed range without bias, normal numbers, points in the unit ball and on the unit
//! sphere, and shuffles. Only IEEE-exact operations (+, −, ×, ÷, √) and `libm`'s pure-Rust
//! logarithm are used, so a seed gives the same numbers on every platform and build.

use super::{SplitMix64, Vec3};

impl SplitMix64 {
    /// A uniform integer in `lo..=hi` (both included), without modulo bias: Lemire's
    /// multiply-and-reject ("Fast random integer generation in an interval", 2019), which
    /// draws a second number only when the first falls in the biased zone (probability below
    /// span / 2⁶⁴). `lo > hi` is treated as the range `hi..=lo`.
    pub fn int_inclusive(&mut self, lo: i64, hi: i64) -> i64 {
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        // The number of values, minus one, as an unsigned span (wraps for the full i64 range).
        let span_minus_one = hi.wrapping_sub(lo) as u64;
        if span_minus_one == u64::MAX {
            return self.next_u64() as i64;
        }
        let span = span_minus_one + 1;
        let offset = self.below_u64(span);
        lo.wrapping_add(offset as i64)
    }

    /// A uniform number in `0..n` without bias (Lemire 2019). `n` = 0 counts as 1.
    pub fn below_u64(&mut self, n: u64) -> u64 {
        let n = n.max(1);
        let mut m = u128::from(self.next_u64()) * u128::from(n);
        let mut low = m as u64;
        if low < n {
            let threshold = n.wrapping_neg() % n;
            while low < threshold {
                m = u128::from(self.next_u64()) * u128::from(n);
                low = m as u64;
            }
        }
        (m >> 64) as u64
    }

    /// A standard normal number (mean 0, standard deviation 1) by Marsaglia's polar method
    /// (Marsaglia and Bray 1964): pairs in the unit disc by rejection, each accepted pair
    /// giving one number (the second is dropped so every draw advances the stream the same way
    /// whatever came before).
    pub fn standard_normal(&mut self) -> f64 {
        loop {
            let u = 2.0 * self.next_f64() - 1.0;
            let v = 2.0 * self.next_f64() - 1.0;
            let s = u * u + v * v;
            if s > 0.0 && s < 1.0 {
                return u * (-2.0 * libm::log(s) / s).sqrt();
            }
        }
    }

    /// A uniform point in the closed unit ball, by rejection from the cube [−1, 1]³ (accepts
    /// π/6 ≈ 52 % of the draws; three numbers per draw).
    pub fn in_unit_ball(&mut self) -> Vec3 {
        loop {
            let p = Vec3::new(2.0 * self.next_f64() - 1.0, 2.0 * self.next_f64() - 1.0, 2.0 * self.next_f64() - 1.0);
            if p.length_squared() <= 1.0 {
                return p;
            }
        }
    }

    /// A uniform direction: a point of the unit ball (away from its centre) scaled to length 1.
    /// Uniform because the ball's points are uniform in direction.
    pub fn unit_vector(&mut self) -> Vec3 {
        loop {
            let p = self.in_unit_ball();
            let l2 = p.length_squared();
            if l2 > 1e-12 {
                return p / l2.sqrt();
            }
        }
    }

    /// Shuffles `items` in place (Fisher–Yates, Durstenfeld's form: from the end, each item
    /// swapped with a uniform one at or before it), every order equally likely.
    pub fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            let j = self.below_u64(i as u64 + 1) as usize;
            items.swap(i, j);
        }
    }
}

#[cfg(test)]
#[path = "tests_draw.rs"]
mod tests;
