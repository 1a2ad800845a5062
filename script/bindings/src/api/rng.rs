//! Seeded random numbers (API.md §Random; kernel `math::SplitMix64` and its draws): `rng(seed)`
//! makes an `Rng`, a handle on one stream. Every copy of the handle — an argument to a helper
//! `fn`, an element of an array, `let b = a;` — draws from the same stream, so a helper that
//! takes the `Rng` advances it for its caller. The numbers are SplitMix64's (Steele, Lea and
//! Flood 2014) and the same on every platform and build.

use std::cell::RefCell;
use std::fmt;
use std::rc::Rc;

use blocksmith_kernel::math::{fmt_num, SplitMix64};
use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, INT};

use crate::convert::{fail, number, type_name, Integer, Number, ScriptResult};

/// A seeded random stream as scripts hold it (script type `Rng`): every clone shares the
/// stream, so a helper function given the `Rng` advances it.
#[derive(Clone)]
pub struct Rng(Rc<RefCell<SplitMix64>>);

impl Rng {
    /// A stream starting from `seed`.
    #[must_use]
    pub fn new(seed: INT) -> Rng {
        Rng(Rc::new(RefCell::new(SplitMix64::new(seed as u64))))
    }

    /// Runs `f` on the stream (never borrowed across a script call).
    fn with<T>(&self, f: impl FnOnce(&mut SplitMix64) -> T) -> T {
        f(&mut self.0.borrow_mut())
    }
}

impl fmt::Debug for Rng {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Rng")
    }
}

/// Registers `Rng` and the random functions on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<Rng>("Rng");
    engine.register_global_module(exported_module!(rng_api).into());
}

fn int_arg(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<INT> {
    v.as_int().or_else(|_| fail(func, format!("argument `{arg}` must be an integer, got {}", type_name(v))))
}

#[export_module]
pub mod rng_api {
    use super::*;

    /// A random stream seeded by `seed` (any integer): the same seed gives the same numbers on
    /// every run, platform and build. The `Rng` is shared, not copied: a helper function that
    /// is given it advances it, so successive calls give new numbers.
    ///
    /// ```rhai
    /// fn jitter(r) { r.range(-1.0, 1.0) }   // advances the caller's stream
    /// let r = rng(7);
    /// let a = jitter(r);
    /// let b = jitter(r);
    /// assert(a != b);
    /// assert_eq(rng(7).float(), rng(7).float());
    /// ```
    pub fn rng(seed: INT) -> Rng {
        Rng::new(seed)
    }

    /// A uniform number in [0, 1) with 53 random bits.
    ///
    /// ```rhai
    /// let x = rng(1).float();
    /// assert(x >= 0.0 && x < 1.0);
    /// ```
    pub fn float(r: &mut Rng) -> f64 {
        r.with(SplitMix64::next_f64)
    }

    /// A uniform number in [a, b) (a = b gives a). Integers and floats are both taken.
    ///
    /// ```rhai
    /// let r = rng(2);
    /// let x = r.range(10, 20.5);
    /// assert(x >= 10.0 && x < 20.5);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn range(r: &mut Rng, a: Number, b: Number) -> ScriptResult<f64> {
        let (lo, hi) = (number("range", "a", &a)?, number("range", "b", &b)?);
        if hi < lo {
            return fail("range", format!("argument `b` ({}) must not be below `a` ({})", fmt_num(hi), fmt_num(lo)));
        }
        if !(hi - lo).is_finite() {
            return fail("range", "the interval from `a` to `b` is wider than a float can hold");
        }
        let u = r.with(SplitMix64::next_f64);
        // lo + (hi − lo)·u can round up to hi: keep the interval half-open.
        let x = lo + (hi - lo) * u;
        Ok(if x >= hi && hi > lo { hi.next_down().max(lo) } else { x })
    }

    /// A uniform integer from `a` to `b`, both included, without bias (Lemire's method).
    ///
    /// ```rhai
    /// let r = rng(3);
    /// let die = r.int(1, 6);
    /// assert(die >= 1 && die <= 6);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn int(r: &mut Rng, a: Integer, b: Integer) -> ScriptResult<INT> {
        let (lo, hi) = (int_arg("int", "a", &a)?, int_arg("int", "b", &b)?);
        if hi < lo {
            return fail("int", format!("argument `b` ({hi}) must not be below `a` ({lo})"));
        }
        Ok(r.with(|s| s.int_inclusive(lo, hi)))
    }

    /// A normal (Gaussian) number with mean `mean` and standard deviation `sd` (≥ 0), by
    /// Marsaglia's polar method.
    ///
    /// ```rhai
    /// let r = rng(4);
    /// let xs = [];
    /// for i in 0..2000 { xs.push(r.normal(10, 2)); }
    /// let mean = xs.reduce(|s, x| s + x, 0.0) / xs.len();
    /// assert(abs(mean - 10.0) < 0.3);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn normal(r: &mut Rng, mean: Number, sd: Number) -> ScriptResult<f64> {
        let (m, s) = (number("normal", "mean", &mean)?, number("normal", "sd", &sd)?);
        if s < 0.0 {
            return fail("normal", format!("argument `sd` must be 0 or more, got {}", fmt_num(s)));
        }
        Ok(m + s * r.with(SplitMix64::standard_normal))
    }

    /// One element of `array`, each equally likely.
    ///
    /// ```rhai
    /// let c = rng(5).choice(["oak", "ash", "elm"]);
    /// assert(["oak", "ash", "elm"].contains(c));
    /// ```
    #[rhai_fn(return_raw)]
    pub fn choice(r: &mut Rng, array: Array) -> ScriptResult<Dynamic> {
        if array.is_empty() {
            return fail("choice", "argument `array` is empty: there is nothing to choose");
        }
        let i = r.with(|s| s.below_u64(array.len() as u64)) as usize;
        Ok(array[i].clone())
    }

    /// A copy of `array` in a random order (Fisher–Yates), every order equally likely; the
    /// array given is left as it was.
    ///
    /// ```rhai
    /// let a = [1, 2, 3, 4, 5];
    /// let s = rng(6).shuffle(a);
    /// assert_eq(s.len(), 5);
    /// assert_eq(a, [1, 2, 3, 4, 5]);
    /// s.sort();
    /// assert_eq(s, a);
    /// ```
    pub fn shuffle(r: &mut Rng, array: Array) -> Array {
        let mut out = array;
        r.with(|s| s.shuffle(&mut out));
        out
    }

    /// A random direction: a `Vec3` of length 1, uniform over the sphere.
    ///
    /// ```rhai
    /// let d = rng(8).unit_vector();
    /// assert(abs(d.length() - 1.0) < 1e-12);
    /// ```
    pub fn unit_vector(r: &mut Rng) -> Vec3 {
        r.with(SplitMix64::unit_vector)
    }

    /// A random point in the ball of radius 1 about the origin, uniform in volume.
    ///
    /// ```rhai
    /// let p = rng(9).in_sphere();
    /// assert(p.length() <= 1.0);
    /// ```
    pub fn in_sphere(r: &mut Rng) -> Vec3 {
        r.with(SplitMix64::in_unit_ball)
    }
}
