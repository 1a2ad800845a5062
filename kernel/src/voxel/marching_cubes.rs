//! Marching cubes over a density image (Lorensen & Cline 1987), as used for display in
//! Heurtebise & Thon §2.3, cut into blocks so that a cache can re-mesh only what changed.
//!
//! Samples sit at voxel centres (image voxel i at i + 0.5). The image is padded with one layer of
//! empty samples on every side, so an object touching the border is capped and the output is
//! always closed. Cells are indexed in the padded lattice: cell c spans padded samples c and c+1
//! (image voxels c−1 and c), c = 0…m for an image of side m, grouped in blocks of
//! [`BLOCK`]³ cells. A triangle corner is named by the grid edge it lies on, so the triangles of
//! different blocks weld by name into one indexed, manifold mesh (see [`mc_table`](super::mc_table)
//! for why it is closed and manifold).

use super::mc_table::{table, EDGES};
use super::smooth_field::{smooth_block, GAIN};
use super::{map_range_checked, map_range_polled, VoxelError};
use crate::math::Vec3;
use crate::mesh::Mesh;

/// Cells per block side.
pub(super) const BLOCK: usize = 16;
/// The work of meshing one block, in cancellation units (its cells).
pub(super) const CELLS_PER_BLOCK: u64 = (BLOCK * BLOCK * BLOCK) as u64;
/// Samples per block side (a block's cells reach one sample past the block).
pub(super) const BS: usize = BLOCK + 1;

/// Which field marching cubes contours.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Surface {
    /// The densities smoothed by a 7-tap filter with no second moment (see `smooth_field`): no
    /// terraces on curved surfaces, flat faces on rotated boxes, sharp edges rounded over about
    /// three voxels. The default.
    #[default]
    Smooth,
    /// The densities themselves, as Heurtebise & Thon §2.3 display them: exact where a voxel is
    /// partly covered, stepped where the densities jump from 0 to 255.
    Raw,
}

impl Surface {
    /// How far (in samples) a density change can move this surface: the filter's reach.
    pub(super) fn reach(self) -> usize {
        match self {
            Surface::Smooth => super::smooth_field::RADIUS,
            Surface::Raw => 0,
        }
    }
}

/// The smoothed field of one block's BS³ padded samples, with the iso level on its scale.
struct BlockField {
    values: Vec<i32>,
    iso: f64,
}

impl BlockField {
    fn new(img: Image<'_>, iso: f64, origin: [usize; 3]) -> BlockField {
        BlockField { values: smooth_block(img, origin), iso: iso * GAIN }
    }

    /// Whether local sample `s` is inside.
    #[inline]
    fn inside(&self, s: usize) -> bool {
        f64::from(self.values[s]) > self.iso
    }

    /// Where the field crosses the iso level between local samples `a` (inside) and `b`, kept
    /// 10⁻³ of a voxel from both: a smoothed sample can equal the iso level exactly, and two
    /// crossings at one sample would make a triangle of no area.
    fn crossing(&self, a: usize, b: usize) -> f64 {
        let (va, vb) = (f64::from(self.values[a]), f64::from(self.values[b]));
        ((va - self.iso) / (va - vb)).clamp(1e-3, 1.0 - 1e-3)
    }
}

/// A density image of side m; samples outside it read as empty.
#[derive(Clone, Copy)]
pub(super) struct Image<'a> {
    pub values: &'a [u8],
    pub m: usize,
}

impl Image<'_> {
    /// The sample at padded coordinates `p` (image voxel p − 1), 0 outside the image.
    #[inline]
    fn padded(&self, p: [usize; 3]) -> u8 {
        let m = self.m;
        if p.iter().any(|&c| c == 0 || c > m) {
            0
        } else {
            self.values[((p[2] - 1) * m + p[1] - 1) * m + p[0] - 1]
        }
    }
}

/// Blocks per axis for an image of side m (m + 1 cells per axis).
pub(super) fn block_count(m: usize) -> usize {
    (m + 1).div_ceil(BLOCK)
}

/// Checks an iso level: finite, in [0, 255).
pub(super) fn check_iso(iso: f64) -> Result<(), VoxelError> {
    if !iso.is_finite() {
        return Err(VoxelError::NonFinite { what: "iso level", value: format!("{iso}") });
    }
    if !(0.0..255.0).contains(&iso) {
        return Err(VoxelError::InvalidArgument {
            what: "iso level",
            reason: format!("{iso} is outside [0, 255): densities above it are inside"),
        });
    }
    Ok(())
}

/// The triangles of block `b` as block-local edge keys, three per triangle:
/// `((sz · 17 + sy) · 17 + sx) · 3 + axis` for the edge from local sample `s` along `axis`.
pub(super) fn mesh_block(img: Image<'_>, iso: f64, b: [usize; 3], surface: Surface) -> Vec<u16> {
    let cells = img.m + 1;
    let origin = [b[0] * BLOCK, b[1] * BLOCK, b[2] * BLOCK];
    let lim = [(cells - origin[0]).min(BLOCK), (cells - origin[1]).min(BLOCK), (cells - origin[2]).min(BLOCK)];
    let mut inside = [false; BS * BS * BS];
    let (mut any_in, mut any_out) = (false, false);
    match surface {
        Surface::Raw => {
            // A density is inside when above iso, i.e. at least ⌊iso⌋ + 1.
            let threshold = iso.floor() as u16 + 1;
            let m = img.m;
            for lz in 0..=lim[2] {
                let pz = origin[2] + lz;
                for ly in 0..=lim[1] {
                    let py = origin[1] + ly;
                    let row = &mut inside[(lz * BS + ly) * BS..][..=lim[0]];
                    if pz == 0 || pz > m || py == 0 || py > m {
                        row.fill(false);
                        any_out = true;
                        continue;
                    }
                    let r = ((pz - 1) * m + py - 1) * m;
                    for (lx, slot) in row.iter_mut().enumerate() {
                        let px = origin[0] + lx;
                        let v = if px == 0 || px > m { 0 } else { img.values[r + px - 1] };
                        let is_in = u16::from(v) >= threshold;
                        *slot = is_in;
                        any_in |= is_in;
                        any_out |= !is_in;
                    }
                }
            }
        }
        Surface::Smooth => {
            let field = BlockField::new(img, iso, origin);
            for lz in 0..=lim[2] {
                for ly in 0..=lim[1] {
                    for lx in 0..=lim[0] {
                        let s = (lz * BS + ly) * BS + lx;
                        let is_in = field.inside(s);
                        inside[s] = is_in;
                        any_in |= is_in;
                        any_out |= !is_in;
                    }
                }
            }
        }
    }
    let mut out = Vec::new();
    if !(any_in && any_out) {
        return out;
    }
    let t = table();
    for lz in 0..lim[2] {
        for ly in 0..lim[1] {
            for lx in 0..lim[0] {
                let base = (lz * BS + ly) * BS + lx;
                let mut case = 0u8;
                for c in 0..8 {
                    let off = (c & 1) + ((c >> 1) & 1) * BS + ((c >> 2) & 1) * BS * BS;
                    case |= u8::from(inside[base + off]) << c;
                }
                for tri in t.triangles(case) {
                    for &e in tri {
                        let (a, _) = EDGES[e as usize];
                        let a = usize::from(a);
                        let s = base + (a & 1) + ((a >> 1) & 1) * BS + ((a >> 2) & 1) * BS * BS;
                        out.push((s * 3 + usize::from(e) / 4) as u16);
                    }
                }
            }
        }
    }
    out
}

/// Welds the triangles of all blocks (`blocks[(bz · nb + by) · nb + bx]`, as from
/// [`mesh_block`]) into one mesh; vertex positions interpolate the iso crossing along each edge
/// and are mapped by `map` from image coordinates.
///
/// Welding: each grid edge is owned by the block holding its lower sample, so a corner on a
/// block's upper face belongs to the neighbour. Every block gathers the edges it owns from its
/// own corners and those of its 7 lower neighbours, sorts them, and numbers them after the
/// vertices of the blocks before it; a corner is then found by binary search in its owner's
/// short list. Vertex numbers depend only on the triangles, not on how blocks were scheduled.
/// Every pass reads the current cancellation token before each block, and the mesh build
/// charges it: a stop ends the assembly with [`VoxelError::Limit`].
pub(super) fn assemble(
    img: Image<'_>,
    iso: f64,
    surface: Surface,
    blocks: &[Vec<u16>],
    map: impl Fn(Vec3) -> Vec3 + Sync,
    parallel: bool,
) -> Result<Mesh, VoxelError> {
    let nb = block_count(img.m);
    let count = blocks.len();
    // The mesh to build: three corners per triangle, about half as many vertices as triangles.
    let triangles = blocks.iter().map(|b| b.len() as f64).sum::<f64>() / 3.0;
    crate::mesh::check_mesh_size(
        || format!("the marching-cubes surface ({} triangles)", triangles as u64),
        triangles / 2.0,
        3.0 * triangles,
        triangles,
    )?;
    // Each corner as (which of the 8 blocks at or above its block owns it, its key there).
    let refs: Vec<Vec<(u8, u16)>> = map_range_polled(parallel, count, |b| {
        blocks[b]
            .iter()
            .map(|&k| {
                let (s, axis) = (usize::from(k) / 3, usize::from(k) % 3);
                let (x, y, z) = (s % BS, (s / BS) % BS, s / (BS * BS));
                let d = u8::from(x == BLOCK) | u8::from(y == BLOCK) << 1 | u8::from(z == BLOCK) << 2;
                let (x, y, z) = (x % BLOCK, y % BLOCK, z % BLOCK);
                (d, (((z * BS + y) * BS + x) * 3 + axis) as u16)
            })
            .collect()
    })?;
    let step = |d: u8| usize::from(d & 1) + usize::from((d >> 1) & 1) * nb + usize::from(d >> 2) * nb * nb;
    let owned: Vec<Vec<u16>> = map_range_polled(parallel, count, |b| {
        let (bx, by, bz) = (b % nb, (b / nb) % nb, b / (nb * nb));
        let mut keys = Vec::new();
        for d in 0..8u8 {
            let (dx, dy, dz) = (usize::from(d & 1), usize::from((d >> 1) & 1), usize::from(d >> 2));
            if bx < dx || by < dy || bz < dz {
                continue;
            }
            keys.extend(refs[b - step(d)].iter().filter(|r| r.0 == d).map(|r| r.1));
        }
        keys.sort_unstable();
        keys.dedup();
        keys
    })?;
    let mut base = Vec::with_capacity(count + 1);
    let mut total = 0u32;
    for o in &owned {
        base.push(total);
        total += o.len() as u32;
    }
    if total == 0 {
        return Ok(Mesh::default());
    }
    let indices: Vec<u32> = map_range_polled(parallel, count, |b| {
        refs[b]
            .iter()
            .map(|&(d, k)| {
                let o = b + step(d);
                base[o] + owned[o].binary_search(&k).expect("every corner's edge is in its owner's list") as u32
            })
            .collect::<Vec<u32>>()
    })?
    .concat();
    let positions: Vec<Vec3> = map_range_polled(parallel, count, |b| {
        let origin = [(b % nb) * BLOCK, ((b / nb) % nb) * BLOCK, (b / (nb * nb)) * BLOCK];
        if owned[b].is_empty() {
            return Vec::new();
        }
        let field = (surface == Surface::Smooth).then(|| BlockField::new(img, iso, origin));
        owned[b]
            .iter()
            .map(|&k| {
                let (s, axis) = (usize::from(k) / 3, usize::from(k) % 3);
                let p = [origin[0] + s % BS, origin[1] + (s / BS) % BS, origin[2] + s / (BS * BS)];
                let t = match &field {
                    Some(f) => f.crossing(s, s + [1, BS, BS * BS][axis]),
                    None => {
                        let mut q = p;
                        q[axis] += 1;
                        let (va, vb) = (f64::from(img.padded(p)), f64::from(img.padded(q)));
                        (va - iso) / (va - vb)
                    }
                };
                let mut pos = Vec3::new(p[0] as f64 - 0.5, p[1] as f64 - 0.5, p[2] as f64 - 0.5);
                pos[axis] += t;
                map(pos)
            })
            .collect::<Vec<Vec3>>()
    })?
    .concat();
    let arities = vec![3u32; indices.len() / 3];
    Mesh::from_indexed_stoppable(positions, &indices, &arities).map_err(|e| match e {
        crate::mesh::MeshError::Limit(l) => VoxelError::Limit(l),
        e => VoxelError::Internal(format!("marching cubes produced an invalid mesh: {e}")),
    })
}

/// Marching cubes of a density image: the closed, manifold triangle mesh of
/// `{density > iso}` (iso in [0, 255); 127.5 puts the surface where coverage is one half), of the
/// densities themselves ([`Surface::Raw`]) or of their smoothed field ([`Surface::Smooth`]).
///
/// Inputs: `values` (side³, x fastest) with side ≥ 1. Output positions are in image coordinates
/// (voxel i spans [i, i+1), its sample at i + 0.5); the object is capped at the image border.
///
/// # Errors
/// [`VoxelError::InvalidArgument`] when `values.len()` ≠ side³ or for an iso level outside
/// [0, 255), [`VoxelError::NonFinite`] for a NaN iso level.
///
/// See also [`Voxels::to_mesh`](super::Voxels::to_mesh), which maps to world coordinates and
/// caches per level of detail.
pub fn marching_cubes(values: &[u8], side: usize, iso: f64, surface: Surface) -> Result<Mesh, VoxelError> {
    check_iso(iso)?;
    if side == 0 || side.checked_pow(3) != Some(values.len()) {
        return Err(VoxelError::InvalidArgument {
            what: "marching cubes image",
            reason: format!("{} values do not make a {side}³ image", values.len()),
        });
    }
    let img = Image { values, m: side };
    let nb = block_count(side);
    let blocks = map_range_checked(true, nb * nb * nb, CELLS_PER_BLOCK, |bi| {
        mesh_block(img, iso, [bi % nb, (bi / nb) % nb, bi / (nb * nb)], surface)
    })?;
    assemble(img, iso, surface, &blocks, |p| p, true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::SplitMix64;

    /// Seeded random bytes (the top byte of each number of the kernel's SplitMix64).
    fn random_bytes(len: usize, seed: u64) -> Vec<u8> {
        let mut rng = SplitMix64::new(seed);
        (0..len).map(|_| (rng.next_u64() >> 56) as u8).collect()
    }

    #[test]
    fn one_full_voxel_is_an_octahedron() {
        // A single inside sample: each of its 8 surrounding cells has one inside corner, one
        // triangle each, welded at the 6 edge midpoints (iso 127.5 halfway to 0 and 255).
        let m = Mesh::default();
        assert_eq!(m.face_count(), 0);
        let mesh = marching_cubes(&[255], 1, 127.5, Surface::Raw).unwrap();
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (6, 8));
        assert!(mesh.is_closed() && mesh.is_manifold());
        assert_eq!(mesh.genus(), 0);
        // Vertices at distance 0.5 along each axis from the sample at (0.5, 0.5, 0.5): the
        // octahedron of "radius" 0.5 has volume 4/3 · 0.5³ and faces outward.
        assert!((mesh.volume() - 4.0 / 3.0 * 0.125).abs() < 1e-12, "volume {}", mesh.volume());
    }

    #[test]
    fn random_noise_gives_closed_manifold_meshes() {
        // Noise exercises every case and every ambiguous face; each output must weld into a
        // closed 2-manifold with outward faces (positive volume). The smoothed field of noise
        // varies little about 127.5, so it is cut near there.
        for (side, seed) in [(4usize, 1u64), (7, 2), (9, 3), (20, 4), (33, 5)] {
            let values = random_bytes(side * side * side, seed);
            for (surface, isos) in [(Surface::Raw, [30.0, 127.5, 200.0]), (Surface::Smooth, [110.0, 127.5, 140.0])] {
                for iso in isos {
                    let mesh = marching_cubes(&values, side, iso, surface).unwrap();
                    let at = format!("{surface:?} side {side} iso {iso}");
                    assert!(mesh.face_count() > 0, "{at}");
                    assert!(mesh.is_closed(), "{at}");
                    assert!(mesh.is_manifold(), "{at}");
                    assert!(mesh.volume() > 0.0, "{at}: volume {}", mesh.volume());
                    // No smooth triangle of zero area (its crossings are kept off the samples; raw
                    // ones sit on a sample equal to an integer iso level).
                    if surface == Surface::Smooth {
                        assert!((0..mesh.face_count() as u32).all(|f| mesh.face_area(f) > 0.0), "{at}");
                    }
                }
            }
        }
    }

    #[test]
    fn samples_exactly_at_the_iso_level_still_give_closed_manifold_meshes() {
        // Densities 0–3 with integer iso levels: many samples equal the level (they count as
        // outside), so vertices land exactly on samples and coincide in space, yet stay distinct
        // edge vertices: the connectivity is still a closed 2-manifold.
        for (side, seed) in [(6usize, 7u64), (12, 8)] {
            let values: Vec<u8> = random_bytes(side * side * side, seed).iter().map(|v| v % 4).collect();
            for iso in [0.0, 1.0, 2.0] {
                let mesh = marching_cubes(&values, side, iso, Surface::Raw).unwrap();
                assert!(mesh.face_count() > 0 && mesh.is_closed() && mesh.is_manifold(), "side {side} iso {iso}");
            }
        }
    }

    #[test]
    fn checkerboard_separates_every_inside_voxel() {
        // Inside voxels touching only along edges or corners are separated by the face rule: a
        // 4³ checkerboard has 32 inside voxels and gives 32 octahedra (genus 0 each).
        let side = 4;
        let values: Vec<u8> = (0..64).map(|i| if (i % 4 + i / 4 % 4 + i / 16) % 2 == 0 { 255 } else { 0 }).collect();
        let mesh = marching_cubes(&values, side, 127.5, Surface::Raw).unwrap();
        assert!(mesh.is_closed() && mesh.is_manifold());
        assert_eq!(mesh.component_count(), 32);
        assert_eq!(mesh.genus(), 0);
    }

    #[test]
    fn bad_images_and_iso_levels_are_refused() {
        assert!(matches!(marching_cubes(&[0; 7], 2, 127.5, Surface::Raw), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(marching_cubes(&[0; 8], 2, f64::NAN, Surface::Raw), Err(VoxelError::NonFinite { .. })));
        assert!(matches!(marching_cubes(&[0; 8], 2, 255.0, Surface::Raw), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(marching_cubes(&[0; 8], 2, -1.0, Surface::Raw), Err(VoxelError::InvalidArgument { .. })));
        assert_eq!(marching_cubes(&[0; 8], 2, 0.0, Surface::Raw).unwrap().face_count(), 0);
    }
}
