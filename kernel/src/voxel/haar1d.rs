//! The 1D Haar wavelet transform of Heurtebise & Thon §2.1: averages `(a + b) / 2` and details
//! `(a − b) / 2`, repeated on the averages down to one value.

use super::VoxelError;

fn check(values: &[f64]) -> Result<(), VoxelError> {
    if values.is_empty() || !values.len().is_power_of_two() {
        return Err(VoxelError::InvalidArgument {
            what: "Haar transform input",
            reason: format!("its length {} is not a power of two", values.len()),
        });
    }
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(VoxelError::NonFinite { what: "Haar transform input value", value: format!("{v}") });
    }
    Ok(())
}

/// The full 1D Haar decomposition of `values` (length p, a power of two): the final sequence
/// `[coarsest average, coarsest detail, next details (2), …, finest details (p/2)]`, of length p.
///
/// The paper's example: `[9, 7, 3, 5]` → `[6, 2, 1, −1]`.
///
/// # Errors
/// [`VoxelError::InvalidArgument`] for an empty input or a length that is not a power of two,
/// [`VoxelError::NonFinite`] for NaN or infinite values.
///
/// See also [`ihaar1d`], and [`HaarHierarchy`](super::HaarHierarchy) for the 3D form.
pub fn haar1d(values: &[f64]) -> Result<Vec<f64>, VoxelError> {
    check(values)?;
    let mut out = values.to_vec();
    let mut tmp = vec![0.0; values.len()];
    let mut len = values.len();
    while len > 1 {
        let half = len / 2;
        for i in 0..half {
            let (a, b) = (out[2 * i], out[2 * i + 1]);
            tmp[i] = (a + b) / 2.0;
            tmp[half + i] = (a - b) / 2.0;
        }
        out[..len].copy_from_slice(&tmp[..len]);
        len = half;
    }
    Ok(out)
}

/// The inverse of [`haar1d`]: `[6, 2, 1, −1]` → `[9, 7, 3, 5]`, using `a = s + d`, `b = s − d`.
///
/// # Errors
/// As [`haar1d`].
pub fn ihaar1d(values: &[f64]) -> Result<Vec<f64>, VoxelError> {
    check(values)?;
    let mut out = values.to_vec();
    let mut tmp = vec![0.0; values.len()];
    let mut len = 1;
    while len < values.len() {
        for i in 0..len {
            let (s, d) = (out[i], out[len + i]);
            tmp[2 * i] = s + d;
            tmp[2 * i + 1] = s - d;
        }
        len *= 2;
        out[..len].copy_from_slice(&tmp[..len]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn papers_example_round_trips() {
        // §2.1: X⁰ = [9 7 3 5], X¹ = [8 4], Y¹ = [1 −1], X² = [6], Y² = [2].
        assert_eq!(haar1d(&[9.0, 7.0, 3.0, 5.0]).unwrap(), vec![6.0, 2.0, 1.0, -1.0]);
        assert_eq!(ihaar1d(&[6.0, 2.0, 1.0, -1.0]).unwrap(), vec![9.0, 7.0, 3.0, 5.0]);
    }

    #[test]
    fn one_value_is_its_own_transform_and_long_inputs_round_trip() {
        assert_eq!(haar1d(&[4.5]).unwrap(), vec![4.5]);
        let x: Vec<f64> = (0..64).map(|i| f64::from((i * 37 % 101) as u8)).collect();
        // Integer inputs: every intermediate is a dyadic rational, so the round trip is exact.
        assert_eq!(ihaar1d(&haar1d(&x).unwrap()).unwrap(), x);
        // The first coefficient is the mean.
        let mean = x.iter().sum::<f64>() / 64.0;
        assert_eq!(haar1d(&x).unwrap()[0], mean);
    }

    #[test]
    fn bad_lengths_and_values_are_refused() {
        assert!(matches!(haar1d(&[]), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(haar1d(&[1.0, 2.0, 3.0]), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(ihaar1d(&[1.0, f64::NAN]), Err(VoxelError::NonFinite { .. })));
    }
}
