//! Lofts: a solid skinned through a sequence of profiles with the same contour structure.
//!
//! Contours are matched between consecutive profiles (outer with outer, hole with hole, by
//! nearest centroid relative to the profile's own), each matched chain is given a common
//! start (the point whose direction from its contour's centroid is nearest the previous
//! profile's start's) and resampled at the union of all its contours' arc-length parameters —
//! every corner of every profile is kept, and all rings of a chain get one point count.

use super::convert::{check_solid_size, mesh_error};
use super::measure::contour_area;
use super::self_crossing::{nearest, refuse_self_crossing};
use super::{Profile, ProfileError, Vec2};
use crate::csg::engine::triangulate_contours;
use crate::math::{Mat4, Vec3};
use crate::mesh::Mesh;

/// Where each lofted profile is placed.
#[derive(Clone, Debug, PartialEq)]
pub enum Placement {
    /// Profile i in the plane z = heights[i] (strictly increasing).
    Heights(Vec<f64>),
    /// Profile i's point (x, y) at transforms[i] · (x, y, 0); the solid runs from each placed
    /// profile to the next (the faces are turned outwards whichever way that is).
    Transforms(Vec<Mat4>),
}

/// Options of [`loft`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct LoftOptions {
    /// Where the profiles go. Default value: heights 0, 1, 2, …
    pub placement: Option<Placement>,
    /// Whether the last profile joins back to the first, making a ring with no caps (with
    /// [`Placement::Transforms`] that come round, and at least 3 profiles). Default value: false.
    pub closed: bool,
}

impl LoftOptions {
    /// Profiles one unit apart up z, open.
    pub const DEFAULT: LoftOptions = LoftOptions { placement: None, closed: false };

    /// With the profiles at `heights`.
    #[must_use]
    pub fn with_heights(mut self, heights: Vec<f64>) -> LoftOptions {
        self.placement = Some(Placement::Heights(heights));
        self
    }

    /// With the profiles placed by `transforms`.
    #[must_use]
    pub fn with_transforms(mut self, transforms: Vec<Mat4>) -> LoftOptions {
        self.placement = Some(Placement::Transforms(transforms));
        self
    }

    /// Closed or open.
    #[must_use]
    pub fn with_closed(mut self, closed: bool) -> LoftOptions {
        self.closed = closed;
        self
    }
}

impl Default for LoftOptions {
    fn default() -> LoftOptions {
        LoftOptions::DEFAULT
    }
}

/// The centroid of a contour's vertices.
fn mean(c: &[Vec2]) -> Vec2 {
    c.iter().copied().sum::<Vec2>() / c.len() as f64
}

/// Normalised arc-length parameters of a closed contour's vertices, in [0, 1).
fn parameters(c: &[Vec2]) -> Vec<f64> {
    let n = c.len();
    let mut acc = vec![0.0; n + 1];
    for i in 0..n {
        acc[i + 1] = acc[i] + c[i].distance(c[(i + 1) % n]);
    }
    let total = acc[n];
    acc.truncate(n);
    acc.into_iter().map(|a| a / total).collect()
}

/// Normalised arc-length parameters closer than this are resampled as one point.
const LOFT_PARAMETER_TOLERANCE: f64 = 1e-6;

/// The closed contour `c` (vertex parameters `params`) at each of `at` (sorted, in [0, 1)).
fn resample(c: &[Vec2], params: &[f64], at: &[f64]) -> Vec<Vec2> {
    let n = c.len();
    let mut seg = 0;
    at.iter()
        .map(|&u| {
            while seg + 1 < n && params[seg + 1] <= u {
                seg += 1;
            }
            let (u0, u1) = (params[seg], if seg + 1 < n { params[seg + 1] } else { 1.0 });
            let f = if u1 > u0 { (u - u0) / (u1 - u0) } else { 0.0 };
            c[seg].lerp(c[(seg + 1) % n], f)
        })
        .collect()
}

/// Matches each contour of `from` (indices) to one of `to` of the same kind by nearest
/// centroid relative to each profile's centroid; `order[i]` is the contour of `to` matched to
/// contour i of `from`.
fn match_contours(from: &Profile, to: &Profile, index: usize) -> Result<Vec<usize>, ProfileError> {
    let kinds = |p: &Profile| {
        let holes = p.contours().iter().filter(|c| contour_area(c) < 0.0).count();
        (p.contours().len() - holes, holes)
    };
    let (a, b) = (kinds(from), kinds(to));
    if a != b {
        return Err(ProfileError::LoftMismatch {
            index,
            reason: format!("it has {} outer contours and {} holes, profile 0 has {} and {}", b.0, b.1, a.0, a.1),
        });
    }
    let centre = |p: &Profile| p.centroid().unwrap_or(Vec2::ZERO);
    let (ca, cb) = (centre(from), centre(to));
    let mut taken = vec![false; to.contours().len()];
    let mut order = Vec::with_capacity(from.contours().len());
    for c in from.contours() {
        let hole = contour_area(c) < 0.0;
        let m = mean(c) - ca;
        let best = to
            .contours()
            .iter()
            .enumerate()
            .filter(|&(j, d)| !taken[j] && (contour_area(d) < 0.0) == hole)
            .min_by(|x, y| (mean(x.1) - cb - m).length_squared().total_cmp(&(mean(y.1) - cb - m).length_squared()))
            .map(|(j, _)| j)
            .ok_or_else(|| ProfileError::LoftMismatch { index, reason: "its contours do not correspond".into() })?;
        taken[best] = true;
        order.push(best);
    }
    Ok(order)
}

/// A solid through `profiles` (at least 2, each non-empty, all with as many outer contours and
/// holes), a closed manifold triangle mesh. See the [module documentation](self) for how
/// contours are matched and resampled.
///
/// # Errors
/// [`ProfileError::TooFewPoints`] for fewer than 2 profiles (3 closed); [`ProfileError::Empty`] naming an
/// empty profile; [`ProfileError::LoftMismatch`] naming a profile whose contours do not match
/// the first's; [`ProfileError::BadValue`] for heights not strictly increasing or finite, a
/// placement count other than the profiles', a non-finite or flattening transform, `closed`
/// without transforms; [`ProfileError::SelfCrossing`] naming the profile nearest where the
/// solid passes through itself (placed profiles that cross).
pub fn loft(profiles: &[Profile], options: &LoftOptions) -> Result<Mesh, ProfileError> {
    if profiles.len() < 2 {
        return Err(ProfileError::TooFewPoints { what: "the loft".into(), count: profiles.len(), needed: 2 });
    }
    for (i, p) in profiles.iter().enumerate() {
        p.require_region(&format!("profile {i}"))?;
    }
    if options.closed && !matches!(options.placement, Some(Placement::Transforms(_))) {
        // Stacked up z, the last profile joined back to the first would run down through the
        // solid itself.
        return Err(ProfileError::BadValue {
            name: "`closed`",
            value: 1.0,
            expected: "false when the profiles are stacked by heights (a ring needs transforms placing them round)",
        });
    }
    if options.closed && profiles.len() < 3 {
        return Err(ProfileError::TooFewPoints { what: "a closed loft".into(), count: profiles.len(), needed: 3 });
    }
    let transforms: Vec<Mat4> = match &options.placement {
        None => (0..profiles.len()).map(|i| Mat4::from_translation(Vec3::new(0.0, 0.0, i as f64))).collect(),
        Some(Placement::Heights(h)) => {
            if h.len() != profiles.len() {
                return Err(ProfileError::BadValue {
                    name: "the number of heights",
                    value: h.len() as f64,
                    expected: "one per profile",
                });
            }
            if let Some(&bad) = h.iter().find(|v| !v.is_finite()) {
                return Err(ProfileError::BadValue { name: "a height", value: bad, expected: "a finite number" });
            }
            if let Some(w) = h.windows(2).find(|w| w[1] <= w[0]) {
                return Err(ProfileError::BadValue {
                    name: "a height",
                    value: w[1],
                    expected: "greater than the one before (heights strictly increasing)",
                });
            }
            h.iter().map(|&z| Mat4::from_translation(Vec3::new(0.0, 0.0, z))).collect()
        }
        Some(Placement::Transforms(t)) => {
            if t.len() != profiles.len() {
                return Err(ProfileError::BadValue {
                    name: "the number of transforms",
                    value: t.len() as f64,
                    expected: "one per profile",
                });
            }
            for m in t {
                if !m.is_finite() {
                    return Err(ProfileError::BadValue { name: "a transform", value: f64::NAN, expected: "finite" });
                }
                let (x, y) = (m.transform_vector3(Vec3::X), m.transform_vector3(Vec3::Y));
                if x.cross(y).length() == 0.0 {
                    return Err(ProfileError::BadValue {
                        name: "a transform's area scale",
                        value: 0.0,
                        expected: "non-zero (it flattens the profile)",
                    });
                }
            }
            t.clone()
        }
    };
    // Contour chains: chain k is contour order[i][k] of profile i.
    let mut order: Vec<Vec<usize>> = vec![(0..profiles[0].contours().len()).collect()];
    for i in 1..profiles.len() {
        let m = match_contours(&profiles[i - 1], &profiles[i], i)?;
        let prev = &order[i - 1];
        order.push(prev.iter().map(|&k| m[k]).collect());
    }
    // chains[k][i]: the contour of profile i in chain k.
    let chains: Vec<Vec<usize>> = (0..order[0].len()).map(|k| order.iter().map(|o| o[k]).collect()).collect();
    // Aligned, resampled rings: rings[i][k] is chain k in profile i.
    let mut rings: Vec<Vec<Vec<Vec2>>> = vec![Vec::with_capacity(chains.len()); profiles.len()];
    for chain in &chains {
        let mut aligned: Vec<Vec<Vec2>> = Vec::with_capacity(profiles.len());
        for (p, &contour) in profiles.iter().zip(chain) {
            let c = &p.contours()[contour];
            let shift = match aligned.last() {
                None => 0,
                Some(prev) => {
                    let want = (prev[0] - mean(prev)).normalize_or_zero();
                    let centre = mean(c);
                    (0..c.len())
                        .max_by(|&a, &b| {
                            let da = (c[a] - centre).normalize_or_zero().dot(want);
                            let db = (c[b] - centre).normalize_or_zero().dot(want);
                            da.total_cmp(&db)
                        })
                        .unwrap_or(0)
                }
            };
            let mut c = c.clone();
            c.rotate_left(shift);
            aligned.push(c);
        }
        let params: Vec<Vec<f64>> = aligned.iter().map(|c| parameters(c)).collect();
        let mut all: Vec<f64> = params.iter().flatten().copied().collect();
        all.sort_by(f64::total_cmp);
        // Parameters closer than a millionth of the perimeter are one: nearer points (corners
        // of different profiles a rounding apart) made slivers whose corners coincide once
        // written in f32, which other tools then weld into edges of four faces.
        all.dedup_by(|a, b| (*a - *b).abs() <= LOFT_PARAMETER_TOLERANCE);
        for (i, c) in aligned.iter().enumerate() {
            rings[i].push(resample(c, &params[i], &all));
        }
    }
    let per_ring: usize = rings[0].iter().map(Vec::len).sum();
    check_solid_size(
        || format!("a loft of {} rings of {per_ring} points", profiles.len()),
        (per_ring * profiles.len()) as f64,
        2.0 * (per_ring * profiles.len()) as f64,
    )?;
    crate::limits::charge((per_ring * profiles.len()) as u64)?;
    let mut positions = Vec::with_capacity(per_ring * profiles.len());
    for (ring, m) in rings.iter().zip(&transforms) {
        positions.extend(ring.iter().flatten().map(|q| m.transform_point3(Vec3::new(q.x, q.y, 0.0))));
    }
    let n = profiles.len();
    let segments = if options.closed { n } else { n - 1 };
    let at = |i: usize, p: usize| (i * per_ring + p) as u32;
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut start = 0;
    for c in &rings[0] {
        let len = c.len();
        for seg in 0..segments {
            let (i, j) = (seg, (seg + 1) % n);
            for p in 0..len {
                let (a, b) = (start + p, start + (p + 1) % len);
                faces.push([at(i, a), at(i, b), at(j, b)]);
                faces.push([at(i, a), at(j, b), at(j, a)]);
            }
        }
        start += len;
    }
    if !options.closed {
        let last = ((n - 1) * per_ring) as u32;
        // Each ring keeps its profile's orientation (outer counter-clockwise, holes clockwise),
        // so both caps triangulate as their profiles do.
        for [a, b, c] in triangulate_contours(&rings[0]) {
            faces.push([c, b, a]);
        }
        for [a, b, c] in triangulate_contours(&rings[n - 1]) {
            faces.push([a + last, b + last, c + last]);
        }
    }
    let mut mesh = Mesh::from_polygons(positions.clone(), &faces).map_err(mesh_error)?;
    if mesh.volume() < 0.0 {
        // Placed so the profiles run along −z of their planes: turn every face.
        let flipped: Vec<[u32; 3]> = faces.iter().map(|&[a, b, c]| [c, b, a]).collect();
        mesh = Mesh::from_polygons(positions, &flipped).map_err(mesh_error)?;
    }
    let centres: Vec<Vec3> = (0..n)
        .map(|i| {
            let ring = &mesh.positions()[i * per_ring..(i + 1) * per_ring];
            ring.iter().copied().sum::<Vec3>() / per_ring as f64
        })
        .collect();
    refuse_self_crossing(&mesh, "the loft", |at| format!("profile {}", nearest(centres.iter().copied(), at)))?;
    Ok(mesh)
}

#[cfg(test)]
mod parameter_tests {
    use super::*;

    #[test]
    fn no_two_points_of_a_loft_coincide_when_profiles_share_corners_almost() {
        // The vase of examples/vase_loft.rhai: a 64-gon, a rounded square turned 45°, two more
        // 64-gons. Their arc-length parameters nearly meet at corners; points a rounding apart
        // made slivers whose corners other tools weld (trimesh found edges of four faces).
        let square = Profile::rect(Vec2::splat(-4.5), Vec2::splat(4.5)).unwrap().fillet(2.25, 32).unwrap();
        let sections = [
            Profile::circle(3.0, 64).unwrap(),
            square.rotate(45.0).unwrap(),
            Profile::circle(1.6, 64).unwrap(),
            Profile::circle(2.4, 64).unwrap(),
        ];
        let options = LoftOptions::DEFAULT.with_heights(vec![0.0, 4.8, 10.2, 12.0]);
        let m = loft(&sections, &options).unwrap();
        let p = m.positions();
        let nearest = (0..p.len())
            .flat_map(|i| (i + 1..p.len()).map(move |j| (i, j)))
            .map(|(i, j)| p[i].distance(p[j]))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest > 1e-6, "two vertices {nearest:e} apart");
        assert!(m.is_closed() && m.genus() == 0);
    }
}
