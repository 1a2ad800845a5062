//! Growth (seed 004, §9.1): the plant grows from being collapsed on its root to its modelled
//! shape. Each node's length (its offset from its parent) and thickness (the scale of its
//! vertices' offsets) are interpolated from 0 to 1, each with its own delay and speed; a node
//! `d` segments from the root starts growing at `d × delay`, so later parts mature later, as
//! the thesis observes ("parts mature in sequence from base to apex").

use super::nodes::{NodeState, Tree};
use super::AnimError;
use crate::math::fmt_num;

/// The interpolation curve of a growth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Curve {
    /// f(x) = x.
    Linear,
    /// The thesis's sigmoid 1/(1 + e^(5 − 10x)) (Fig. 9.1), rescaled to run exactly from 0 to 1
    /// (the raw curve gives 0.0067 at x = 0 and 0.9933 at x = 1, which would leave a plant that
    /// never collapses nor reaches its modelled shape).
    #[default]
    Sigmoid,
}

impl Curve {
    /// The curve at `x`, clamped to [0, 1]; exactly 0 at 0 and exactly 1 at 1.
    #[must_use]
    pub fn eval(self, x: f64) -> f64 {
        let x = x.clamp(0.0, 1.0);
        match self {
            Curve::Linear => x,
            Curve::Sigmoid => {
                let s = |x: f64| 1.0 / (1.0 + (5.0 - 10.0 * x).exp());
                (s(x) - s(0.0)) / (s(1.0) - s(0.0))
            }
        }
    }
}

/// The growth modifier's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Growth {
    /// Time between the onsets of a node and of its children, for the length. Default 1.
    pub delay: f64,
    /// How fast a node's length grows: it takes `1 / speed` from onset to full length. Default 1.
    pub speed: f64,
    /// As `delay`, for the thickness. Default 1.
    pub thickness_delay: f64,
    /// As `speed`, for the thickness. Default 1.
    pub thickness_speed: f64,
    /// The interpolation curve. Default [`Curve::Sigmoid`].
    pub curve: Curve,
}

/// The slowest growth speed: a node takes at most 1,000 time units to grow, so that the
/// animation's duration (and the frames that cover it) stays countable.
pub const MIN_SPEED: f64 = 1e-3;
/// The fastest growth speed.
pub const MAX_SPEED: f64 = 1e9;
/// The longest delay between a node's onset and its children's.
pub const MAX_DELAY: f64 = 1e3;

impl Default for Growth {
    fn default() -> Self {
        Growth { delay: 1.0, speed: 1.0, thickness_delay: 1.0, thickness_speed: 1.0, curve: Curve::Sigmoid }
    }
}

impl Growth {
    /// Checks the parameters: delays from 0 to [`MAX_DELAY`], speeds from [`MIN_SPEED`] to
    /// [`MAX_SPEED`].
    ///
    /// # Errors
    /// [`AnimError::InvalidParameter`] naming the parameter.
    pub fn validate(&self) -> Result<(), AnimError> {
        for (name, v) in [("delay", self.delay), ("thickness_delay", self.thickness_delay)] {
            if !(v.is_finite() && (0.0..=MAX_DELAY).contains(&v)) {
                return Err(AnimError::InvalidParameter {
                    name,
                    reason: format!("must be a number from 0 to {MAX_DELAY}, got {}", fmt_num(v)),
                });
            }
        }
        for (name, v) in [("speed", self.speed), ("thickness_speed", self.thickness_speed)] {
            if !(v.is_finite() && (MIN_SPEED..=MAX_SPEED).contains(&v)) {
                return Err(AnimError::InvalidParameter {
                    name,
                    reason: format!(
                        "must be a number from {MIN_SPEED} to {} (growing takes 1 / speed), got {}",
                        fmt_num(MAX_SPEED),
                        fmt_num(v)
                    ),
                });
            }
        }
        Ok(())
    }

    /// The time at which a node at `depth` starts growing in length.
    #[must_use]
    pub fn onset(&self, depth: u32) -> f64 {
        self.delay * f64::from(depth)
    }

    /// The time at which every node of a tree `max_depth` deep has reached its full length and
    /// thickness.
    #[must_use]
    pub fn end(&self, max_depth: u32) -> f64 {
        let d = f64::from(max_depth);
        (self.delay * d + 1.0 / self.speed).max(self.thickness_delay * d + 1.0 / self.thickness_speed)
    }

    /// The length and thickness factors of a node at `depth` at time `t`.
    #[must_use]
    pub fn factors(&self, depth: u32, t: f64) -> (f64, f64) {
        let d = f64::from(depth);
        let length = self.curve.eval((t - self.delay * d) * self.speed);
        let thickness = self.curve.eval((t - self.thickness_delay * d) * self.thickness_speed);
        (length, thickness)
    }

    /// Applies the growth at time `t` to `states` (parents before children): each node's
    /// offset from its parent is scaled by its length factor, its thickness by its thickness
    /// factor. Written so that factors of exactly 1 give back the input bit for bit.
    pub(crate) fn apply(&self, tree: &Tree, t: f64, states: &mut [NodeState]) {
        let input: Vec<NodeState> = states.to_vec();
        for &n in &tree.order {
            let n = n as usize;
            let (length, thickness) = self.factors(tree.depth[n], t);
            if let Some(p) = tree.parent[n] {
                let p = p as usize;
                let offset = input[n].position - input[p].position;
                states[n].position =
                    input[n].position + (states[p].position - input[p].position) + (length - 1.0) * offset;
            }
            states[n].thickness = input[n].thickness * thickness;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_run_exactly_from_zero_to_one() {
        for c in [Curve::Linear, Curve::Sigmoid] {
            assert_eq!(c.eval(0.0), 0.0);
            assert_eq!(c.eval(1.0), 1.0);
            assert_eq!(c.eval(-3.0), 0.0);
            assert_eq!(c.eval(7.0), 1.0);
            // Monotone.
            let mut last = -1.0;
            for i in 0..=100 {
                let y = c.eval(f64::from(i) / 100.0);
                assert!(y >= last);
                last = y;
            }
        }
        // The sigmoid is symmetric about (½, ½) and slow at both ends.
        assert!((Curve::Sigmoid.eval(0.5) - 0.5).abs() < 1e-15);
        assert!(Curve::Sigmoid.eval(0.1) < 0.05);
    }

    #[test]
    fn bad_parameters_are_named() {
        let g = Growth { speed: -1.0, ..Growth::default() };
        assert!(matches!(g.validate(), Err(AnimError::InvalidParameter { name: "speed", .. })));
        let g = Growth { thickness_delay: f64::NAN, ..Growth::default() };
        assert!(matches!(g.validate(), Err(AnimError::InvalidParameter { name: "thickness_delay", .. })));
    }
}
