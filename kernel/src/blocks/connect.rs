//! Finding connections between blocks and pairing their vertices (seed 000 §2.2, Figs. 6–8).
//!
//! From the centre of every sub-face a ray is cast outward along its normal (reaching back by
//! [`OVERLAP`] of the sub-face's mean side, so that touching and barely overlapping blocks
//! connect too); the nearest sub-face of another block facing it is its hit. Sub-faces A and B
//! connect when
//! 1. they belong to different blocks,
//! 2. their groups are an allowed pair,
//! 3. their distance is below `threshold × (perimeter(A) + perimeter(B))`,
//! 4. B is A's nearest hit and A is B's,
//! 5. no other connection joins the same two blocks with a shorter distance (one connection per
//!    block pair, so no degenerate edges; Fig. 7).
//!
//! Manual connections come first; a sub-face or block pair they use gets no found connection.
//! The rays run through a [`QuadBvh`](super::bvh::QuadBvh) over all sub-faces.

use std::collections::HashSet;

use crate::math::Vec3;

use super::bvh::QuadBvh;
use super::{BlockError, BlockModel, Connection, Face, SubFaceRef};

/// How far behind a sub-face its ray looks, as a fraction of the sub-face's mean side length.
pub const OVERLAP: f64 = 0.01;

/// One sub-face with the geometry the search needs.
struct Probe {
    r: SubFaceRef,
    corners: [Vec3; 4],
    centre: Vec3,
    normal: Vec3,
    perimeter: f64,
    group: i64,
}

impl BlockModel {
    /// Every connection: the manual ones (in the order given), then the found ones ordered by
    /// block, face and sub-face of their first side. See the [module documentation](self).
    ///
    /// # Errors
    /// None today for a valid model; kept fallible for the checks a model may grow.
    pub fn connections(&self) -> Result<Vec<Connection>, BlockError> {
        let mut out: Vec<Connection> = self.manual_connections().to_vec();
        let taken: HashSet<SubFaceRef> = out.iter().flat_map(|c| [c.a, c.b]).collect();
        let mut pairs: HashSet<(u32, u32)> = out.iter().map(|c| block_pair(c.a.block, c.b.block)).collect();

        let probes = self.probes();
        if probes.is_empty() {
            return Ok(out);
        }
        let bvh = QuadBvh::new(probes.iter().map(|p| p.corners).collect());
        let max_perimeter = probes.iter().map(|p| p.perimeter).fold(0.0, f64::max);

        // Each sub-face's nearest facing hit on another block, if it passes conditions 2 and 3.
        let best: Vec<Option<(u32, f64)>> = probes
            .iter()
            .map(|a| {
                if taken.contains(&a.r) || self.threshold() == 0.0 {
                    return None;
                }
                let reach = self.threshold() * (a.perimeter + max_perimeter);
                let back = OVERLAP * a.perimeter / 4.0;
                let (j, t) = bvh.nearest(a.centre, a.normal, back, reach, |j| {
                    let b = &probes[j as usize];
                    b.r.block != a.r.block && b.normal.dot(a.normal) < 0.0 && !taken.contains(&b.r)
                })?;
                let b = &probes[j as usize];
                let d = t.abs();
                (self.is_allowed(a.group, b.group) && d < self.threshold() * (a.perimeter + b.perimeter))
                    .then_some((j, d))
            })
            .collect();

        // Condition 4: mutual nearest hits.
        let mut found: Vec<Connection> = Vec::new();
        for (i, hit) in best.iter().enumerate() {
            let Some((j, d)) = *hit else { continue };
            if (j as usize) <= i {
                continue;
            }
            if let Some((back, d2)) = best[j as usize] {
                if back as usize == i {
                    found.push(Connection {
                        a: probes[i].r,
                        b: probes[j as usize].r,
                        distance: 0.5 * (d + d2),
                        manual: false,
                    });
                }
            }
        }
        // Condition 5: the shortest connection of each block pair.
        found.sort_by(|x, y| x.distance.total_cmp(&y.distance).then(x.a.cmp(&y.a)).then(x.b.cmp(&y.b)));
        let mut kept: Vec<Connection> =
            found.into_iter().filter(|c| pairs.insert(block_pair(c.a.block, c.b.block))).collect();
        kept.sort_by(|x, y| x.a.cmp(&y.a).then(x.b.cmp(&y.b)));
        out.extend(kept);
        Ok(out)
    }

    /// Every sub-face of every block, in block, face, sub-face order.
    fn probes(&self) -> Vec<Probe> {
        let mut out = Vec::new();
        for (bi, block) in self.blocks().iter().enumerate() {
            for face in Face::ALL {
                for sub in 0..block.subface_count(face) {
                    let q = block.subface_corners(face, sub);
                    let normal = (q[2] - q[0]).cross(q[3] - q[1]).normalize_or_zero();
                    let perimeter = (0..4).map(|k| q[k].distance(q[(k + 1) % 4])).sum();
                    out.push(Probe {
                        r: SubFaceRef { block: bi as u32, face, sub },
                        corners: q,
                        centre: (q[0] + q[1] + q[2] + q[3]) * 0.25,
                        normal,
                        perimeter,
                        group: block.group(),
                    });
                }
            }
        }
        out
    }
}

fn block_pair(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The rotation `r` that pairs corner `i` of sub-face A with corner `(r - i) mod 4` of sub-face B
/// at the least total distance (Fig. 8): both lists are counter-clockwise seen from outside
/// their own block, so walking A counter-clockwise walks B clockwise.
#[must_use]
pub(super) fn pairing(a: &[Vec3; 4], b: &[Vec3; 4]) -> usize {
    let cost = |r: usize| (0..4).map(|i| a[i].distance(b[(r + 4 - i) % 4])).sum::<f64>();
    (0..4).min_by(|&x, &y| cost(x).total_cmp(&cost(y))).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blocks::Block;

    fn cube_at(x: f64, y: f64, z: f64) -> Block {
        Block::from_bounds(Vec3::new(x, y, z), Vec3::new(x + 1.0, y + 1.0, z + 1.0)).unwrap()
    }

    #[test]
    fn touching_blocks_connect_once_when_their_groups_are_allowed() {
        let mut m = BlockModel::new();
        m.add(cube_at(0.0, 0.0, 0.0));
        m.add(cube_at(1.0, 0.0, 0.0));
        // No allowed pair: nothing connects (Fig. 5a).
        assert!(m.connections().unwrap().is_empty());
        m.allow(0, 0);
        let c = m.connections().unwrap();
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].a.block, c[0].a.face, c[0].b.block, c[0].b.face), (0, Face::PosX, 1, Face::NegX));
        assert!(c[0].distance.abs() < 1e-12);
    }

    #[test]
    fn the_threshold_scales_with_the_perimeters() {
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(cube_at(0.0, 0.0, 0.0));
        // A gap of 0.5 between unit faces (perimeters 4 + 4): connects for threshold > 0.5 / 8.
        m.add(cube_at(1.5, 0.0, 0.0));
        m.set_threshold(0.06).unwrap();
        assert!(m.connections().unwrap().is_empty());
        m.set_threshold(0.07).unwrap();
        let c = m.connections().unwrap();
        assert_eq!(c.len(), 1);
        assert!((c[0].distance - 0.5).abs() < 1e-12);
        assert_eq!(m.set_threshold(-1.0), Err(BlockError::BadThreshold { value: -1.0 }));
        assert_eq!(m.threshold(), 0.07);
    }

    #[test]
    fn only_mutual_nearest_sub_faces_connect_and_one_per_block_pair() {
        let mut m = BlockModel::new();
        m.allow(0, 0);
        let mut a = cube_at(0.0, 0.0, 0.0);
        a.subdivide(Face::PosX, 2, 2).unwrap();
        m.add(a);
        let mut b = cube_at(1.0, 0.0, 0.0);
        b.subdivide(Face::NegX, 2, 2).unwrap();
        m.add(b);
        // Four facing pairs at distance 0, but only one connection between the two blocks.
        let c = m.connections().unwrap();
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].a.sub, c[0].b.sub);
    }

    #[test]
    fn disallowed_groups_do_not_connect_and_manual_connections_win() {
        let mut m = BlockModel::new();
        m.allow(0, 1);
        let mut a = cube_at(0.0, 0.0, 0.0);
        a.set_group(0);
        let mut b = cube_at(1.0, 0.0, 0.0);
        b.set_group(2);
        m.add(a);
        m.add(b);
        assert!(m.connections().unwrap().is_empty());
        m.connect(0, Face::PosY, 0, 1, Face::PosY, 0).unwrap();
        let c = m.connections().unwrap();
        assert_eq!(c.len(), 1);
        assert!(c[0].manual);
        let before = m.clone();
        assert_eq!(
            m.connect(0, Face::PosY, 0, 1, Face::NegY, 0),
            Err(BlockError::AlreadyConnected { block: 0, face: "+y", sub: 0 })
        );
        assert_eq!(m.connect(0, Face::NegY, 0, 0, Face::NegZ, 0), Err(BlockError::SameBlock { block: 0 }));
        assert!(matches!(m.connect(0, Face::NegY, 3, 1, Face::NegZ, 0), Err(BlockError::SubFaceOutOfRange { .. })));
        assert!(matches!(m.connect(5, Face::NegY, 0, 1, Face::NegZ, 0), Err(BlockError::NoSuchBlock { id: 5, .. })));
        assert_eq!(m, before);
    }

    #[test]
    fn pairing_picks_the_least_cost_rotation() {
        let a =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        // B faces the other way (clockwise here), starting at a different corner.
        let b = [a[2], a[1], a[0], a[3]].map(|p| p + Vec3::new(0.0, 0.0, 0.1));
        let r = pairing(&a, &b);
        for i in 0..4 {
            assert!(a[i].distance(b[(r + 4 - i) % 4]) < 0.11);
        }
    }

    #[test]
    fn blocks_sharing_a_twisted_face_connect() {
        // A's +x face is warped (corner 7 pushed out, so it is no plane) and B's -x face is the
        // same four points: a split of the quad along one diagonal would put the two surfaces
        // apart by the warp at the centre and the rays would miss each other (the Fig. 15 tree's
        // side branch on its twisting trunk).
        for warp in [0.02, 0.1, 0.3] {
            let mut a = *cube_at(0.0, 0.0, 0.0).corners();
            a[7].x += warp;
            let mut b = [Vec3::ZERO; 8];
            for k in 0..8 {
                b[k] = if k % 2 == 0 { a[k + 1] } else { a[k] + Vec3::new(1.0, 0.0, 0.0) };
            }
            let mut m = BlockModel::new();
            m.allow(0, 0);
            m.add(Block::from_corners(a).unwrap());
            m.add(Block::from_corners(b).unwrap());
            let c = m.connections().unwrap();
            assert_eq!(c.len(), 1, "warp {warp}");
            assert_eq!((c[0].a.face, c[0].b.face), (Face::PosX, Face::NegX));
            assert!(c[0].distance.abs() < 1e-12, "warp {warp}: {}", c[0].distance);
            let t = m.tessellate(&crate::blocks::MeshOptions::DEFAULT.with_tolerance(0.01), None).unwrap();
            assert!(t.mesh.is_closed() && t.mesh.is_manifold() && t.mesh.genus() == 0);
        }
    }

    #[test]
    fn connecting_many_blocks_scales() {
        // A 20 × 20 × 5 lattice of touching cubes: each interior face pair connects once.
        let mut m = BlockModel::new();
        m.allow(0, 0);
        let n = 20;
        for i in 0..n {
            for j in 0..n {
                for k in 0..5 {
                    m.add(cube_at(f64::from(i), f64::from(j), f64::from(k)));
                }
            }
        }
        let c = m.connections().unwrap();
        // (n-1)·n·5 along x, the same along y, n·n·4 along z.
        assert_eq!(c.len(), ((n - 1) * n * 5 * 2 + n * n * 4) as usize);
    }
}
