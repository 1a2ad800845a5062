//! Numbers as messages show them: short, never a 300-digit decimal.

/// `x` as Rust prints it when that is short (`0.5`, `1000`, `-3.25`), else in scientific
/// notation (`1e300`, `1.5e-12`); `NaN`, `inf` and `-inf` as such.
#[must_use]
pub fn fmt_num(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-6..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_and_tiny_numbers_are_scientific_others_plain() {
        assert_eq!(fmt_num(1e300), "1e300");
        assert_eq!(fmt_num(-1.5e-300), "-1.5e-300");
        assert_eq!(fmt_num(0.25), "0.25");
        assert_eq!(fmt_num(12345.0), "12345");
        assert_eq!(fmt_num(f64::NAN), "NaN");
        assert_eq!(fmt_num(f64::NEG_INFINITY), "-inf");
        assert_eq!(fmt_num(i64::MAX as f64), "9.223372036854776e18");
    }
}
