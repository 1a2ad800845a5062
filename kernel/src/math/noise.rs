//! Seeded coherent noise at a point: Perlin's improved gradient noise (Perlin, "Improving
//! noise", SIGGRAPH 2002: quintic fade, 12 edge gradients), simplex noise (Perlin 2001, in
//! Gustavson's formulation), value noise (random values at the lattice, quintic interpolation)
//! and Worley's cellular noise (Worley, "A cellular texture basis function", SIGGRAPH 1996:
//! distance to the nearest feature point), from the `noise` crate (noise-rs), summed over
//! octaves as fractional Brownian motion (Musgrave, in Ebert et al., "Texturing and Modeling",
//! ch. 16).
//!
//! Every kind is scaled into [−1, 1] and the octave sum is divided by the sum of its amplitudes,
//! so [`Noise::sample`] stays in [−1, 1] whatever the octaves. The crate uses only arithmetic,
//! `floor` and `sqrt` and seeds its permutation tables with a fixed generator, so a seed gives
//! the same field on every platform.

use noise::{NoiseFn, Perlin, Simplex, Value, Worley};
use thiserror::Error;

use super::{SplitMix64, Vec3};

/// The basis function of a [`Noise`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseKind {
    /// Improved Perlin gradient noise (Perlin 2002): zero at every lattice point.
    Perlin,
    /// Simplex noise (Perlin 2001): fewer directional artefacts, cheaper in 3D.
    Simplex,
    /// Value noise: random values at the lattice points, smoothly interpolated.
    Value,
    /// Worley cellular noise (Worley 1996): 2·d − 1, d the distance to the nearest feature
    /// point (one per unit cell), clamped to [−1, 1]: −1 at the feature points.
    Worley,
}

impl NoiseKind {
    /// The kinds' names as scripts spell them, in declaration order.
    pub const NAMES: [&'static str; 4] = ["perlin", "simplex", "value", "worley"];

    /// The kind named `name` (one of [`NoiseKind::NAMES`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<NoiseKind> {
        match name {
            "perlin" => Some(NoiseKind::Perlin),
            "simplex" => Some(NoiseKind::Simplex),
            "value" => Some(NoiseKind::Value),
            "worley" => Some(NoiseKind::Worley),
            _ => None,
        }
    }
}

/// The parameters of a [`Noise`]: basis, seed and the fractal sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseOptions {
    /// The basis function.
    pub kind: NoiseKind,
    /// Any integer: each octave (and each component of [`Noise::sample3`]) gets its own 32-bit
    /// seed drawn from it by [`SplitMix64`].
    pub seed: i64,
    /// Lattice cells per unit length of the first octave (> 0).
    pub frequency: f64,
    /// The number of octaves summed (1 to [`MAX_OCTAVES`]).
    pub octaves: u32,
    /// The frequency factor from one octave to the next (> 0; 2 doubles it).
    pub lacunarity: f64,
    /// The amplitude factor from one octave to the next (≥ 0; 0.5 halves it).
    pub gain: f64,
}

impl Default for NoiseOptions {
    fn default() -> NoiseOptions {
        NoiseOptions { kind: NoiseKind::Perlin, seed: 0, frequency: 1.0, octaves: 1, lacunarity: 2.0, gain: 0.5 }
    }
}

/// The most octaves a [`Noise`] sums.
pub const MAX_OCTAVES: u32 = 16;

/// The largest |coordinate × frequency| of any octave: beyond it f64 keeps no fraction of a
/// lattice cell (and the crate's integer cell index would overflow).
pub const MAX_LATTICE_COORDINATE: f64 = 1e15;

/// Why noise could not be made or sampled.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum NoiseError {
    /// An option outside its range.
    #[error("option `{name}` must be {range}, got {value}")]
    BadOption { name: &'static str, value: String, range: &'static str },
    /// A point so far out that the noise lattice has no resolution there.
    #[error(
        "the point ({x}, {y}, {z}) is too far out: at the finest octave a coordinate reaches {reach:e} \
         lattice cells, more than {MAX_LATTICE_COORDINATE:e}"
    )]
    TooFar { x: f64, y: f64, z: f64, reach: f64 },
}

/// One octave's basis function.
#[derive(Clone)]
enum Basis {
    Perlin(Perlin),
    Simplex(Simplex),
    Value(Value),
    Worley(Worley),
}

impl Basis {
    fn new(kind: NoiseKind, seed: u32) -> Basis {
        match kind {
            NoiseKind::Perlin => Basis::Perlin(Perlin::new(seed)),
            NoiseKind::Simplex => Basis::Simplex(Simplex::new(seed)),
            NoiseKind::Value => Basis::Value(Value::new(seed)),
            NoiseKind::Worley => {
                Basis::Worley(Worley::new(seed).set_return_type(noise::core::worley::ReturnType::Distance))
            }
        }
    }

    fn get(&self, p: [f64; 3]) -> f64 {
        let v = match self {
            Basis::Perlin(n) => n.get(p),
            Basis::Simplex(n) => n.get(p),
            Basis::Value(n) => n.get(p),
            Basis::Worley(n) => n.get(p),
        };
        v.clamp(-1.0, 1.0)
    }
}

/// A seeded noise field: [`Noise::sample`] a number in [−1, 1], [`Noise::sample3`] a vector of
/// three independent fields (for displacing points).
#[derive(Clone)]
pub struct Noise {
    options: NoiseOptions,
    /// The octaves of each of the three components, each with its own seed.
    octaves: [Vec<Basis>; 3],
    /// 1 / the sum of the octaves' amplitudes.
    norm: f64,
}

impl std::fmt::Debug for Noise {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Noise").field("options", &self.options).finish_non_exhaustive()
    }
}

impl Noise {
    /// The field `options` describe.
    ///
    /// # Errors
    /// [`NoiseError::BadOption`] for a frequency or lacunarity that is not finite and above 0, a
    /// gain that is negative or not finite, or octaves outside 1 to [`MAX_OCTAVES`].
    pub fn new(options: NoiseOptions) -> Result<Noise, NoiseError> {
        let bad = |name, value: f64, range| Err(NoiseError::BadOption { name, value: super::fmt_num(value), range });
        if !(options.frequency.is_finite() && options.frequency > 0.0) {
            return bad("frequency", options.frequency, "a finite number above 0");
        }
        if !(options.lacunarity.is_finite() && options.lacunarity > 0.0) {
            return bad("lacunarity", options.lacunarity, "a finite number above 0");
        }
        if !(options.gain.is_finite() && options.gain >= 0.0) {
            return bad("gain", options.gain, "a finite number of 0 or more");
        }
        if !(1..=MAX_OCTAVES).contains(&options.octaves) {
            return bad("octaves", f64::from(options.octaves), "between 1 and 16");
        }
        let seeds = |component: u64| {
            let mut s = SplitMix64::new((options.seed as u64) ^ component.wrapping_mul(0xD1B5_4A32_D192_ED03));
            (0..options.octaves).map(|_| Basis::new(options.kind, (s.next_u64() >> 32) as u32)).collect::<Vec<_>>()
        };
        let amplitude_sum: f64 = (0..options.octaves).map(|i| options.gain.powi(i as i32)).sum();
        Ok(Noise { options, octaves: [seeds(0), seeds(1), seeds(2)], norm: 1.0 / amplitude_sum })
    }

    /// The options this field was made with.
    #[must_use]
    pub fn options(&self) -> &NoiseOptions {
        &self.options
    }

    fn check(&self, p: Vec3) -> Result<(), NoiseError> {
        let o = &self.options;
        let reach = p.abs().max_element() * o.frequency * o.lacunarity.max(1.0).powi(o.octaves as i32 - 1);
        // (`max_element` skips NaN: a NaN coordinate is caught by `is_finite`.)
        if super::is_finite(p) && reach.is_finite() && reach <= MAX_LATTICE_COORDINATE {
            return Ok(());
        }
        Err(NoiseError::TooFar { x: p.x, y: p.y, z: p.z, reach })
    }

    fn fbm(&self, component: usize, p: Vec3) -> f64 {
        let o = &self.options;
        let (mut sum, mut amplitude, mut frequency) = (0.0, 1.0, o.frequency);
        for basis in &self.octaves[component] {
            let q = p * frequency;
            sum += amplitude * basis.get([q.x, q.y, q.z]);
            amplitude *= o.gain;
            frequency *= o.lacunarity;
        }
        (sum * self.norm).clamp(-1.0, 1.0)
    }

    /// The field at `p`, in [−1, 1].
    ///
    /// # Errors
    /// [`NoiseError::TooFar`] when a coordinate times the finest octave's frequency is beyond
    /// [`MAX_LATTICE_COORDINATE`] (or `p` is not finite).
    pub fn sample(&self, p: Vec3) -> Result<f64, NoiseError> {
        self.check(p)?;
        Ok(self.fbm(0, p))
    }

    /// Three independent fields at `p` (the first equal to [`Noise::sample`]), each in [−1, 1].
    ///
    /// # Errors
    /// As [`Noise::sample`].
    pub fn sample3(&self, p: Vec3) -> Result<Vec3, NoiseError> {
        self.check(p)?;
        Ok(Vec3::new(self.fbm(0, p), self.fbm(1, p), self.fbm(2, p)))
    }
}

#[cfg(test)]
#[path = "tests_noise.rs"]
mod tests;
