//! Seeded fuzz of whole layouts (issue #5: "a seeded fuzz of 500 random block layouts"): blocks
//! of random sizes placed against a random face of an earlier block with a random offset and a
//! small random gap, random sub-face grids, sharp tags, groups and allowed pairs, some blocks
//! turned about their contact normal and the whole layout turned at random. Every layout the
//! kernel accepts must tessellate to a closed, manifold triangle mesh with positive volume, the
//! control mesh's Euler characteristic and one source per triangle; a refusal must be a
//! [`BlockError::Topology`] (connections that pinch the surface). Each mesh is written to
//! `target/test-output/blocks_fuzz/NNN.obj`, where CI checks it again with trimesh (closed,
//! consistently wound, positive volume).
//!
//! The default run meshes 500 layouts (about 10 s in the optimised dev profile); set
//! `BLOCKS_FUZZ_CASES` for more.

use std::path::PathBuf;

use super::{Block, BlockError, BlockModel, Edge, Face, MeshOptions};
use crate::math::SplitMix64;
use crate::math::{Quat, Vec3};

fn uniform(rng: &mut SplitMix64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn below(rng: &mut SplitMix64, n: u64) -> u64 {
    rng.next_u64() % n
}

/// The axis-aligned bounds of a block's corners.
fn bounds(b: &Block) -> (Vec3, Vec3) {
    b.corners().iter().fold((Vec3::splat(f64::MAX), Vec3::splat(f64::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}

/// Whether two boxes overlap by more than `eps` on every axis.
fn overlap(a: (Vec3, Vec3), b: (Vec3, Vec3), eps: f64) -> bool {
    (0..3).all(|k| a.0[k] < b.1[k] - eps && b.0[k] < a.1[k] - eps)
}

/// One random layout of 1 to 8 blocks (see the module documentation).
fn layout(rng: &mut SplitMix64) -> BlockModel {
    let mut m = BlockModel::new();
    let groups = 1 + below(rng, 3) as i64;
    for g in 0..groups {
        for h in g..groups {
            if g == h || below(rng, 3) != 0 {
                m.allow(g, h);
            }
        }
    }
    let count = 1 + below(rng, 8);
    let mut placed: Vec<(Vec3, Vec3)> = Vec::new();
    let mut tries = 0;
    while (placed.len() as u64) < count && tries < 40 {
        tries += 1;
        let size = Vec3::new(uniform(rng, 0.4, 2.0), uniform(rng, 0.4, 2.0), uniform(rng, 0.4, 2.0));
        let (min, contact) = if placed.is_empty() {
            (Vec3::ZERO, None)
        } else {
            // Against face `f` of an earlier block, offset across it, a small gap along it.
            let (lo, hi) = placed[below(rng, placed.len() as u64) as usize];
            let f = Face::ALL[below(rng, 6) as usize];
            let a = f.axis();
            let gap = if below(rng, 3) == 0 { uniform(rng, 0.0, 0.05) } else { 0.0 };
            let mut min = Vec3::ZERO;
            for k in 0..3 {
                min[k] = if k == a {
                    if f.is_high() {
                        hi[k] + gap
                    } else {
                        lo[k] - gap - size[k]
                    }
                } else {
                    uniform(rng, lo[k] - 0.5 * size[k], hi[k] - 0.5 * size[k])
                };
            }
            let mut centre = min + size * 0.5;
            centre[a] = if f.is_high() { hi[a] } else { lo[a] };
            (min, Some((a, centre)))
        };
        let mut b = Block::from_bounds(min, min + size).expect("a positive size");
        let bb = bounds(&b);
        if placed.iter().any(|p| overlap(*p, bb, 1e-9)) {
            continue;
        }
        for f in Face::ALL {
            if below(rng, 3) == 0 {
                b.subdivide(f, 1 + below(rng, 3) as i64, 1 + below(rng, 3) as i64).expect("a small grid");
            }
        }
        for e in Edge::all() {
            b.set_sharp(e, below(rng, 3) == 0);
        }
        b.set_group(below(rng, groups as u64) as i64);
        // Now and then a small turn about the contact normal, through the contact point.
        if let Some((a, c)) = contact {
            if below(rng, 4) == 0 {
                let mut axis = Vec3::ZERO;
                axis[a] = 1.0;
                b.translate(-c).and_then(|()| b.rotate(axis, uniform(rng, -15.0, 15.0))).expect("finite");
                b.translate(c).expect("finite");
            }
        }
        placed.push(bounds(&b));
        m.add(b);
    }
    // The whole layout turned at random half of the time.
    if below(rng, 2) == 0 {
        let axis = Vec3::new(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
        let q =
            Quat::from_axis_angle(axis.try_normalize().unwrap_or(Vec3::Z), uniform(rng, 0.0, std::f64::consts::TAU));
        let mut turned = BlockModel::new();
        for g in 0..groups {
            for h in g..groups {
                if m.is_allowed(g, h) {
                    turned.allow(g, h);
                }
            }
        }
        for b in m.blocks() {
            let mut t = b.clone();
            t.set_corners(b.corners().map(|p| q * p)).expect("a rotation keeps a block valid");
            turned.add(t);
        }
        return turned;
    }
    m
}

#[test]
fn random_layouts_tessellate_closed_and_are_written_for_an_independent_check() {
    let wanted: usize = std::env::var("BLOCKS_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(500);
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/test-output/blocks_fuzz");
    std::fs::create_dir_all(&dir).unwrap();
    let mut rng = SplitMix64::new(0x0005_B10C_F022);
    let (mut built, mut refused, mut connected, mut cases) = (0usize, 0usize, 0usize, 0usize);
    while built < wanted {
        cases += 1;
        assert!(cases < 3 * wanted, "{refused} refusals in {cases} layouts");
        let m = layout(&mut rng);
        let cm = match m.control_mesh() {
            Ok(cm) => cm,
            Err(BlockError::Topology { .. }) => {
                refused += 1;
                continue;
            }
            Err(e) => panic!("layout {cases}: unexpected error {e}"),
        };
        if !m.connections().unwrap().is_empty() {
            connected += 1;
        }
        let tol = 0.02 * cm.mesh.bounds().size().length();
        let t = m
            .tessellate(&MeshOptions::DEFAULT.with_tolerance(tol).with_max_depth(3), None)
            .unwrap_or_else(|e| panic!("layout {cases}: {e}"));
        let mesh = &t.mesh;
        assert!(mesh.is_closed() && mesh.is_manifold() && mesh.is_triangle_mesh(), "layout {cases}");
        assert_eq!(mesh.euler(), cm.mesh.euler(), "layout {cases}");
        assert!(mesh.volume() > 0.0, "layout {cases}: volume {}", mesh.volume());
        assert_eq!(t.triangle_sources.len(), mesh.face_count(), "layout {cases}");
        let path = dir.join(format!("{built:03}.obj"));
        let mut out = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
        crate::io::obj::write_obj(mesh, &mut out).unwrap();
        built += 1;
    }
    eprintln!("blocks fuzz: {built} layouts meshed ({connected} with connections), {refused} refused");
    // Most layouts connect something, and refusals stay the exception.
    assert!(connected * 2 > built, "{connected} of {built} connected");
    assert!(refused * 4 < cases, "{refused} of {cases} refused");
}
