//! The singular value decomposition of a 3×3 matrix, through faer.

use crate::math::{Mat3, Vec3};

/// `m = u · diag(s) · vᵀ` with `s` descending and `u`, `v` orthogonal (possibly reflections).
#[must_use]
pub fn svd3(m: Mat3) -> (Mat3, Vec3, Mat3) {
    let a = faer::Mat::<f64>::from_fn(3, 3, |i, j| m.col(j)[i]);
    match a.svd() {
        Ok(svd) => {
            let (u, v) = (svd.U(), svd.V());
            let s = svd.S().column_vector();
            let col = |x: faer::MatRef<'_, f64>, j: usize| Vec3::new(x[(0, j)], x[(1, j)], x[(2, j)]);
            (
                Mat3::from_cols(col(u, 0), col(u, 1), col(u, 2)),
                Vec3::new(s[0], s[1], s[2]),
                Mat3::from_cols(col(v, 0), col(v, 1), col(v, 2)),
            )
        }
        // faer's SVD fails only without convergence (non-finite input): no rotation is known.
        Err(_) => (Mat3::IDENTITY, Vec3::ZERO, Mat3::IDENTITY),
    }
}

/// The rotation R minimising Σ‖R·aᵢ − bᵢ‖² for centred point sets (Kabsch/Umeyama, seed 002
/// Eqs. 5–8): from the covariance C = Σ aᵢ bᵢᵀ = U D Vᵀ, R = V S Uᵀ with S = diag(1, 1, ±1)
/// choosing det R = +1 — never a reflection.
///
/// Speed: when det C > 0 the answer is the orthogonal polar factor of Cᵀ, found by Newton's
/// iteration X ← (X + X⁻ᵀ)/2 (Higham), a few 3×3 inverses instead of an SVD; a covariance with
/// det C ≤ 0 (a reflection to fix, or a degenerate point set) takes the SVD.
#[must_use]
pub fn best_rotation(a: &[Vec3], b: &[Vec3]) -> Mat3 {
    let mut c = Mat3::ZERO;
    for (p, q) in a.iter().zip(b) {
        // Σ p qᵀ: column j is p · q_j.
        c += Mat3::from_cols(*p * q.x, *p * q.y, *p * q.z);
    }
    polar_rotation(c.transpose()).unwrap_or_else(|| rotation_by_svd(c))
}

/// The orthogonal polar factor of `m` when it is a rotation reached by Newton's iteration, or
/// `None` (det ≤ 0, ill-conditioned, or no convergence in 30 steps).
fn polar_rotation(m: Mat3) -> Option<Mat3> {
    let scale = m.to_cols_array().iter().map(|x| x.abs()).fold(0.0, f64::max);
    if scale.is_nan() || scale <= 0.0 || !scale.is_finite() {
        return None;
    }
    let mut x = m * (1.0 / scale);
    if x.determinant() <= 1e-9 {
        return None;
    }
    for _ in 0..30 {
        let next = (x + x.inverse().transpose()) * 0.5;
        let change = (next - x).to_cols_array().iter().map(|d| d.abs()).fold(0.0, f64::max);
        x = next;
        if change < 1e-14 {
            return Some(x);
        }
    }
    None
}

/// [`best_rotation`] by the SVD of the covariance `c`, fixing a reflection (Eq. 8).
fn rotation_by_svd(c: Mat3) -> Mat3 {
    let (u, _, v) = svd3(c);
    let d = (v * u.transpose()).determinant();
    let s = Mat3::from_diagonal(Vec3::new(1.0, 1.0, if d < 0.0 { -1.0 } else { 1.0 }));
    v * s * u.transpose()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Quat;

    #[test]
    fn svd_reconstructs_the_matrix() {
        let m = Mat3::from_cols(Vec3::new(2.0, 0.5, -1.0), Vec3::new(0.3, 1.0, 4.0), Vec3::new(-2.0, 1.5, 0.2));
        let (u, s, v) = svd3(m);
        let back = u * Mat3::from_diagonal(s) * v.transpose();
        assert!((back - m).to_cols_array().iter().all(|x| x.abs() < 1e-12), "{back} vs {m}");
        assert!(s.x >= s.y && s.y >= s.z && s.z >= 0.0);
    }

    #[test]
    fn newton_polar_and_svd_agree() {
        // Pseudo-random covariances with det > 0: both paths give the same rotation.
        let mut rng = crate::math::SplitMix64::new(0x2545_F491_4F6C_DD1D);
        let mut next = || rng.next_f64() * 2.0 - 1.0;
        let mut checked = 0;
        for _ in 0..500 {
            let c = Mat3::from_cols(
                Vec3::new(next(), next(), next()),
                Vec3::new(next(), next(), next()),
                Vec3::new(next(), next(), next()),
            );
            if c.determinant() < 1e-3 {
                continue;
            }
            let fast = polar_rotation(c.transpose()).expect("converges");
            let slow = rotation_by_svd(c);
            assert!((fast - slow).to_cols_array().iter().all(|x| x.abs() < 1e-9), "{fast} vs {slow}");
            assert!((fast.determinant() - 1.0).abs() < 1e-12);
            checked += 1;
        }
        assert!(checked > 100);
    }

    #[test]
    fn best_rotation_recovers_a_known_rotation_and_never_reflects() {
        let q = Quat::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 1.1);
        let a =
            [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 0.0, 0.5), Vec3::new(-1.0, -2.0, -0.5)];
        let b: Vec<Vec3> = a.iter().map(|p| q * *p).collect();
        let r = best_rotation(&a, &b);
        let want = Mat3::from_quat(q);
        assert!((r - want).to_cols_array().iter().all(|x| x.abs() < 1e-12), "{r} vs {want}");
        // A mirrored target: the best proper rotation, determinant +1, not the mirror.
        let mirrored: Vec<Vec3> = a.iter().map(|p| Vec3::new(-p.x, p.y, p.z)).collect();
        let r = best_rotation(&a, &mirrored);
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        // Planar points (a degenerate covariance) still give a rotation.
        let flat = [Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y];
        let r = best_rotation(&flat, &flat);
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        assert!(flat.iter().all(|p| (r * *p - *p).length() < 1e-12));
    }
}
