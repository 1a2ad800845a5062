//! A seeded fuzz of 1,000 random boolean trees of boxes, spheres and block groups: coordinates
//! on a coarse grid so that coplanar faces, shared edges, touching and identical operands are
//! common. Every result must be closed and manifold (or empty), with a source on every face, and
//! no evaluation may panic. Small meshes keep it a few seconds in debug.

use blocksmith_kernel::blocks::{Block, BlockModel, MeshOptions};
use blocksmith_kernel::csg::Csg;
use blocksmith_kernel::math::SplitMix64;
use blocksmith_kernel::{Mesh, Vec3};

/// A coordinate on the grid of quarters in [-1, 1].
fn grid(rng: &mut SplitMix64) -> f64 {
    (rng.next_u64() % 9) as f64 * 0.25 - 1.0
}

fn corner_pair(rng: &mut SplitMix64) -> (Vec3, Vec3) {
    loop {
        let a = Vec3::new(grid(rng), grid(rng), grid(rng));
        let b = Vec3::new(grid(rng), grid(rng), grid(rng));
        let (lo, hi) = (a.min(b), a.max(b));
        if (hi - lo).min_element() > 0.0 {
            return (lo, hi);
        }
    }
}

fn leaf(rng: &mut SplitMix64) -> Csg {
    match rng.next_u64() % 10 {
        0..=4 => {
            let (lo, hi) = corner_pair(rng);
            Csg::mesh(Mesh::cuboid(lo, hi))
        }
        5..=7 => {
            let r = 0.25 * (1 + rng.next_u64() % 3) as f64;
            let c = Vec3::new(grid(rng), grid(rng), grid(rng));
            Csg::mesh(Mesh::icosphere(r, 1).translate(c))
        }
        _ => {
            // A group of one or two blocks, sharp or smooth, meshed coarsely.
            let mut model = BlockModel::new();
            model.allow(0, 0);
            for _ in 0..1 + rng.next_u64() % 2 {
                let (lo, hi) = corner_pair(rng);
                let mut b = Block::from_bounds(lo, hi).unwrap();
                if rng.next_u64().is_multiple_of(2) {
                    b.sharp_all();
                } else {
                    b.smooth_all();
                }
                model.add(b);
            }
            Csg::blocks(model, MeshOptions::DEFAULT.with_tolerance(0.05).with_max_depth(2))
        }
    }
}

fn tree(rng: &mut SplitMix64, depth: u32) -> Csg {
    if depth == 0 || rng.next_u64().is_multiple_of(3) {
        return leaf(rng);
    }
    let a = tree(rng, depth - 1);
    // Identical operands now and then.
    let b = if rng.next_u64().is_multiple_of(8) { a.clone() } else { tree(rng, depth - 1) };
    match rng.next_u64() % 3 {
        0 => a.union(b),
        1 => a.difference(b),
        _ => a.intersection(b),
    }
}

/// The volume a shell of `m` (triangles) bounds.
fn shell_volume(m: &Mesh, faces: &[u32]) -> f64 {
    faces
        .iter()
        .map(|&f| {
            let v: Vec<Vec3> = m.face_vertices(f).map(|v| m.position(v)).collect();
            v[0].dot(v[1].cross(v[2])) / 6.0
        })
        .sum()
}

#[test]
fn random_boolean_trees_are_closed_and_manifold() {
    let mut rng = SplitMix64::new(0x5eed_c5a6);
    let (mut empty, mut slivers, mut refused) = (0, 0, Vec::new());
    for i in 0..1000 {
        let t = tree(&mut rng, 3);
        let r = std::panic::catch_unwind(|| t.evaluate());
        let m = match r {
            Err(_) => panic!("tree {i} panicked"),
            Ok(Err(e)) => {
                // Only a block group the blocks engine cannot mesh may be refused.
                refused.push(format!("tree {i}: {e}"));
                continue;
            }
            Ok(Ok(m)) => m,
        };
        if m.face_count() == 0 {
            empty += 1;
            continue;
        }
        assert!(m.is_closed() && m.is_manifold(), "tree {i}: not closed and manifold");
        // Regularised: solids that only touch leave no flat shell; every shell bounds volume
        // (negative for a cavity).
        for shell in m.face_components() {
            let volume = shell_volume(&m, &shell);
            if volume.abs() < 1e-9 {
                slivers += 1;
                eprintln!("tree {i}: a shell of {} faces, volume {volume:e}", shell.len());
            }
        }
        let s = m.face_sources().unwrap();
        assert!(s.len() == m.face_count() && s.iter().all(|s| s.leaf().is_some()), "tree {i}: sources");
    }
    assert!(refused.iter().all(|e| e.contains("could not be meshed")), "{refused:#?}");
    assert!(refused.len() < 50, "{} of 1000 refused", refused.len());
    // The grid makes empty results (touching, disjoint, a − a) common but not the rule.
    assert!((50..700).contains(&empty), "{empty} empty results");
    assert_eq!(slivers, 0, "flat shells");
    println!("1000 trees: {empty} empty, {slivers} slivers, {} refused", refused.len());
}
