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
#[must_use]
pub fn best_rotation(a: &[Vec3], b: &[Vec3]) -> Mat3 {
    let mut c = Mat3::ZERO;
    for (p, q) in a.iter().zip(b) {
        // Σ p qᵀ: column j is p · q_j.
        c += Mat3::from_cols(*p * q.x, *p * q.y, *p * q.z);
    }
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
