//! Blocks that touch but do not connect (seed 000 §2.2): a connection joins two sub-faces
//! whose centres' rays hit each other, so a table leg under the top's corner touches the top's
//! single `-z` sub-face without connecting to it (the ray from that sub-face's centre, the
//! middle of the top, finds no leg), and the model's surface comes out in more pieces than
//! its blocks suggest. This finds such blocks and, for each, the nearest miss: the facing
//! sub-faces, their gap and how far apart their centres lie, so that the message can say what
//! to change.
//!
//! Two blocks touch when their bounds touch or overlap (within a millionth of the model's
//! size) and their groups may connect. Among the pieces the connections make of a set of
//! touching blocks, the one of largest volume is the model's body; every block of another
//! piece that touches a block outside its own piece is reported.

use crate::math::Vec3;

use super::block::MAX_SUBDIVISIONS;
use super::{Block, BlockError, BlockModel, Face, SubFaceRef};

/// One block left out of the piece it touches, and its nearest miss.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Miss {
    /// The unconnected block.
    pub block: u32,
    /// A block it touches in another piece.
    pub other: u32,
    /// The sub-face of `block` nearest to facing one of `other`.
    pub a: SubFaceRef,
    /// The sub-face of `other` it faces.
    pub b: SubFaceRef,
    /// The gap between them along `a`'s normal (negative when the blocks overlap there).
    pub gap: f64,
    /// How far `b`'s centre lies from `a`'s across the normal: rays from the two centres must
    /// hit each other's sub-faces for them to connect.
    pub offset: f64,
    /// The greatest distance at which these two sub-faces connect (`threshold × (perimeter(a)
    /// + perimeter(b))`).
    pub reach: f64,
    /// The subdivision of `other`'s face `b.face` that makes a sub-face centre face `block`
    /// (and every other block touching that face), when `block`'s sub-face centre lies over
    /// that face; see [`Subdivision`].
    pub advice: Option<Subdivision>,
}

/// Advice for blocks that touch a face without connecting: divide face `face` of block
/// `block` into `nu × nv` sub-faces. Then, for every block touching that face (the one missed
/// and those it may already connect to), the sub-face under the touching block's centre has
/// its own centre on the touching block's face, so the rays from the two centres hit each
/// other (seed 000 §2.2) and they connect. The smallest `nu`, then `nv`, that does it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Subdivision {
    /// The block whose face to divide.
    pub block: u32,
    /// The face.
    pub face: Face,
    /// Divisions along u.
    pub nu: u32,
    /// Divisions along v.
    pub nv: u32,
}

impl BlockModel {
    /// The blocks that touch a block they may connect with but end up in another piece of the
    /// surface, each with its nearest miss, in block order. See the [module
    /// documentation](self).
    ///
    /// # Errors
    /// As [`BlockModel::connections`].
    pub fn unconnected(&self) -> Result<Vec<Miss>, BlockError> {
        let n = self.blocks().len();
        if n < 2 {
            return Ok(Vec::new());
        }
        let mut pieces = UnionFind::new(n);
        for c in self.connections()? {
            pieces.join(c.a.block as usize, c.b.block as usize);
        }
        let bounds: Vec<(Vec3, Vec3)> = self
            .blocks()
            .iter()
            .map(|b| {
                let c = b.corners();
                c.iter().fold((c[0], c[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
            })
            .collect();
        let (lo, hi) = bounds.iter().fold((bounds[0].0, bounds[0].1), |(lo, hi), b| (lo.min(b.0), hi.max(b.1)));
        let eps = 1e-6 * (hi - lo).length();
        let touching = self.touching_pairs(&bounds, eps);
        // The body of each set of touching blocks: its piece of largest volume.
        let mut sets = UnionFind::new(n);
        for &(i, j) in &touching {
            sets.join(i, j);
        }
        let piece: Vec<usize> = (0..n).map(|i| pieces.root(i)).collect();
        let set: Vec<usize> = (0..n).map(|i| sets.root(i)).collect();
        let mut piece_volume = vec![0.0; n];
        for (i, b) in self.blocks().iter().enumerate() {
            piece_volume[piece[i]] += b.volume().abs();
        }
        let mut body: Vec<Option<usize>> = vec![None; n];
        for i in 0..n {
            let (s, p) = (set[i], piece[i]);
            if body[s]
                .is_none_or(|b| piece_volume[p] > piece_volume[b] || (piece_volume[p] == piece_volume[b] && p < b))
            {
                body[s] = Some(p);
            }
        }
        let mut misses: Vec<Miss> = Vec::new();
        for i in (0..n).filter(|&i| body[set[i]] != Some(piece[i])) {
            let others = touching.iter().filter_map(|&(a, b)| match (a == i, b == i) {
                (true, _) => Some(b),
                (_, true) => Some(a),
                _ => None,
            });
            let best = others
                .filter(|&j| piece[j] != piece[i])
                .filter_map(|j| self.nearest_miss(i as u32, j as u32))
                .min_by(|x, y| (x.gap.abs() + x.offset).total_cmp(&(y.gap.abs() + y.offset)));
            if let Some(m) = best {
                misses.push(m);
            }
        }
        for m in &mut misses {
            m.advice = self.subdivision_advice(m, &touching);
        }
        Ok(misses)
    }

    /// The subdivision of face `m.b.face` of block `m.other` that lets `m.block` connect to it,
    /// keeping every other block that touches the face connectable ([`Subdivision`]); `None`
    /// when `m.block`'s sub-face centre does not lie over that face (the blocks overlap only
    /// at an edge) or no division up to the limit serves every block.
    fn subdivision_advice(&self, m: &Miss, touching: &[(usize, usize)]) -> Option<Subdivision> {
        let (j, face) = (m.other as usize, m.b.face);
        let target = &self.blocks()[j];
        // Every block touching the face: the extent (in the face's u, v) of its facing
        // sub-face, and where that sub-face's centre falls.
        let mut clients: Vec<([f64; 2], [f64; 2], [f64; 2])> = Vec::new();
        let partners = touching.iter().filter_map(|&(a, b)| match (a == j, b == j) {
            (true, _) => Some(b),
            (_, true) => Some(a),
            _ => None,
        });
        for k in partners {
            let block = &self.blocks()[k];
            for f in Face::ALL {
                for sub in 0..block.subface_count(f) {
                    let q = block.subface_corners(f, sub);
                    let n = (q[2] - q[0]).cross(q[3] - q[1]).normalize_or_zero();
                    if n.dot(face_normal(target, face)) > -0.5 {
                        continue;
                    }
                    let c = (q[0] + q[1] + q[2] + q[3]) * 0.25;
                    let uv = |p: Vec3| face_uv(target, face, p);
                    let [cu, cv] = uv(c);
                    let gap = (c - target.face_point(face, cu, cv)).dot(n).abs();
                    let inside = (0.0..=1.0).contains(&cu) && (0.0..=1.0).contains(&cv);
                    let size = (q[0] - q[2]).length().max((q[1] - q[3]).length());
                    if !inside || gap > 1e-6 * size.max(1e-300) + self.threshold() * size {
                        continue;
                    }
                    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                    for p in q {
                        let w = uv(p);
                        for d in 0..2 {
                            lo[d] = lo[d].min(w[d]);
                            hi[d] = hi[d].max(w[d]);
                        }
                    }
                    clients.push(([cu, cv], lo, hi));
                }
            }
        }
        let mine = face_uv(target, face, subface_centre(&self.blocks()[m.block as usize], m.a.face, m.a.sub));
        if !clients.iter().any(|(c, _, _)| (c[0] - mine[0]).abs() < 1e-9 && (c[1] - mine[1]).abs() < 1e-9) {
            return None;
        }
        // Along each direction apart: the cell holding a client's centre must have its own
        // centre strictly inside the client's extent; two clients may not share a cell.
        let fits = |d: usize, n: u32| {
            clients.iter().all(|(c, lo, hi)| {
                let i = (c[d] * f64::from(n)).floor().clamp(0.0, f64::from(n - 1));
                let centre = (i + 0.5) / f64::from(n);
                let margin = 1e-9;
                centre > lo[d] + margin && centre < hi[d] - margin
            })
        };
        let cell = |c: &[f64; 2], nu: u32, nv: u32| {
            let i = (c[0] * f64::from(nu)).floor().clamp(0.0, f64::from(nu - 1)) as u32;
            let j = (c[1] * f64::from(nv)).floor().clamp(0.0, f64::from(nv - 1)) as u32;
            i + nu * j
        };
        // The divisions that fit each direction; the pair of fewest sub-faces (then fewest
        // along u) whose cells are all different.
        let us: Vec<u32> = (1..=MAX_SUBDIVISIONS).filter(|&n| fits(0, n)).take(32).collect();
        let vs: Vec<u32> = (1..=MAX_SUBDIVISIONS).filter(|&n| fits(1, n)).take(32).collect();
        let mut pairs: Vec<(u32, u32)> = us.iter().flat_map(|&u| vs.iter().map(move |&v| (u, v))).collect();
        pairs.sort_by_key(|&(u, v)| (u * v, u));
        pairs
            .into_iter()
            .find(|&(nu, nv)| {
                let mut cells: Vec<u32> = clients.iter().map(|(c, _, _)| cell(c, nu, nv)).collect();
                cells.sort_unstable();
                cells.windows(2).all(|w| w[0] != w[1])
            })
            .map(|(nu, nv)| Subdivision { block: m.other, face, nu, nv })
    }

    /// The pairs `(i, j)`, `i < j`, of blocks whose bounds touch within `eps` and whose groups
    /// may connect (a sweep along x).
    fn touching_pairs(&self, bounds: &[(Vec3, Vec3)], eps: f64) -> Vec<(usize, usize)> {
        let mut order: Vec<usize> = (0..bounds.len()).collect();
        order.sort_by(|&a, &b| bounds[a].0.x.total_cmp(&bounds[b].0.x));
        let blocks = self.blocks();
        let mut out = Vec::new();
        for (k, &i) in order.iter().enumerate() {
            for &j in &order[k + 1..] {
                if bounds[j].0.x > bounds[i].1.x + eps {
                    break;
                }
                let (a, b) = (bounds[i], bounds[j]);
                let apart = (0..3).any(|d| a.0[d] > b.1[d] + eps || b.0[d] > a.1[d] + eps);
                if !apart && self.is_allowed(blocks[i].group(), blocks[j].group()) {
                    out.push((i.min(j), i.max(j)));
                }
            }
        }
        out.sort_unstable();
        out
    }

    /// The facing sub-faces of blocks `i` and `j` nearest to connecting: least gap plus
    /// offset across the normal, over the pairs whose normals oppose.
    fn nearest_miss(&self, i: u32, j: u32) -> Option<Miss> {
        let subfaces = |b: u32| {
            let block = &self.blocks()[b as usize];
            Face::ALL.into_iter().flat_map(move |face| {
                (0..block.subface_count(face)).map(move |sub| {
                    let q = block.subface_corners(face, sub);
                    let normal = (q[2] - q[0]).cross(q[3] - q[1]).normalize_or_zero();
                    let perimeter: f64 = (0..4).map(|k| q[k].distance(q[(k + 1) % 4])).sum();
                    (SubFaceRef { block: b, face, sub }, (q[0] + q[1] + q[2] + q[3]) * 0.25, normal, perimeter)
                })
            })
        };
        let theirs: Vec<_> = subfaces(j).collect();
        let mut best: Option<Miss> = None;
        for (a, ca, na, pa) in subfaces(i) {
            for &(b, cb, nb, pb) in &theirs {
                if na.dot(nb) > -0.5 {
                    continue;
                }
                let d = cb - ca;
                let gap = d.dot(na);
                let offset = (d - na * gap).length();
                let m =
                    Miss { block: i, other: j, a, b, gap, offset, reach: self.threshold() * (pa + pb), advice: None };
                // Faces that face each other (one's centre over the other) before faces that
                // merely lie near (a leg's side and the top's side): then least gap and offset.
                let facing = |x: &Miss| {
                    let (ba, bb) = (&self.blocks()[x.block as usize], &self.blocks()[x.other as usize]);
                    let over = |blk: &Block, f: Face, p: Vec3| {
                        let [u, v] = face_uv(blk, f, p);
                        (-1e-9..=1.0 + 1e-9).contains(&u) && (-1e-9..=1.0 + 1e-9).contains(&v)
                    };
                    over(bb, x.b.face, subface_centre(ba, x.a.face, x.a.sub))
                        || over(ba, x.a.face, subface_centre(bb, x.b.face, x.b.sub))
                };
                let key = |x: &Miss| (u8::from(!facing(x)), x.gap.abs() + x.offset);
                let better = |x: &Miss| {
                    let (k, kx) = (key(&m), key(x));
                    k.0.cmp(&kx.0).then(k.1.total_cmp(&kx.1)).is_lt()
                };
                if best.as_ref().is_none_or(better) {
                    best = Some(m);
                }
            }
        }
        best
    }
}

/// The centre of sub-face `sub` of `face`.
fn subface_centre(b: &Block, face: Face, sub: u32) -> Vec3 {
    let q = b.subface_corners(face, sub);
    (q[0] + q[1] + q[2] + q[3]) * 0.25
}

/// The outward unit normal of a whole face (from its corners).
fn face_normal(b: &Block, face: Face) -> Vec3 {
    let p = |u, v| b.face_point(face, u, v);
    let n = (p(1.0, 0.0) - p(0.0, 0.0)).cross(p(0.0, 1.0) - p(0.0, 0.0)).normalize_or_zero();
    // The face's (u, v) frame may turn either way; outward is away from the block's centre.
    let centre = (b.face_point(face, 0.5, 0.5) - block_centre(b)).dot(n);
    if centre < 0.0 {
        -n
    } else {
        n
    }
}

fn block_centre(b: &Block) -> Vec3 {
    b.corners().iter().fold(Vec3::ZERO, |s, p| s + *p) / 8.0
}

/// The face coordinates `(u, v)` of `p` projected onto `face` (exact on a parallelogram face,
/// as blocks built from bounds have).
fn face_uv(b: &Block, face: Face, p: Vec3) -> [f64; 2] {
    let o = b.face_point(face, 0.0, 0.0);
    let (eu, ev) = (b.face_point(face, 1.0, 0.0) - o, b.face_point(face, 0.0, 1.0) - o);
    // Solve p - o = u eu + v ev in the least-squares sense (2 × 2 normal equations).
    let d = p - o;
    let (a, bb, c) = (eu.dot(eu), eu.dot(ev), ev.dot(ev));
    let (r, s) = (d.dot(eu), d.dot(ev));
    let det = a * c - bb * bb;
    if det.abs() < 1e-300 {
        return [f64::NAN, f64::NAN];
    }
    [(r * c - s * bb) / det, (s * a - r * bb) / det]
}

/// Disjoint sets of `0..n` (path halving).
struct UnionFind(Vec<usize>);

impl UnionFind {
    fn new(n: usize) -> UnionFind {
        UnionFind((0..n).collect())
    }

    fn root(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blocks::Block;

    /// A 2 × 2 × 0.2 top on four 0.2 × 0.2 legs at its corners, touching its underside.
    fn table(top_divisions: i64) -> BlockModel {
        let mut m = BlockModel::new();
        m.allow(0, 0);
        let mut top = Block::from_bounds(Vec3::new(0.0, 0.0, 1.0), Vec3::new(2.0, 2.0, 1.2)).unwrap();
        top.subdivide(Face::NegZ, top_divisions, top_divisions).unwrap();
        m.add(top);
        for (x, y) in [(0.0, 0.0), (1.8, 0.0), (0.0, 1.8), (1.8, 1.8)] {
            m.add(Block::from_bounds(Vec3::new(x, y, 0.0), Vec3::new(x + 0.2, y + 0.2, 1.0)).unwrap());
        }
        m
    }

    #[test]
    fn legs_under_the_top_s_corners_touch_it_without_connecting() {
        // The top's one -z sub-face has its centre in the middle, over no leg: no leg connects,
        // and each is reported with its top against the top's underside, touching (gap 0) but
        // with centres √2·0.9 apart across the faces.
        let m = table(1);
        let misses = m.unconnected().unwrap();
        assert_eq!(misses.iter().map(|x| x.block).collect::<Vec<_>>(), [1, 2, 3, 4]);
        for x in &misses {
            assert_eq!((x.other, x.a.face, x.b.face), (0, Face::PosZ, Face::NegZ), "{x:?}");
            assert!(x.gap.abs() < 1e-12, "{x:?}");
            assert!((x.offset - 0.9 * 2f64.sqrt()).abs() < 1e-12, "{x:?}");
        }
    }

    #[test]
    fn the_advice_names_a_subdivision_that_connects_every_leg_when_applied() {
        // Legs a tenth of the top wide at its corners: the smallest grid whose corner cells'
        // centres lie over the legs is 6 × 6 (5 puts the corner cell's centre at 0.1, the legs'
        // edge; 6 at 1/12 of the width, inside them).
        let mut m = table(1);
        let misses = m.unconnected().unwrap();
        for x in &misses {
            assert_eq!(x.advice, Some(Subdivision { block: 0, face: Face::NegZ, nu: 6, nv: 6 }), "{x:?}");
        }
        let mut top = m.blocks()[0].clone();
        top.subdivide(Face::NegZ, 6, 6).unwrap();
        m.set_block(0, top).unwrap();
        assert_eq!(m.connections().unwrap().len(), 4, "applying the advice connects all four legs");
        assert!(m.unconnected().unwrap().is_empty());
    }

    #[test]
    fn legs_off_the_grid_get_a_grid_that_serves_them_all() {
        // Legs of different sizes at uneven places under a 3 × 2 top: whatever the advice,
        // applying it connects every leg (and keeps the one already connected).
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(Block::from_bounds(Vec3::new(0.0, 0.0, 1.0), Vec3::new(3.0, 2.0, 1.3)).unwrap());
        let legs = [(0.1, 0.2, 0.25), (2.6, 0.05, 0.3), (1.2, 1.5, 0.4), (1.35, 0.8, 0.3)];
        for (x, y, w) in legs {
            m.add(Block::from_bounds(Vec3::new(x, y, 0.0), Vec3::new(x + w, y + w, 1.0)).unwrap());
        }
        let misses = m.unconnected().unwrap();
        assert!(!misses.is_empty());
        let advice = misses[0].advice.expect("advice for a leg under the top");
        assert!(misses.iter().all(|x| x.advice == Some(advice)), "one grid for the face: {misses:?}");
        let mut top = m.blocks()[0].clone();
        top.subdivide(advice.face, i64::from(advice.nu), i64::from(advice.nv)).unwrap();
        m.set_block(0, top).unwrap();
        assert_eq!(m.connections().unwrap().len(), legs.len(), "{advice:?}");
        assert!(m.unconnected().unwrap().is_empty());
    }

    #[test]
    fn a_leg_s_top_is_preferred_to_its_side_even_when_the_sides_lie_nearer() {
        // A thick leg flush with the top's corner: its side faces lie nearer the top's side faces
        // (by gap plus offset) than its top face's centre lies to the top's underside centre;
        // only the top faces face each other, and the advice is about them.
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(Block::from_bounds(Vec3::new(0.0, 0.0, 1.0), Vec3::new(4.0, 4.0, 1.2)).unwrap());
        m.add(Block::from_bounds(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.6, 0.6, 1.0)).unwrap());
        let miss = m.unconnected().unwrap()[0];
        assert_eq!((miss.a.face, miss.b.face), (Face::PosZ, Face::NegZ), "{miss:?}");
        assert!(miss.advice.is_some());
    }

    #[test]
    fn legs_under_sub_face_centres_connect_and_nothing_is_reported() {
        // Ten by ten sub-faces of 0.2: the corner sub-faces' centres lie over the legs' centres.
        let m = table(10);
        assert_eq!(m.connections().unwrap().len(), 4);
        assert!(m.unconnected().unwrap().is_empty());
    }

    #[test]
    fn apart_or_disallowed_blocks_and_single_pieces_are_not_reported() {
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(Block::from_bounds(Vec3::ZERO, Vec3::ONE).unwrap());
        assert!(m.unconnected().unwrap().is_empty());
        // Apart: two pieces on purpose.
        m.add(Block::from_bounds(Vec3::new(3.0, 0.0, 0.0), Vec3::new(4.0, 1.0, 1.0)).unwrap());
        assert!(m.unconnected().unwrap().is_empty());
        // Touching but of groups that may not connect (seed 000 Fig. 5a).
        let mut b = Block::from_bounds(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0)).unwrap();
        b.set_group(1);
        m.add(b);
        assert!(m.unconnected().unwrap().is_empty());
        m.allow(0, 1);
        assert!(m.unconnected().unwrap().is_empty(), "it connects now");
    }
}
