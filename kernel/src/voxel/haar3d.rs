//! The 3D Haar hierarchy of Heurtebise & Thon §2.2, in Pinnamaneni's layout.
//!
//! Notation: n the grid side; level L = 1…T transforms a cube of side m = n / 2^(L−1) (the
//! averages of level L − 1) by the 1D Haar transform along x, then y, then z; along each axis the
//! low-pass half goes first and the high-pass half second, so the octant `o = (ox, oy, oz)` of the
//! cube (offset `o · m/2`) holds the block `L…` / `H…` named by its bits (`(0,0,0)` = LLL, the
//! averages that level L + 1 transforms in turn). The coefficient of block `(i, j, k)` and octant
//! `o` sits at `(i, j, k) + o · m/2`.
//!
//! Exactness: the paper's transform is `(a + b)/2`, `(a − b)/2`; here every pass stores `a + b`
//! and `a − b` instead, i.e. each level-L coefficient is 8ᴸ × the paper's. Every coefficient is
//! then an integer (a level-L average is the exact block sum / 8ᴸ) and the inverse
//! `a = (s + d)/2`, `b = (s − d)/2` divides exactly: reconstruction is bit-identical and every
//! level of detail is the exact 2ᴸ box-filter average, rounded once.
//!
//! Storage: level 1 coefficients are at most 8 · 255 in magnitude and level 2 at most 64 · 255,
//! so levels 1–2 live in one n³ `i16` array (2 bytes per voxel); levels 3 and up, which need
//! more bits, live in an (n/4)³ `i64` array with the same in-place layout.
//!
//! Evaluation: a level's three passes are fused per 2 × 2 × 2 block (the result is the same
//! as three whole-array passes, since each pass pairs the same two entries), run over z-slabs on
//! rayon's pool when asked.

use rayon::prelude::*;

use super::VoxelError;

/// The Haar coefficients of a grid: see the module documentation for layout and scaling.
#[derive(Clone, Debug, PartialEq)]
pub struct HaarHierarchy {
    n: usize,
    levels: u32,
    /// Levels 1–2 (or the densities themselves when `levels` is 0), stride n.
    near: Vec<i16>,
    /// Levels 3…, stride n/4; empty when `levels` < 3.
    deep: Vec<i64>,
}

/// The forward transform of one 2 × 2 × 2 block, corner `c = x + 2y + 4z` in, octant
/// `o = ox + 2oy + 4oz` out: pairs along x, then y, then z become (sum, difference).
#[inline]
fn forward8(mut a: [i64; 8]) -> [i64; 8] {
    for step in [1, 2, 4] {
        for p in 0..8 {
            if p & step == 0 {
                let (s, d) = (a[p] + a[p + step], a[p] - a[p + step]);
                a[p] = s;
                a[p + step] = d;
            }
        }
    }
    a
}

/// The inverse of [`forward8`]: the same butterflies in reverse order yield 8 × the corners,
/// divided exactly at the end.
#[inline]
fn inverse8(mut a: [i64; 8]) -> [i64; 8] {
    for step in [4, 2, 1] {
        for p in 0..8 {
            if p & step == 0 {
                let (s, d) = (a[p] + a[p + step], a[p] - a[p + step]);
                a[p] = s;
                a[p + step] = d;
            }
        }
    }
    // Exact: every entry is 8 × an integer, so the shift divides without rounding.
    a.map(|v| v >> 3)
}

/// A coefficient store: `i16` for levels 1–2, `i64` above.
trait Store: Copy + Send + Sync + Default {
    fn to_i64(self) -> i64;
    fn from_i64(v: i64) -> Self;
}

impl Store for i16 {
    #[inline]
    fn to_i64(self) -> i64 {
        i64::from(self)
    }
    #[inline]
    fn from_i64(v: i64) -> Self {
        debug_assert!(i16::try_from(v).is_ok(), "level 1–2 coefficient {v} out of i16 range");
        v as i16
    }
}

impl Store for i64 {
    #[inline]
    fn to_i64(self) -> i64 {
        self
    }
    #[inline]
    fn from_i64(v: i64) -> Self {
        v
    }
}

/// Input of a forward level: the densities (u8) or the previous level's sums (i64).
trait Load: Copy + Send + Sync {
    fn load(self) -> i64;
}

impl Load for u8 {
    #[inline]
    fn load(self) -> i64 {
        i64::from(self)
    }
}

impl Load for i64 {
    #[inline]
    fn load(self) -> i64 {
        self
    }
}

/// Runs `f(k, plane k, plane k + h)` for k in 0..h over the planes (`plane` entries each) of
/// `dst`, on rayon's pool when `parallel`.
fn for_each_plane_pair<S: Send>(
    parallel: bool,
    dst: &mut [S],
    plane: usize,
    h: usize,
    f: impl Fn(usize, &mut [S], &mut [S]) + Sync + Send,
) {
    let (lower, upper) = dst.split_at_mut(h * plane);
    let lower = &mut lower[..h * plane];
    let upper = &mut upper[..h * plane];
    if parallel {
        lower.par_chunks_mut(plane).zip(upper.par_chunks_mut(plane)).enumerate().for_each(|(k, (a, b))| f(k, a, b));
    } else {
        lower.chunks_mut(plane).zip(upper.chunks_mut(plane)).enumerate().for_each(|(k, (a, b))| f(k, a, b));
    }
}

/// One forward level: `src` is a cube of side m at row stride `ss` (x fastest, plane stride
/// `ss²`); its coefficients go into `dst` (stride `ds`) in the octant layout of side m.
fn forward_level<I: Load, S: Store>(src: &[I], ss: usize, m: usize, dst: &mut [S], ds: usize, parallel: bool) {
    let h = m / 2;
    let splane = ss * ss;
    for_each_plane_pair(parallel, dst, ds * ds, h, |k, lo, hi| {
        let z0 = 2 * k * splane;
        let z1 = z0 + splane;
        for j in 0..h {
            let (y0, y1) = (2 * j * ss, (2 * j + 1) * ss);
            let (r0, r1) = (j * ds, (j + h) * ds);
            for i in 0..h {
                let x = 2 * i;
                let c = forward8([
                    src[z0 + y0 + x].load(),
                    src[z0 + y0 + x + 1].load(),
                    src[z0 + y1 + x].load(),
                    src[z0 + y1 + x + 1].load(),
                    src[z1 + y0 + x].load(),
                    src[z1 + y0 + x + 1].load(),
                    src[z1 + y1 + x].load(),
                    src[z1 + y1 + x + 1].load(),
                ]);
                lo[r0 + i] = S::from_i64(c[0]);
                lo[r0 + i + h] = S::from_i64(c[1]);
                lo[r1 + i] = S::from_i64(c[2]);
                lo[r1 + i + h] = S::from_i64(c[3]);
                hi[r0 + i] = S::from_i64(c[4]);
                hi[r0 + i + h] = S::from_i64(c[5]);
                hi[r1 + i] = S::from_i64(c[6]);
                hi[r1 + i + h] = S::from_i64(c[7]);
            }
        }
    });
}

/// The octant-0 cube of side `side` at stride `stride`, copied compactly as i64.
fn copy_lows<S: Store>(store: &[S], stride: usize, side: usize) -> Vec<i64> {
    let mut out = Vec::with_capacity(side * side * side);
    for z in 0..side {
        for y in 0..side {
            let r = (z * stride + y) * stride;
            out.extend(store[r..r + side].iter().map(|v| v.to_i64()));
        }
    }
    out
}

/// One row of blocks of an inverse level: the averages `parent` and the details at `bases[o] + x`
/// (octants 1–7) become two rows of children in each of two planes:
/// `rows = [(y0, z0), (y1, z0), (y0, z1), (y1, z1)]`.
fn inverse_row<S: Store>(store: &[S], bases: &[usize; 8], parent: &[i64], rows: [&mut [i64]; 4]) {
    let [r00, r10, r01, r11] = rows;
    for (x, &p) in parent.iter().enumerate() {
        let v = inverse8([
            p,
            store[bases[1] + x].to_i64(),
            store[bases[2] + x].to_i64(),
            store[bases[3] + x].to_i64(),
            store[bases[4] + x].to_i64(),
            store[bases[5] + x].to_i64(),
            store[bases[6] + x].to_i64(),
            store[bases[7] + x].to_i64(),
        ]);
        r00[2 * x] = v[0];
        r00[2 * x + 1] = v[1];
        r10[2 * x] = v[2];
        r10[2 * x + 1] = v[3];
        r01[2 * x] = v[4];
        r01[2 * x + 1] = v[5];
        r11[2 * x] = v[6];
        r11[2 * x + 1] = v[7];
    }
}

impl HaarHierarchy {
    /// [`HaarHierarchy::build`] on raw densities; `levels` ≤ log₂ n is the caller's promise.
    pub(crate) fn build_with(data: &[u8], n: usize, levels: u32, parallel: bool) -> HaarHierarchy {
        let mut near = vec![0i16; n * n * n];
        let mut deep = Vec::new();
        if levels == 0 {
            near.iter_mut().zip(data).for_each(|(c, &v)| *c = i16::from(v));
        } else {
            forward_level(data, n, n, &mut near, n, parallel);
        }
        if levels >= 2 {
            let lows = copy_lows(&near, n, n / 2);
            forward_level(&lows, n / 2, n / 2, &mut near, n, parallel);
        }
        if levels >= 3 {
            let d = n / 4;
            let lows = copy_lows(&near, n, d);
            // The level-2 averages move to `deep`; clear them in `near` so no stale copy remains.
            for z in 0..d {
                for y in 0..d {
                    let r = (z * n + y) * n;
                    near[r..r + d].fill(0);
                }
            }
            deep = vec![0i64; d * d * d];
            forward_level(&lows, d, d, &mut deep, d, parallel);
            for l in 4..=levels {
                let m = n >> (l - 1);
                let lows = copy_lows(&deep, d, m);
                forward_level(&lows, m, m, &mut deep, d, parallel);
            }
        }
        HaarHierarchy { n, levels, near, deep }
    }

    /// The grid side n.
    #[must_use]
    pub fn size(&self) -> usize {
        self.n
    }

    /// The number of levels built (the coarsest averages are at this level).
    #[must_use]
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// Heap bytes of the coefficients.
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        self.near.capacity() * 2 + self.deep.capacity() * 8
    }

    /// Where level `level`'s coefficient of block `b` and octant `o` lives: (in `deep`?, index).
    fn slot(&self, level: u32, o: usize, b: [usize; 3]) -> (bool, usize) {
        let h = self.n >> level;
        let p = [b[0] + (o & 1) * h, b[1] + ((o >> 1) & 1) * h, b[2] + ((o >> 2) & 1) * h];
        if level <= 2 {
            (false, (p[2] * self.n + p[1]) * self.n + p[0])
        } else {
            let d = self.n / 4;
            (true, (p[2] * d + p[1]) * d + p[0])
        }
    }

    fn read(&self, slot: (bool, usize)) -> i64 {
        if slot.0 {
            self.deep[slot.1]
        } else {
            i64::from(self.near[slot.1])
        }
    }

    fn add(&mut self, slot: (bool, usize), v: i64) {
        if slot.0 {
            self.deep[slot.1] += v;
        } else {
            self.near[slot.1] = i16::from_i64(i64::from(self.near[slot.1]) + v);
        }
    }

    /// The stored coefficient of level `level` (1…levels), octant `octant` (0…7, bits x, y, z;
    /// 0 = LLL, kept only at the coarsest level) and block `(i, j, k)`: 8ˡᵉᵛᵉˡ × the paper's
    /// coefficient. With `level` 0 (only when no level was built) it is the density.
    ///
    /// # Errors
    /// [`VoxelError::LevelOutOfRange`] or [`VoxelError::InvalidArgument`] for an index outside
    /// the level.
    pub fn coefficient(&self, level: u32, octant: usize, block: [usize; 3]) -> Result<i64, VoxelError> {
        if level > self.levels || (level == 0 && self.levels != 0) {
            return Err(VoxelError::LevelOutOfRange { level: i64::from(level), max: self.levels, n: self.n });
        }
        let h = self.n >> level.max(1);
        if octant > 7 || block.iter().any(|&b| b >= h.max(1)) || (level == 0 && octant != 0) {
            return Err(VoxelError::InvalidArgument {
                what: "Haar coefficient index",
                reason: format!("octant {octant}, block {block:?} outside level {level}"),
            });
        }
        if level == 0 {
            return Ok(i64::from(self.near[(block[2] * self.n + block[1]) * self.n + block[0]]));
        }
        if octant == 0 && level < self.levels {
            return Err(VoxelError::InvalidArgument {
                what: "Haar coefficient index",
                reason: format!("the averages of level {level} are not stored (level {} transforms them)", level + 1),
            });
        }
        Ok(self.read(self.slot(level, octant, block)))
    }

    /// The exact block sums of level `level` (side s = n / 2ˡᵉᵛᵉˡ, each the sum of the 8ˡᵉᵛᵉˡ
    /// densities of its block) over the box `[lo, hi)` of that level, x fastest, reconstructed
    /// from the coarsest averages down through the stored details (the inverse transform, only
    /// for the blocks above the box).
    ///
    /// # Errors
    /// [`VoxelError::LevelOutOfRange`] for a level above the built ones,
    /// [`VoxelError::InvalidArgument`] for an empty box or one outside the level.
    pub fn sums(&self, level: u32, lo: [usize; 3], hi: [usize; 3], parallel: bool) -> Result<Vec<i64>, VoxelError> {
        if level > self.levels {
            return Err(VoxelError::LevelOutOfRange { level: i64::from(level), max: self.levels, n: self.n });
        }
        let side = self.n >> level;
        if (0..3).any(|a| lo[a] >= hi[a] || hi[a] > side) {
            return Err(VoxelError::InvalidArgument {
                what: "Haar extraction box",
                reason: format!("[{lo:?}, {hi:?}) is empty or outside the {side}³ level {level}"),
            });
        }
        Ok(self.sums_in(level, lo, hi, parallel))
    }

    fn sums_in(&self, level: u32, lo: [usize; 3], hi: [usize; 3], parallel: bool) -> Vec<i64> {
        let dims = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        if level == self.levels {
            let mut out = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
            for z in lo[2]..hi[2] {
                for y in lo[1]..hi[1] {
                    for x in lo[0]..hi[0] {
                        let v = if level == 0 {
                            i64::from(self.near[(z * self.n + y) * self.n + x])
                        } else {
                            self.read(self.slot(level, 0, [x, y, z]))
                        };
                        out.push(v);
                    }
                }
            }
            return out;
        }
        // The parent blocks covering the box, then one inverse level over them.
        let plo = [lo[0] / 2, lo[1] / 2, lo[2] / 2];
        let phi = [hi[0].div_ceil(2), hi[1].div_ceil(2), hi[2].div_ceil(2)];
        let parent = self.sums_in(level + 1, plo, phi, parallel);
        let pd = [phi[0] - plo[0], phi[1] - plo[1], phi[2] - plo[2]];
        let od = [2 * pd[0], 2 * pd[1], 2 * pd[2]];
        let mut out = vec![0i64; od[0] * od[1] * od[2]];
        let plane = od[0] * od[1];
        let pl = level + 1;
        let h = self.n >> pl;
        let stride = if pl <= 2 { self.n } else { self.n / 4 };
        super::for_each_chunk(parallel, &mut out, 2 * plane, |bz, chunk| {
            let (a, b) = chunk.split_at_mut(plane);
            let gz = plo[2] + bz;
            for by in 0..pd[1] {
                let gy = plo[1] + by;
                // Where each octant's row of coefficients starts in the store.
                let bases: [usize; 8] = std::array::from_fn(|o| {
                    ((gz + ((o >> 2) & 1) * h) * stride + gy + ((o >> 1) & 1) * h) * stride + (o & 1) * h + plo[0]
                });
                let prow = &parent[(bz * pd[1] + by) * pd[0]..][..pd[0]];
                let r0 = 2 * by * od[0];
                let r1 = r0 + od[0];
                let (a0, a1) = a[r0..r1 + od[0]].split_at_mut(od[0]);
                let (b0, b1) = b[r0..r1 + od[0]].split_at_mut(od[0]);
                let rows = [a0, a1, b0, b1];
                if pl <= 2 {
                    inverse_row(&self.near, &bases, prow, rows);
                } else {
                    inverse_row(&self.deep, &bases, prow, rows);
                }
            }
        });
        let start = [lo[0] - 2 * plo[0], lo[1] - 2 * plo[1], lo[2] - 2 * plo[2]];
        if start == [0; 3] && dims == od {
            return out;
        }
        let mut cropped = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                let r = ((z + start[2]) * od[1] + y + start[1]) * od[0] + start[0];
                cropped.extend_from_slice(&out[r..r + dims[0]]);
            }
        }
        cropped
    }

    /// Level `level` of detail: side n / 2ˡᵉᵛᵉˡ, each density the average of its 2ˡᵉᵛᵉˡ-cube
    /// block rounded half up — exactly the direct box filter. Level 0 reconstructs the grid
    /// bit for bit.
    ///
    /// # Errors
    /// [`VoxelError::LevelOutOfRange`] for a level above the built ones.
    pub fn extract(&self, level: u32, parallel: bool) -> Result<Vec<u8>, VoxelError> {
        let side = self.n >> level.min(31);
        let sums = self.sums(level, [0; 3], [side; 3], parallel)?;
        Ok(sums_to_densities(&sums, level))
    }

    /// Adds the Haar transform of a change of densities (`delta` over the box at `lo` with
    /// `dims`, x fastest) to the coefficients: the transform is linear, so this equals a rebuild
    /// from the edited grid while touching only the blocks above the box.
    pub(crate) fn add_delta(&mut self, lo: [usize; 3], dims: [usize; 3], delta: &[i16], _parallel: bool) {
        if self.levels == 0 {
            for z in 0..dims[2] {
                for y in 0..dims[1] {
                    for x in 0..dims[0] {
                        let i = ((lo[2] + z) * self.n + lo[1] + y) * self.n + lo[0] + x;
                        let d = delta[(z * dims[1] + y) * dims[0] + x];
                        self.near[i] += d;
                    }
                }
            }
            return;
        }
        // The change at the current level over [clo, clo + cd).
        let mut clo = lo;
        let mut cd = dims;
        let mut cur: Vec<i64> = delta.iter().map(|&d| i64::from(d)).collect();
        for level in 1..=self.levels {
            let blo = [clo[0] / 2, clo[1] / 2, clo[2] / 2];
            let bhi = [(clo[0] + cd[0]).div_ceil(2), (clo[1] + cd[1]).div_ceil(2), (clo[2] + cd[2]).div_ceil(2)];
            let bd = [bhi[0] - blo[0], bhi[1] - blo[1], bhi[2] - blo[2]];
            let mut next = vec![0i64; bd[0] * bd[1] * bd[2]];
            let at = |p: [usize; 3]| -> i64 {
                if (0..3).all(|a| p[a] >= clo[a] && p[a] < clo[a] + cd[a]) {
                    cur[((p[2] - clo[2]) * cd[1] + p[1] - clo[1]) * cd[0] + p[0] - clo[0]]
                } else {
                    0
                }
            };
            let mut adds = Vec::with_capacity(bd[0] * bd[1] * bd[2] * 7);
            for bz in 0..bd[2] {
                for by in 0..bd[1] {
                    for bx in 0..bd[0] {
                        let b = [blo[0] + bx, blo[1] + by, blo[2] + bz];
                        let mut v = [0i64; 8];
                        for (c, slot) in v.iter_mut().enumerate() {
                            *slot = at([2 * b[0] + (c & 1), 2 * b[1] + ((c >> 1) & 1), 2 * b[2] + ((c >> 2) & 1)]);
                        }
                        let coef = forward8(v);
                        next[(bz * bd[1] + by) * bd[0] + bx] = coef[0];
                        let first = if level == self.levels { 0 } else { 1 };
                        for (o, &cv) in coef.iter().enumerate().skip(first) {
                            if cv != 0 {
                                adds.push((level, o, b, cv));
                            }
                        }
                    }
                }
            }
            for (level, o, b, cv) in adds {
                let slot = self.slot(level, o, b);
                self.add(slot, cv);
            }
            clo = blo;
            cd = bd;
            cur = next;
        }
    }
}

/// Exact level-`level` block sums → densities: the average rounded half up,
/// `⌊(2S + 8ˡ) / (2 · 8ˡ)⌋`.
pub(crate) fn sums_to_densities(sums: &[i64], level: u32) -> Vec<u8> {
    let count = 1i64 << (3 * level);
    sums.iter().map(|&s| ((2 * s + count) / (2 * count)).clamp(0, 255) as u8).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{SplitMix64, Vec3};
    use crate::voxel::Voxels;

    /// Seeded random bytes (the top byte of each number of the kernel's SplitMix64).
    fn random_bytes(len: usize, seed: u64) -> Vec<u8> {
        let mut rng = SplitMix64::new(seed);
        (0..len).map(|_| (rng.next_u64() >> 56) as u8).collect()
    }

    #[test]
    fn block_transform_inverts_exactly() {
        let v = [255, 0, 17, 3, 200, 199, 1, 254];
        assert_eq!(inverse8(forward8(v)), v);
        // The LLL coefficient is the block sum (8 × the paper's average).
        assert_eq!(forward8(v)[0], v.iter().sum::<i64>());
    }

    #[test]
    fn reconstruction_is_bit_identical_for_random_grids() {
        // Integer coefficients and exact halving make the inverse exact at every level count.
        for (n, seed) in [(2usize, 1u64), (8, 2), (16, 3), (32, 4)] {
            let data = random_bytes(n * n * n, seed);
            for levels in 0..=n.trailing_zeros() {
                for parallel in [false, true] {
                    let h = HaarHierarchy::build_with(&data, n, levels, parallel);
                    assert_eq!(h.extract(0, parallel).unwrap(), data, "n {n}, levels {levels}, parallel {parallel}");
                }
            }
        }
    }

    #[test]
    fn parallel_build_equals_serial_build() {
        let n = 32;
        let data = random_bytes(n * n * n, 99);
        assert_eq!(HaarHierarchy::build_with(&data, n, 5, true), HaarHierarchy::build_with(&data, n, 5, false));
    }

    /// The direct 2ᵏ box-filter average of a grid, rounded half up.
    fn box_filter(data: &[u8], n: usize, k: u32) -> Vec<u8> {
        let b = 1usize << k;
        let s = n / b;
        let mut out = Vec::with_capacity(s * s * s);
        for z in 0..s {
            for y in 0..s {
                for x in 0..s {
                    let mut sum = 0i64;
                    for dz in 0..b {
                        for dy in 0..b {
                            for dx in 0..b {
                                sum += i64::from(data[((z * b + dz) * n + y * b + dy) * n + x * b + dx]);
                            }
                        }
                    }
                    out.push(sum);
                }
            }
        }
        sums_to_densities(&out, k)
    }

    #[test]
    fn level_k_of_a_sphere_is_the_direct_box_filter_average() {
        // Level k averages are exact block sums / 8ᵏ, so rounding once matches the direct filter.
        let mut v = Voxels::new(32).unwrap();
        v.fill_sphere(Vec3::new(15.3, 16.8, 16.1), 11.7).unwrap();
        let h = HaarHierarchy::build(&v, 5).unwrap();
        for k in 0..=5 {
            let direct = box_filter(v.data(), 32, k);
            assert_eq!(h.extract(k, true).unwrap(), direct, "level {k}");
        }
        // Level 5 is the single average of the whole grid: volume · 255 / 32³.
        let mean = v.data().iter().map(|&d| f64::from(d)).sum::<f64>() / 32768.0;
        assert_eq!(f64::from(h.extract(5, false).unwrap()[0]), mean.round());
    }

    #[test]
    fn papers_one_dimensional_example_is_a_row_of_the_3d_transform() {
        // A grid constant along y and z, with x-rows [9 7 3 5]: the LLL of level 2 is 64 · 6 and the
        // x-only detail coefficients are 8 · 1, 8 · (−1) at level 1 and 64 · 2 at level 2.
        let n = 4;
        let row = [9u8, 7, 3, 5];
        let data: Vec<u8> = (0..n * n * n).map(|i| row[i % 4]).collect();
        let h = HaarHierarchy::build_with(&data, n, 2, false);
        assert_eq!(h.coefficient(2, 0, [0, 0, 0]).unwrap(), 64 * 6);
        assert_eq!(h.coefficient(2, 1, [0, 0, 0]).unwrap(), 64 * 2);
        assert_eq!(h.coefficient(1, 1, [0, 0, 0]).unwrap(), 8);
        assert_eq!(h.coefficient(1, 1, [1, 1, 1]).unwrap(), -8);
        // Details along y and z vanish for data constant along y and z.
        for o in 2..8 {
            assert_eq!(h.coefficient(1, o, [0, 1, 0]).unwrap(), 0, "octant {o}");
        }
        assert!(h.coefficient(1, 0, [0, 0, 0]).is_err(), "level-1 averages are not stored");
        assert!(h.coefficient(3, 0, [0, 0, 0]).is_err());
    }

    #[test]
    fn delta_updates_equal_a_rebuild() {
        let n = 16;
        let data = random_bytes(n * n * n, 5);
        for levels in [0, 1, 2, 3, 4] {
            let mut h = HaarHierarchy::build_with(&data, n, levels, false);
            let mut edited = data.clone();
            let (lo, dims) = ([3usize, 5, 7], [5usize, 2, 6]);
            let mut delta = Vec::new();
            let fresh = random_bytes(60, 77);
            for z in 0..dims[2] {
                for y in 0..dims[1] {
                    for x in 0..dims[0] {
                        let i = ((lo[2] + z) * n + lo[1] + y) * n + lo[0] + x;
                        let new = fresh[(z * dims[1] + y) * dims[0] + x];
                        delta.push(i16::from(new) - i16::from(edited[i]));
                        edited[i] = new;
                    }
                }
            }
            h.add_delta(lo, dims, &delta, false);
            assert_eq!(h, HaarHierarchy::build_with(&edited, n, levels, false), "levels {levels}");
        }
    }

    #[test]
    fn regions_of_a_level_match_the_whole_level() {
        let n = 16;
        let data = random_bytes(n * n * n, 11);
        let h = HaarHierarchy::build_with(&data, n, 4, false);
        let whole = h.sums(1, [0; 3], [8; 3], false).unwrap();
        let part = h.sums(1, [1, 2, 3], [6, 5, 8], true).unwrap();
        let mut i = 0;
        for z in 3..8 {
            for y in 2..5 {
                for x in 1..6 {
                    assert_eq!(part[i], whole[(z * 8 + y) * 8 + x]);
                    i += 1;
                }
            }
        }
        assert!(h.sums(1, [0; 3], [9, 8, 8], false).is_err());
        assert!(h.sums(5, [0; 3], [1; 3], false).is_err());
    }
}
