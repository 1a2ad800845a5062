//! Colour for display: the HSV colour model (Smith 1978), for the palettes written as glTF
//! vertex colours (polar features, boolean sources).

/// Opaque RGBA of hue `h` (turns, any real: taken modulo 1), saturation `s` and value `v` in
/// [0, 1].
#[must_use]
pub fn hsv_rgba(h: f64, s: f64, v: f64) -> [f32; 4] {
    let h6 = h.rem_euclid(1.0) * 6.0;
    let i = h6.floor() as u32 % 6;
    let f = h6 - h6.floor();
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let (r, g, b) = match i {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    };
    [r as f32, g as f32, b as f32, 1.0]
}

#[cfg(test)]
mod tests {
    use super::hsv_rgba;

    #[test]
    fn primaries_and_greys() {
        assert_eq!(hsv_rgba(0.0, 1.0, 1.0), [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(hsv_rgba(1.0 / 3.0, 1.0, 1.0), [0.0, 1.0, 0.0, 1.0]);
        assert_eq!(hsv_rgba(2.0 / 3.0, 1.0, 1.0), [0.0, 0.0, 1.0, 1.0]);
        assert_eq!(hsv_rgba(-1.0 / 3.0, 1.0, 1.0), hsv_rgba(2.0 / 3.0, 1.0, 1.0));
        assert_eq!(hsv_rgba(0.3, 0.0, 0.5), [0.5, 0.5, 0.5, 1.0]);
    }
}
