//! Property tests: seeded random sequences of the seven operations and the low-level moves keep
//! every chapter-3 invariant, closedness, manifoldness and the Euler characteristic each
//! operation implies; random invalid calls are refused with the mesh unchanged.
//!
//! `random_sequences_keep_every_invariant` runs 50 sequences of 50 operations;
//! `thousand_random_sequences_keep_every_invariant` runs the 1,000 (under a second in the
//! debug suite; `--nocapture` prints the tally of applied and refused operations).

use super::{Frame, PolarError, PolarMesh};
use crate::math::{SplitMix64, Vec3};

/// Counts of what a run did, to make sure the sequences exercise every operation.
#[derive(Default, Debug)]
struct Tally {
    ok: [usize; 8],
    refused: [usize; 8],
    /// Features bounded by two loops removed (χ + 2), the case the thesis could not handle.
    two_loop_removals: usize,
    /// Merges that joined two parts of one connected mesh (a handle: genus + 1).
    handles: usize,
}

const NAMES: [&str; 8] =
    ["add_refinement", "remove_refinement", "add_feature", "remove_feature", "merge", "split", "select", "move"];

fn assert_polar(pm: &PolarMesh, what: &str) {
    if let Err(e) = pm.check() {
        panic!("{what}: check failed: {e}");
    }
    assert!(pm.mesh().is_closed() && pm.mesh().is_manifold(), "{what}: not closed manifold");
}

fn random_loop_halfedge(pm: &PolarMesh, rng: &mut SplitMix64) -> Option<u32> {
    let n = pm.halfedge_count();
    (0..16).map(|_| rng.below(n) as u32).find(|&h| pm.is_loop(h))
}

/// One valid-looking random operation. Returns the op index and whether it succeeded; panics on
/// any broken invariant.
fn random_op(pm: &mut PolarMesh, rng: &mut SplitMix64, tally: &mut Tally) -> (usize, bool) {
    let big = pm.face_count() > 2500;
    let op = loop {
        let op = rng.below(8);
        if big && matches!(op, 0 | 2) {
            continue;
        }
        break op;
    };
    let before = pm.clone();
    let chi = pm.mesh().euler();
    let (result, delta): (Result<(), PolarError>, i64) = match op {
        0 => {
            let h = rng.below(pm.halfedge_count()) as i64;
            let t = 0.1 + 0.8 * rng.next_f64();
            let r = pm.add_refinement_at(h, t).map(|_| ());
            assert!(r.is_ok(), "add_refinement has no limitation (§4.1.4) but failed: {r:?}");
            (r, 0)
        }
        1 => (pm.remove_refinement(rng.below(pm.halfedge_count()) as i64), 0),
        2 => {
            let Some(h) = random_loop_halfedge(pm, rng) else { return (op, false) };
            let walk = pm.walk_of(h);
            let verts = pm.walk_vertices(&walk);
            let n = verts.len();
            if n < 4 {
                return (op, false);
            }
            let k = 3 + rng.below((n - 3).min(4));
            let s = rng.below(n);
            let run: Vec<u32> = (0..k).map(|i| verts[(s + i) % n]).collect();
            (pm.add_feature(&run).map(|_| ()), 0)
        }
        3 => {
            let f = rng.below(pm.face_count()) as u32;
            let has_pole = pm.feature_faces(f).iter().any(|&g| pm.mesh().face_vertices(g).any(|v| pm.is_pole(v)));
            (pm.remove_feature(i64::from(f)), if has_pole { 0 } else { 2 })
        }
        4 => {
            let poles = pm.poles();
            if poles.len() < 2 {
                return (op, false);
            }
            let p = poles[rng.below(poles.len())];
            let same: Vec<u32> = poles.iter().copied().filter(|&q| q != p && pm.valence(q) == pm.valence(p)).collect();
            let q = if same.is_empty() { poles[rng.below(poles.len())] } else { same[rng.below(same.len())] };
            (pm.merge_features(i64::from(p), i64::from(q)), -2)
        }
        5 => {
            let Some(h) = random_loop_halfedge(pm, rng) else { return (op, false) };
            (pm.split_feature(i64::from(h)).map(|_| ()), 2)
        }
        6 => {
            let f = rng.below(pm.face_count());
            let sel = pm.select_feature(f as i64).unwrap();
            let (ids, _) = pm.feature_ids();
            let want: Vec<u32> = (0..pm.face_count() as u32).filter(|&g| ids[g as usize] == ids[f]).collect();
            assert_eq!(sel, want, "select_feature disagrees with the global feature partition");
            (Ok(()), 0)
        }
        _ => {
            let k = 1 + rng.below(6);
            let verts: Vec<u32> = (0..k).map(|_| rng.below(pm.vertex_count()) as u32).collect();
            let d = Vec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5) * 0.1;
            let frame = if rng.below(2) == 0 { Frame::Global } else { Frame::Local };
            (pm.move_vertices(&verts, d, frame), 0)
        }
    };
    match result {
        Ok(()) => {
            assert_polar(pm, NAMES[op]);
            assert_eq!(pm.mesh().euler(), chi + delta, "{} changed χ by {}", NAMES[op], pm.mesh().euler() - chi);
            if op == 3 && delta == 2 {
                tally.two_loop_removals += 1;
            }
            if op == 4 && pm.mesh().genus() > before.mesh().genus() {
                tally.handles += 1;
            }
            (op, true)
        }
        Err(e) => {
            assert!(!matches!(e, PolarError::Internal(_)), "{}: internal error {e}", NAMES[op]);
            assert!(*pm == before, "{} refused ({e}) but changed the mesh", NAMES[op]);
            (op, false)
        }
    }
}

/// One random invalid call; it must be refused (or, rarely, succeed validly) and a refusal must
/// leave the mesh unchanged.
fn random_invalid_call(pm: &mut PolarMesh, rng: &mut SplitMix64) {
    let before = pm.clone();
    let nv = pm.vertex_count() as i64;
    let bad = |rng: &mut SplitMix64, n: i64| -> i64 {
        match rng.below(3) {
            0 => -1 - rng.below(5) as i64,
            1 => n + rng.below(5) as i64,
            _ => rng.below(n as usize) as i64,
        }
    };
    let chi = pm.mesh().euler();
    let r: Result<(), PolarError> = match rng.below(7) {
        0 => pm.add_refinement_at(bad(rng, 2 * nv), if rng.below(2) == 0 { f64::NAN } else { 1.5 }).map(|_| ()),
        1 => {
            let k = rng.below(6);
            let verts: Vec<u32> = (0..k).map(|_| bad(rng, nv).max(0) as u32).collect();
            pm.add_feature(&verts).map(|_| ())
        }
        2 => pm.merge_features(bad(rng, nv), bad(rng, nv)),
        3 => pm.split_feature(bad(rng, 2 * nv)).map(|_| ()),
        4 => pm.remove_feature(bad(rng, nv)),
        5 => pm.move_vertices(&[], Vec3::X, Frame::Global),
        _ => pm.scale_vertices(&[0], Vec3::splat(f64::INFINITY), None, Frame::Local),
    };
    match r {
        Ok(()) => {
            // A random call that happened to be valid must still leave a valid mesh.
            assert_polar(pm, "random call");
            let d = pm.mesh().euler() - chi;
            assert!(d == 0 || d == 2 || d == -2, "random call changed χ by {d}");
        }
        Err(e) => {
            assert!(!matches!(e, PolarError::Internal(_)), "internal error {e}");
            assert!(*pm == before, "refused ({e}) but changed the mesh");
        }
    }
}

fn run_sequences(count: u64, ops: usize) -> Tally {
    let mut tally = Tally::default();
    for seed in 0..count {
        let mut rng = SplitMix64::new(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x1234_5678);
        let mut pm = if seed % 2 == 0 { PolarMesh::octahedron() } else { PolarMesh::uv_sphere(1.0, 6, 5) };
        for _ in 0..ops {
            if rng.below(4) == 0 {
                random_invalid_call(&mut pm, &mut rng);
            } else {
                let (op, ok) = random_op(&mut pm, &mut rng, &mut tally);
                if ok {
                    tally.ok[op] += 1;
                } else {
                    tally.refused[op] += 1;
                }
            }
        }
    }
    tally
}

#[test]
fn random_sequences_keep_every_invariant() {
    let tally = run_sequences(50, 50);
    // Every kind of operation must have succeeded at least once, so the test means something.
    for (i, name) in NAMES.iter().enumerate() {
        assert!(tally.ok[i] > 0, "{name} never succeeded: {tally:?}");
    }
}

#[test]
fn thousand_random_sequences_keep_every_invariant() {
    let tally = run_sequences(1000, 50);
    for (i, name) in NAMES.iter().enumerate() {
        assert!(tally.ok[i] > 0, "{name} never succeeded: {tally:?}");
    }
    assert!(tally.two_loop_removals > 0 && tally.handles > 0, "{tally:?}");
    eprintln!("{tally:?}");
}
