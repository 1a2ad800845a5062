//! Seeded coherent noise at a point (API.md §Random; kernel `math::Noise`): `noise(p, #{…})` a
//! number in [−1, 1], `noise3(p, #{…})` a `Vec3` of three independent fields for displacing.
//! The field of the last options used is kept, so a loop over many points builds it once.

use std::cell::RefCell;
use std::rc::Rc;

use blocksmith_kernel::math::{Noise, NoiseKind, NoiseOptions, MAX_OCTAVES};
use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map};

use crate::convert::{fail, kernel, number, type_name, vec3, Options, ScriptResult, Vector};

/// Registers the noise functions on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_global_module(exported_module!(noise_api).into());
}

/// The options every noise function takes.
const KEYS: &[&str] = &["kind", "seed", "frequency", "octaves", "lacunarity", "gain"];

thread_local! {
    /// The field of the last options seen: a script sampling one field at many points builds
    /// its permutation tables once.
    static LAST: RefCell<Option<Rc<Noise>>> = const { RefCell::new(None) };
}

/// The field `opts` describe (checked, errors naming `func` and the option).
fn field(func: &'static str, opts: Map) -> ScriptResult<Rc<Noise>> {
    let o = Options::new(func, opts, KEYS)?;
    let kind = o.choice("kind", "perlin", &NoiseKind::NAMES)?;
    let octaves = o.int("octaves", 1)?;
    if !(1..=i64::from(MAX_OCTAVES)).contains(&octaves) {
        return fail(func, format!("option `octaves` must be between 1 and {MAX_OCTAVES}, got {octaves}"));
    }
    let options = NoiseOptions {
        kind: NoiseKind::from_name(&kind).unwrap_or(NoiseKind::Perlin),
        seed: o.int("seed", 0)?,
        frequency: o.number("frequency", 1.0)?,
        octaves: octaves as u32,
        lacunarity: o.number("lacunarity", 2.0)?,
        gain: o.number("gain", 0.5)?,
    };
    if let Some(n) = LAST.with(|l| l.borrow().as_ref().filter(|n| *n.options() == options).cloned()) {
        return Ok(n);
    }
    let n = Rc::new(kernel(func, Noise::new(options))?);
    LAST.with(|l| *l.borrow_mut() = Some(n.clone()));
    Ok(n)
}

/// A point: a `Vec3`, or an array of 2 (z = 0) or 3 numbers.
fn point(func: &str, p: &Dynamic) -> ScriptResult<Vec3> {
    if let Some(a) = p.read_lock::<Array>() {
        if a.len() == 2 {
            return Ok(Vec3::new(number(func, "p[0]", &a[0])?, number(func, "p[1]", &a[1])?, 0.0));
        }
        if a.len() != 3 {
            return fail(
                func,
                format!("argument `p` must be a Vec3 or an array of 2 or 3 numbers, got {}", type_name(p)),
            );
        }
    }
    vec3(func, "p", p)
}

#[export_module]
pub mod noise_api {
    use super::*;

    /// Seeded noise at point `p` (a `Vec3`, or `[x, y]` / `[x, y, z]`), a number in [−1, 1]
    /// that changes smoothly with `p`. Options: `kind` `"perlin"` (Perlin's improved noise,
    /// 2002; the default), `"simplex"`, `"value"` or `"worley"` (cellular: −1 at the cell
    /// points, rising with the distance to the nearest); `seed` (any integer, default 0);
    /// `frequency` (cells per unit, default 1); `octaves` (1–16, default 1), each `lacunarity`
    /// (default 2) times finer and `gain` (default 0.5) times weaker than the last, the sum
    /// divided by the sum of the weights so it stays in [−1, 1].
    ///
    /// ```rhai
    /// let h = noise([0.3, 0.7], #{seed: 4, octaves: 5, frequency: 0.5});
    /// assert(h >= -1.0 && h <= 1.0);
    /// assert_eq(h, noise([0.3, 0.7, 0.0], #{seed: 4, octaves: 5, frequency: 0.5}));
    /// assert(noise(vec3(1, 2, 3), #{kind: "worley"}) >= -1.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn noise(p: Vector, options: Map) -> ScriptResult<f64> {
        let q = point("noise", &p)?;
        kernel("noise", field("noise", options)?.sample(q))
    }

    /// `noise(p, #{})`: Perlin noise of seed 0, frequency 1, one octave.
    ///
    /// ```rhai
    /// assert_eq(noise([1, 2, 3]), 0.0);     // zero on the lattice
    /// assert(noise([0.5, 0.25, 0.1]) != 0.0);
    /// ```
    #[rhai_fn(return_raw, name = "noise")]
    pub fn noise_default(p: Vector) -> ScriptResult<f64> {
        noise(p, Map::new())
    }

    /// Three independent noise fields at `p` as a `Vec3`, each in [−1, 1] (the x field is
    /// `noise(p, options)`); the options are `noise`'s. For displacing points:
    /// `m.warp(|p| p + noise3(p, #{seed: 1}) * 0.1)`.
    ///
    /// ```rhai
    /// let d = noise3([0.2, 0.4, 0.6], #{seed: 9, kind: "simplex"});
    /// assert_eq(d.x, noise([0.2, 0.4, 0.6], #{seed: 9, kind: "simplex"}));
    /// assert(d.y != d.x && d.z >= -1.0 && d.z <= 1.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn noise3(p: Vector, options: Map) -> ScriptResult<Vec3> {
        let q = point("noise3", &p)?;
        kernel("noise3", field("noise3", options)?.sample3(q))
    }

    /// `noise3(p, #{})`: three Perlin fields, frequency 1, one octave.
    ///
    /// ```rhai
    /// let d = noise3(vec3(0.5, 0.5, 0.5));
    /// assert(d.length() <= sqrt(3.0));
    /// ```
    #[rhai_fn(return_raw, name = "noise3")]
    pub fn noise3_default(p: Vector) -> ScriptResult<Vec3> {
        noise3(p, Map::new())
    }
}
