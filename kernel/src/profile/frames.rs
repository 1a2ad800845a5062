//! Rotation-minimising frames along a polyline by the double reflection method.
//!
//! W. Wang, B. Jüttler, D. Zheng, Y. Liu, "Computation of rotation minimizing frames", ACM
//! Transactions on Graphics 27(1), 2008, §4: the frame at sample i+1 is the frame at i
//! reflected in the plane bisecting the chord x_{i+1} − x_i, then in the plane that carries the
//! reflected tangent onto t_{i+1}. A polyline's rotation-minimising frame is constant along
//! each segment and turns at a vertex by the least rotation carrying one segment's direction
//! onto the next: the double reflection with the chord through the vertex (samples just
//! before and after it, chord direction d_before + d_after), which is exactly that rotation.
//! [`transport`] is that step; [`polyline`] chains it along the segments.

use crate::math::Vec3;

/// `r` (perpendicular to the unit `from`) carried by the double reflection onto the plane
/// perpendicular to the unit `to`: reflected in the plane normal to `from + to` (which sends
/// `from` to −`to`), then in the plane normal to `to`. The result is the least rotation taking
/// `from` to `to`, applied to `r`.
///
/// `from` and `to` must not be opposite (callers refuse such turns).
#[must_use]
pub fn transport(r: Vec3, from: Vec3, to: Vec3) -> Vec3 {
    let v1 = from + to;
    let c1 = v1.dot(v1);
    let r_l = if c1 > 0.0 { r - (2.0 / c1) * v1.dot(r) * v1 } else { r };
    // Second reflection: v2 = to − t_L = 2·to.
    let out = r_l - 2.0 * to.dot(r_l) * to;
    // Re-orthonormalise against rounding drift over long paths.
    (out - out.dot(to) * to).normalize_or(out)
}

/// The reference direction `r` of each segment of a polyline with unit segment directions
/// `dirs`, starting from `r0` (unit, perpendicular to `dirs[0]`).
#[must_use]
pub fn polyline(dirs: &[Vec3], r0: Vec3) -> Vec<Vec3> {
    let mut r = Vec::with_capacity(dirs.len());
    let mut ri = r0;
    for (i, &d) in dirs.iter().enumerate() {
        if i > 0 {
            ri = transport(ri, dirs[i - 1], d);
        }
        r.push(ri);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_line_keeps_its_frame() {
        // No turning: both reflections fix r.
        let r = polyline(&[Vec3::Z; 4], Vec3::X);
        assert!(r.iter().all(|&v| (v - Vec3::X).length() < 1e-15), "{r:?}");
    }

    #[test]
    fn a_planar_path_keeps_its_plane_normal_as_r() {
        // A rotation-minimising frame of a planar path turns about the plane's normal only: r
        // starting on the normal stays there.
        let dirs: Vec<Vec3> = (0..12)
            .map(|i| {
                let a = 0.5 * f64::from(i);
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let r = polyline(&dirs, Vec3::Z);
        assert!(r.iter().all(|&v| (v - Vec3::Z).length() < 1e-12), "{r:?}");
    }

    #[test]
    fn transport_is_the_least_rotation() {
        // From x to y: the quarter turn about z, so z stays and −y goes to x.
        assert!((transport(Vec3::Z, Vec3::X, Vec3::Y) - Vec3::Z).length() < 1e-15);
        assert!((transport(-Vec3::Y, Vec3::X, Vec3::Y) - Vec3::X).length() < 1e-15);
        // Half of it onto the bisector and half again compose to the whole.
        let (a, b) = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.6, 0.8));
        let mid = (a + b).normalize();
        let r = Vec3::new(0.0, 0.3, -0.4).normalize();
        let two = transport(transport(r, a, mid), mid, b);
        assert!((two - transport(r, a, b)).length() < 1e-14, "{two} vs {}", transport(r, a, b));
    }
}
