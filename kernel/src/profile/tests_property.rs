//! Property tests: random (often self-intersecting) polygons through repair, booleans,
//! offsets, extrusion, revolution and sweeps — every result clean, every solid closed and
//! manifold with the volume geometry gives, never a panic. The kernel's seeded SplitMix64
//! keeps runs repeatable.

use super::tests::assert_near;
use super::*;
use crate::math::Vec3;

use crate::math::SplitMix64 as Rng;

/// Uniform in [lo, hi).
fn range(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.next_f64()
}

/// A random polygon: `n` points in [−10, 10]², most of them self-intersecting.
fn random_polygon(rng: &mut Rng) -> Vec<Vec2> {
    let n = 3 + (rng.next_u64() % 30) as usize;
    (0..n).map(|_| Vec2::new(range(rng, -10.0, 10.0), range(rng, -10.0, 10.0))).collect()
}

/// ∫ x dA over the region.
fn first_moment_x(p: &Profile) -> f64 {
    p.centroid().map_or(0.0, |c| c.x * p.area())
}

#[track_caller]
fn check_clean(p: &Profile) {
    for c in p.contours() {
        assert!(c.len() >= 3 && c.iter().all(|q| q.is_finite()), "{c:?}");
    }
    if !p.is_empty() {
        assert!(p.area() > 0.0, "area {}", p.area());
        assert!((0..p.contours().len()).any(|i| !p.is_hole(i)), "no outer contour");
    }
}

#[test]
fn random_polygons_repair_to_clean_regions_that_extrude_and_revolve_exactly() {
    let mut rng = Rng::new(0x1234_5678_9abc_def1);
    let mut solids = 0;
    for round in 0..150 {
        let rule = if round % 2 == 0 { FillRule::EvenOdd } else { FillRule::NonZero };
        let p = match Profile::polygon(&random_polygon(&mut rng), rule) {
            Ok(p) => p,
            Err(ProfileError::ZeroArea { .. }) => continue,
            Err(e) => panic!("{e}"),
        };
        check_clean(&p);
        // Extruded straight: area × height (the contours go into the engine as they are).
        let m = extrude(&p, 1.5, &ExtrudeOptions::DEFAULT).unwrap();
        assert!(m.is_closed() && m.is_manifold(), "round {round}");
        assert_near(m.volume(), 1.5 * p.area(), 1e-9 * p.area().max(1.0));
        // Moved to x ≥ 1 and revolved in 24 steps: 24·sin(2π/24)·∫x dA (Pappus, polygonal).
        let (lo, _) = p.bounds().unwrap();
        let q = p.translate(Vec2::new(1.0 - lo.x, 0.0)).unwrap();
        let r = revolve(&q, &RevolveOptions::DEFAULT.with_segments(24)).unwrap();
        assert!(r.is_closed() && r.is_manifold(), "round {round}");
        let expected = 24.0 * (std::f64::consts::TAU / 24.0).sin() * first_moment_x(&q);
        assert_near(r.volume(), expected, 1e-9 * expected.abs().max(1.0));
        solids += 1;
    }
    assert!(solids > 50, "only {solids} random polygons enclosed area");
}

#[test]
fn random_booleans_obey_inclusion_exclusion_and_offsets_stay_clean() {
    let mut rng = Rng::new(0x0fed_cba9_8765_4321);
    for _ in 0..100 {
        let (Ok(a), Ok(b)) = (
            Profile::polygon(&random_polygon(&mut rng), FillRule::NonZero),
            Profile::polygon(&random_polygon(&mut rng), FillRule::EvenOdd),
        ) else {
            continue;
        };
        let (u, i, d) = (a.union(&b), a.intersection(&b), a.difference(&b));
        for p in [&u, &i, &d] {
            check_clean(p);
        }
        // |a ∪ b| + |a ∩ b| = |a| + |b| and |a − b| = |a| − |a ∩ b|, up to the 1e-8 grid.
        let tol = 1e-6 * (a.area() + b.area());
        assert_near(u.area() + i.area(), a.area() + b.area(), tol);
        assert_near(d.area(), a.area() - i.area(), tol);
        let delta = range(&mut rng, -2.0, 2.0);
        let join = [JoinType::Round, JoinType::Miter, JoinType::Square][(rng.next_u64() % 3) as usize];
        let o = a.offset(delta, &OffsetOptions::DEFAULT.with_join(join)).unwrap();
        check_clean(&o);
        if delta > 0.0 {
            assert!(o.area() >= a.area(), "growing shrank: {} < {}", o.area(), a.area());
        } else {
            assert!(o.area() <= a.area(), "shrinking grew");
        }
        check_clean(&a.fillet(range(&mut rng, 0.0, 1.0), 16).unwrap());
        check_clean(&a.chamfer(range(&mut rng, 0.0, 1.0)).unwrap());
        check_clean(&a.hull().unwrap());
        check_clean(&a.simplify(range(&mut rng, 0.0, 0.5)).unwrap());
    }
}

#[test]
fn random_sweeps_are_closed_solids_or_refused_by_name() {
    let mut rng = Rng::new(0x5555_aaaa_1234_4321);
    let (mut built, mut refused, mut crossing) = (0, 0, 0);
    for _ in 0..80 {
        let Ok(p) = Profile::polygon(&random_polygon(&mut rng), FillRule::EvenOdd) else { continue };
        let p = p.scale(Vec2::splat(0.05)).unwrap();
        let n = 2 + (rng.next_u64() % 8) as usize;
        let path: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(range(&mut rng, -3.0, 3.0), range(&mut rng, -3.0, 3.0), range(&mut rng, -3.0, 3.0)))
            .collect();
        let closed = n >= 3 && rng.next_u64().is_multiple_of(3);
        match sweep(&p, &path, &SweepOptions::DEFAULT.with_closed(closed)) {
            Ok(m) => {
                assert!(m.is_closed() && m.is_manifold());
                // Each hole is a handle; on a closed path each outer contour's tube is a ring too.
                let holes = (0..p.contours().len()).filter(|&i| p.is_hole(i)).count() as i64;
                let outers = p.contours().len() as i64 - holes;
                assert_eq!(m.genus(), holes + if closed { outers } else { 0 });
                built += 1;
            }
            Err(ProfileError::SharpTurn { index, .. }) => {
                assert!(index < n);
                refused += 1;
            }
            // A random path often comes back through its own tube: refused, naming the point.
            Err(e @ ProfileError::SelfCrossing { .. }) => {
                let ProfileError::SelfCrossing { near, .. } = &e else { unreachable!() };
                let index: usize = near.strip_prefix("path point ").and_then(|i| i.parse().ok()).expect("a point");
                assert!(index < n, "{e}");
                crossing += 1;
            }
            Err(e) => panic!("{e}"),
        }
    }
    assert!(built > 10 && refused > 0 && crossing > 0, "built {built}, refused {refused}, crossing {crossing}");
}
