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

use super::{BlockError, BlockModel, Face, SubFaceRef};

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
        Ok(misses)
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
                let m = Miss { block: i, other: j, a, b, gap, offset, reach: self.threshold() * (pa + pb) };
                if best.is_none_or(|x| gap.abs() + offset < x.gap.abs() + x.offset) {
                    best = Some(m);
                }
            }
        }
        best
    }
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
