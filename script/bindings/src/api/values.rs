//! `Vec3`: construction, fields, arithmetic and the usual vector functions.

use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::INT;

use crate::convert::{number, vec3 as to_vec3, Number, NumberOrVector, ScriptResult, Vector};

#[export_module]
pub mod vec3_api {
    use super::*;

    /// A point or direction `(x, y, z)`. Integers are accepted for any coordinate.
    ///
    /// ```rhai
    /// let p = vec3(1, 2.5, 0);
    /// assert_eq(p.y, 2.5);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn vec3(x: Number, y: Number, z: Number) -> ScriptResult<Vec3> {
        Ok(Vec3::new(number("vec3", "x", &x)?, number("vec3", "y", &y)?, number("vec3", "z", &z)?))
    }

    /// The x coordinate.
    ///
    /// ```rhai
    /// let v = vec3(1, 2, 3);
    /// assert_eq(v.x, 1.0);
    /// v.x = 5;
    /// assert_eq(v, vec3(5, 2, 3));
    /// ```
    #[rhai_fn(get = "x", pure)]
    pub fn get_x(v: &mut Vec3) -> f64 {
        v.x
    }
    /// The y coordinate.
    ///
    /// ```rhai
    /// let v = vec3(1, 2, 3);
    /// assert_eq(v.y, 2.0);
    /// v.y = 5;
    /// assert_eq(v, vec3(1, 5, 3));
    /// ```
    #[rhai_fn(get = "y", pure)]
    pub fn get_y(v: &mut Vec3) -> f64 {
        v.y
    }
    /// The z coordinate.
    ///
    /// ```rhai
    /// let v = vec3(1, 2, 3);
    /// assert_eq(v.z, 3.0);
    /// v.z = 5;
    /// assert_eq(v, vec3(1, 2, 5));
    /// ```
    #[rhai_fn(get = "z", pure)]
    pub fn get_z(v: &mut Vec3) -> f64 {
        v.z
    }
    /// Sets the x coordinate.
    #[rhai_fn(set = "x", return_raw)]
    pub fn set_x(v: &mut Vec3, x: Number) -> ScriptResult<()> {
        v.x = number("x", "value", &x)?;
        Ok(())
    }
    /// Sets the y coordinate.
    #[rhai_fn(set = "y", return_raw)]
    pub fn set_y(v: &mut Vec3, y: Number) -> ScriptResult<()> {
        v.y = number("y", "value", &y)?;
        Ok(())
    }
    /// Sets the z coordinate.
    #[rhai_fn(set = "z", return_raw)]
    pub fn set_z(v: &mut Vec3, z: Number) -> ScriptResult<()> {
        v.z = number("z", "value", &z)?;
        Ok(())
    }

    /// Vector sum.
    ///
    /// ```rhai
    /// assert_eq(vec3(1, 2, 3) + vec3(1, 1, 1), vec3(2, 3, 4));
    /// ```
    #[rhai_fn(name = "+")]
    pub fn add(a: Vec3, b: Vec3) -> Vec3 {
        a + b
    }
    /// Vector difference.
    ///
    /// ```rhai
    /// assert_eq(vec3(3, 3, 3) - vec3(1, 2, 3), vec3(2, 1, 0));
    /// ```
    #[rhai_fn(name = "-")]
    pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
        a - b
    }
    /// The opposite vector.
    ///
    /// ```rhai
    /// assert_eq(-vec3(1, 0, 0), vec3(-1, 0, 0));
    /// ```
    #[rhai_fn(name = "-")]
    pub fn neg(a: Vec3) -> Vec3 {
        -a
    }
    /// Vector times a number (component-wise with a vector).
    ///
    /// ```rhai
    /// assert_eq(vec3(1, 2, 3) * 2, vec3(2, 4, 6));
    /// assert_eq(2.0 * vec3(1, 2, 3), vec3(2, 4, 6));
    /// ```
    #[rhai_fn(name = "*", return_raw)]
    pub fn mul(a: Vec3, s: NumberOrVector) -> ScriptResult<Vec3> {
        if let Some(b) = s.clone().try_cast::<Vec3>() {
            return Ok(a * b);
        }
        Ok(a * number("*", "factor", &s)?)
    }
    /// A number times a vector.
    #[rhai_fn(name = "*")]
    pub fn mul_float_left(s: f64, a: Vec3) -> Vec3 {
        a * s
    }
    /// An integer times a vector.
    #[rhai_fn(name = "*")]
    pub fn mul_int_left(s: INT, a: Vec3) -> Vec3 {
        a * s as f64
    }
    /// Vector divided by a number (component-wise with a vector).
    ///
    /// ```rhai
    /// assert_eq(vec3(2, 4, 6) / 2, vec3(1, 2, 3));
    /// assert_eq(vec3(2, 4, 6) / vec3(2, 4, 6), vec3(1, 1, 1));
    /// ```
    #[rhai_fn(name = "/", return_raw)]
    pub fn div(a: Vec3, s: NumberOrVector) -> ScriptResult<Vec3> {
        let d = if let Some(b) = s.clone().try_cast::<Vec3>() { b } else { Vec3::splat(number("/", "divisor", &s)?) };
        if d.x == 0.0 || d.y == 0.0 || d.z == 0.0 {
            return Err("/: division of a Vec3 by zero".into());
        }
        Ok(a / d)
    }
    /// Exact equality of all three coordinates.
    ///
    /// ```rhai
    /// assert(vec3(1, 2, 3) == vec3(1, 2, 3), "equal");
    /// ```
    #[rhai_fn(name = "==")]
    pub fn eq(a: Vec3, b: Vec3) -> bool {
        a == b
    }
    /// Inequality.
    ///
    /// ```rhai
    /// assert(vec3(1, 2, 3) != vec3(1, 2, 4), "not equal");
    /// ```
    #[rhai_fn(name = "!=")]
    pub fn ne(a: Vec3, b: Vec3) -> bool {
        a != b
    }

    /// Dot product. Arrays of 3 numbers are accepted for either vector.
    ///
    /// Topic: math
    ///
    /// ```rhai
    /// assert_eq(dot(vec3(1, 2, 3), [4, 5, 6]), 32.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn dot(a: Vector, b: Vector) -> ScriptResult<f64> {
        Ok(to_vec3("dot", "a", &a)?.dot(to_vec3("dot", "b", &b)?))
    }
    /// Cross product (right-handed).
    ///
    /// Topic: math
    ///
    /// ```rhai
    /// assert_eq(cross(vec3(1, 0, 0), vec3(0, 1, 0)), vec3(0, 0, 1));
    /// ```
    #[rhai_fn(return_raw)]
    pub fn cross(a: Vector, b: Vector) -> ScriptResult<Vec3> {
        Ok(to_vec3("cross", "a", &a)?.cross(to_vec3("cross", "b", &b)?))
    }
    /// Euclidean length.
    ///
    /// Topic: math
    ///
    /// ```rhai
    /// assert_eq(length(vec3(3, 4, 0)), 5.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn length(v: Vector) -> ScriptResult<f64> {
        Ok(to_vec3("length", "v", &v)?.length())
    }
    /// The unit vector in the direction of `v`; an error for the zero vector.
    ///
    /// Topic: math
    ///
    /// ```rhai
    /// assert_eq(normalize(vec3(0, 0, 2)), vec3(0, 0, 1));
    /// ```
    #[rhai_fn(return_raw)]
    pub fn normalize(v: Vector) -> ScriptResult<Vec3> {
        to_vec3("normalize", "v", &v)?
            .try_normalize()
            .ok_or_else(|| "normalize: argument `v` is the zero vector, which has no direction".into())
    }
    /// Distance between two points.
    ///
    /// Topic: math
    ///
    /// ```rhai
    /// assert_eq(distance(vec3(0, 0, 0), [3, 4, 0]), 5.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn distance(a: Vector, b: Vector) -> ScriptResult<f64> {
        Ok(to_vec3("distance", "a", &a)?.distance(to_vec3("distance", "b", &b)?))
    }
    /// Linear interpolation `a + (b − a)·t`.
    ///
    /// Topic: math
    ///
    /// ```rhai
    /// assert_eq(lerp(vec3(0, 0, 0), vec3(2, 4, 6), 0.5), vec3(1, 2, 3));
    /// ```
    #[rhai_fn(return_raw)]
    pub fn lerp(a: Vector, b: Vector, t: Number) -> ScriptResult<Vec3> {
        Ok(to_vec3("lerp", "a", &a)?.lerp(to_vec3("lerp", "b", &b)?, number("lerp", "t", &t)?))
    }

    /// `vec3(x, y, z)` as text.
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(v: &mut Vec3) -> String {
        format!("vec3({}, {}, {})", v.x, v.y, v.z)
    }
    /// The coordinates as an array `[x, y, z]`.
    ///
    /// ```rhai
    /// assert_eq(vec3(1, 2, 3).to_array(), [1.0, 2.0, 3.0]);
    /// ```
    #[rhai_fn(pure)]
    pub fn to_array(v: &mut Vec3) -> rhai::Array {
        vec![Dynamic::from(v.x), Dynamic::from(v.y), Dynamic::from(v.z)]
    }
}
