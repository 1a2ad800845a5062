//! Bicubic uniform B-spline patches: the exact Catmull–Clark limit over a regular quad.
//!
//! A patch has 16 control points `p[i + 4 j]`, `i` along u and `j` along v, each running over the
//! grid positions −1, 0, 1, 2; the patch spans the cell between grid positions 0 and 1 (Catmull &
//! Clark 1978: the scheme generalises the bicubic B-spline's knot insertion).

use crate::math::Vec3;

/// The four cubic B-spline basis functions and their derivatives at `t` in [0, 1].
#[inline]
#[must_use]
pub(crate) fn basis(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    let b =
        [s * s * s / 6.0, (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0, (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0, t3 / 6.0];
    let d = [-0.5 * s * s, 0.5 * (3.0 * t2 - 4.0 * t), 0.5 * (-3.0 * t2 + 2.0 * t + 1.0), 0.5 * t2];
    (b, d)
}

/// Position and the two partial derivatives of a patch at (u, v).
#[inline]
#[must_use]
pub(crate) fn eval(p: &[Vec3; 16], u: f64, v: f64) -> (Vec3, Vec3, Vec3) {
    let (bu, du) = basis(u);
    let (bv, dv) = basis(v);
    // Relative to the patch's first interior point: the basis sums to 1 (its derivatives to 0),
    // so Σ b (p − o) + o is the same point, and exact in every coordinate the 16 points share (a
    // flat sharp face stays on its plane to the last bit).
    let o = p[5];
    let mut pos = Vec3::ZERO;
    let mut pu = Vec3::ZERO;
    let mut pv = Vec3::ZERO;
    for j in 0..4 {
        // Collapse along u first, then weight by v.
        let row = [p[4 * j] - o, p[4 * j + 1] - o, p[4 * j + 2] - o, p[4 * j + 3] - o];
        let ru = row[0] * bu[0] + row[1] * bu[1] + row[2] * bu[2] + row[3] * bu[3];
        let rd = row[0] * du[0] + row[1] * du[1] + row[2] * du[2] + row[3] * du[3];
        pos += ru * bv[j];
        pv += ru * dv[j];
        pu += rd * bv[j];
    }
    (o + pos, pu, pv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_a_partition_of_unity_with_zero_sum_derivatives() {
        for k in 0..=8 {
            let t = f64::from(k) / 8.0;
            let (b, d) = basis(t);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(d.iter().sum::<f64>().abs() < 1e-15);
        }
        // At t = 0 the weights are 1/6, 4/6, 1/6, 0 (the limit mask of a regular curve point).
        let (b, _) = basis(0.0);
        assert_eq!(b, [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0]);
    }

    #[test]
    fn a_linear_grid_is_reproduced() {
        // Control points on the affine map (i, j) → (i, 2 j, i + j): B-splines reproduce it exactly.
        let p: [Vec3; 16] = std::array::from_fn(|k| {
            let (i, j) = ((k % 4) as f64 - 1.0, (k / 4) as f64 - 1.0);
            Vec3::new(i, 2.0 * j, i + j)
        });
        let (x, du, dv) = eval(&p, 0.25, 0.75);
        assert!((x - Vec3::new(0.25, 1.5, 1.0)).length() < 1e-15);
        assert!((du - Vec3::new(1.0, 0.0, 1.0)).length() < 1e-15);
        assert!((dv - Vec3::new(0.0, 2.0, 1.0)).length() < 1e-15);
    }
}
