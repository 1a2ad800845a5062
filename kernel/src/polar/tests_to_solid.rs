//! `to_solid` tests: the solid of a grown plant is closed, manifold, of the polar mesh's genus,
//! crosses itself nowhere (0 pairs, by the kernel's exact `diagnose::self_intersections` and by
//! Möller's test) and bounds the union of the tubes — the set
//! where the polar mesh's winding number is positive — measured independently by integrating
//! along lines; the polar mesh is unchanged.

use crate::lsystem::tests_grow::{growing_tree, thesis_plant, turtle_plant};
use crate::lsystem::tests_selfint::self_intersections;
use crate::lsystem::{grow, parse_modules, GrowOptions, Lsystem};
use crate::math::{Aabb, Vec3};
use crate::mesh::Mesh;
use crate::polar::to_solid::SolidPiece;
use crate::polar::PolarMesh;

/// Where lines parallel to x cross closed `m`: `n × n` lines through the yz-extent of `b`, at
/// cell centres offset by an irrational fraction so that none runs through an edge; per line,
/// the crossings sorted along it, each with the step of the winding number there (+1 entering
/// where the outward normal faces −x). Near-linear: each triangle is met only by the lines
/// through its own shadow on the yz-plane.
fn line_crossings(m: &Mesh, b: Aabb, n: usize) -> Vec<Vec<(f64, i32)>> {
    let (y0, z0) = (b.min.y, b.min.z);
    let (dy, dz) = ((b.max.y - y0) / n as f64, (b.max.z - z0) / n as f64);
    let mut lines: Vec<Vec<(f64, i32)>> = vec![Vec::new(); n * n];
    for f in 0..m.face_count() as u32 {
        for t in m.triangulate_face(f).unwrap() {
            let [a, b2, c] = t.map(|v| m.position(v));
            let nx = (b2 - a).cross(c - a).x;
            if nx == 0.0 {
                continue;
            }
            let (lo, hi) = (a.min(b2).min(c), a.max(b2).max(c));
            let j0 = (((lo.y - y0) / dy - JITTER).ceil().max(0.0)) as usize;
            let k0 = (((lo.z - z0) / dz - JITTER).ceil().max(0.0)) as usize;
            for j in j0..n {
                let y = y0 + (j as f64 + JITTER) * dy;
                if y > hi.y {
                    break;
                }
                for k in k0..n {
                    let z = z0 + (k as f64 + JITTER) * dz;
                    if z > hi.z {
                        break;
                    }
                    // Barycentric coordinates of (y, z) in the triangle's shadow.
                    let d = (b2.y - a.y) * (c.z - a.z) - (c.y - a.y) * (b2.z - a.z);
                    let u = ((y - a.y) * (c.z - a.z) - (c.y - a.y) * (z - a.z)) / d;
                    let v = ((b2.y - a.y) * (z - a.z) - (y - a.y) * (b2.z - a.z)) / d;
                    if u < 0.0 || v < 0.0 || u + v > 1.0 {
                        continue;
                    }
                    let x = a.x + u * (b2.x - a.x) + v * (c.x - a.x);
                    lines[j * n + k].push((x, if nx < 0.0 { 1 } else { -1 }));
                }
            }
        }
    }
    for l in &mut lines {
        l.sort_by(|p, q| p.0.total_cmp(&q.0));
    }
    lines
}

/// Where the lines sit in the yz-plane: the fraction of a cell from its corner.
const JITTER: f64 = 0.5 + 0.013_579_1;

/// How the solid's inside differs from the union of the tubes (the points where the polar
/// mesh's winding number is positive), integrated along `n × n` lines parallel to x (each
/// line's lengths exact between the crossings of both meshes): volumes `(missing, excess in
/// stand-ins, excess in everted pieces, excess elsewhere)` — of the union outside the solid, and
/// of the solid outside the union inside some stand-in of `pieces`, else inside some everted
/// piece (turned outwards, whose cones no longer cancel its neighbours'), or elsewhere (told by
/// the middle of each stretch).
fn compare_with_union(pm: &PolarMesh, solid: &Mesh, pieces: &[SolidPiece], n: usize) -> (f64, f64, f64, f64) {
    let b = solid.bounds().union(pm.mesh().bounds());
    let b = Aabb { min: b.min - 1e-3, max: b.max + 1e-3 };
    let (of_union, of_solid) = (line_crossings(pm.mesh(), b, n), line_crossings(solid, b, n));
    let (dy, dz) = ((b.max.y - b.min.y) / n as f64, (b.max.z - b.min.z) / n as f64);
    let of_kind = |kind: fn(&SolidPiece) -> bool| -> Vec<(&Mesh, Aabb)> {
        pieces.iter().filter(|p| kind(p)).map(|p| (&p.mesh, p.mesh.bounds())).collect()
    };
    let (stand_ins, everted) = (of_kind(|p| p.stand_in), of_kind(|p| p.everted));
    let (mut missing, mut in_stand_ins, mut in_everted, mut elsewhere) = (0.0, 0.0, 0.0, 0.0);
    for (i, (u, s)) in of_union.iter().zip(&of_solid).enumerate() {
        let (y, z) = (b.min.y + ((i / n) as f64 + JITTER) * dy, b.min.z + ((i % n) as f64 + JITTER) * dz);
        let mut xs: Vec<(f64, i32, i32)> =
            u.iter().map(|c| (c.0, c.1, 0)).chain(s.iter().map(|c| (c.0, 0, c.1))).collect();
        xs.sort_by(|p, q| p.0.total_cmp(&q.0));
        let (mut wu, mut ws) = (0, 0);
        for k in 0..xs.len() {
            wu += xs[k].1;
            ws += xs[k].2;
            let Some(next) = xs.get(k + 1) else { break };
            let volume = (next.0 - xs[k].0) * dy * dz;
            if wu >= 1 && ws < 1 {
                missing += volume;
            } else if ws >= 1 && wu < 1 {
                let p = Vec3::new(0.5 * (xs[k].0 + next.0), y, z);
                let inside = |(m, bb): &(&Mesh, Aabb)| bb.contains(p) && winding_at(m, p).abs() > 0.5;
                if stand_ins.iter().any(inside) {
                    in_stand_ins += volume;
                } else if everted.iter().any(inside) {
                    in_everted += volume;
                } else {
                    elsewhere += volume;
                }
            }
        }
    }
    (missing, in_stand_ins, in_everted, elsewhere)
}

/// The stated tolerance: by how much, as a fraction of its volume, a plant's solid may exceed
/// the union of its tubes inside the hulls standing in for regions whose loops fold.
const EXCESS: f64 = 0.05;
/// The same with wide gaps, whose branches' first loops fold more (measured over the release
/// sweep's 64 seeds: thesis plants at most 5.39 %, median 3.85 %; trees 4.12 %, 3.15 %; with
/// default gaps 3.77 %, 2.90 % and 2.49 %, 1.88 %).
const EXCESS_WIDE: f64 = 0.06;

/// Checks `pm.to_solid()` and returns `(crossing pairs of the polar mesh, triangles of the
/// solid)`.
/// With `exact`, also no pair by the kernel's exact test, which counts touching too (seeded
/// plants still show a few touching pairs there: thesis plant 0 has 13).
fn assert_solid(what: &str, pm: &PolarMesh, exact_test: bool, excess_bound: f64) -> (usize, usize) {
    let before = pm.clone();
    let solid = pm.to_solid().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(*pm, before, "{what}: the polar mesh is unchanged");
    assert!(solid.is_closed() && solid.is_manifold(), "{what}: closed and manifold");
    assert_eq!(solid.component_count(), 1, "{what}: one part");
    // The kernel's exact test (touching counts too), and Möller's of tests_grow.
    let crossings = crate::diagnose::self_intersections(&solid).unwrap();
    // The recipes' plants have no tunnels. Over many seeds, thin last branches that cross each
    // other or come out everted can enclose one (measured: thesis plant 3 with wide gaps, genus
    // 1), kept only when the union crosses itself nowhere.
    assert!(
        solid.genus() == 0 || (!exact_test && crossings.is_empty()),
        "{what}: genus {} with {} crossing pairs",
        solid.genus(),
        crossings.len()
    );
    assert!(self_intersections(&solid).is_empty(), "{what}: Möller pairs");
    assert!(
        !exact_test || crossings.is_empty(),
        "{what}: {} crossing pairs, first {:?}",
        crossings.len(),
        crossings.first()
    );
    // The solid bounds the union of the tubes, the set where the polar mesh's winding number is
    // positive, but for the regions whose own faces cross, which stand in as their convex hulls,
    // and for everted tubes, whose cones no longer cancel their neighbours' (see to_solid's
    // module doc): measured along the same lines through both, none of the union is missing,
    // the solid exceeds it inside those pieces only, inside the stand-ins by at most
    // `excess_bound` of its volume.
    let pieces = pm.solid_pieces(&mut |_, _| {}).unwrap();
    let (missing, in_stand_ins, in_everted, elsewhere) = compare_with_union(pm, &solid, &pieces, 48);
    let v = solid.volume();
    println!(
        "{what}: volume {v:.6}, of the union of the tubes missing {missing:.2e}; in excess: in stand-ins {:.2} %, in everted tubes {in_everted:.2e}, elsewhere {elsewhere:.2e}",
        100.0 * in_stand_ins / v
    );
    assert!(missing <= 1e-9 * v, "{what}: {missing} of the union of the tubes is outside the solid (volume {v})");
    // Elsewhere only where a cone pokes past its loop's centre (REACH) and out of the surface
    // where the loop is not convex about that centre (measured: at most 2.9e-5 of the volume,
    // thesis plants 7, 20 and 59 of the release sweep; else rounding, 1e-16).
    assert!(
        elsewhere <= 1e-4 * v,
        "{what}: the solid exceeds the union of the tubes by {elsewhere} outside the stand-ins"
    );
    assert!(
        in_stand_ins <= excess_bound * v,
        "{what}: the stand-ins exceed the union of the tubes by {in_stand_ins}, over {excess_bound} of the volume {v}"
    );
    assert!(in_everted <= 1e-3 * v, "{what}: the everted tubes' cones exceed the union of the tubes by {in_everted}");
    (self_intersections(pm.mesh()).len(), solid.face_count())
}

/// A polar mesh without branches is a solid already: its solid has the same volume.
#[test]
fn a_mesh_without_branches_is_its_own_solid() {
    let pm = PolarMesh::uv_sphere(1.0, 12, 8);
    assert_solid("sphere", &pm, true, 0.0);
    let v = pm.to_solid().unwrap().volume();
    assert!((v - pm.mesh().volume()).abs() < 1e-9 * v, "{v} against {}", pm.mesh().volume());
    let stem = grow(&parse_modules("t", "F F F").unwrap(), &GrowOptions::DEFAULT).unwrap().mesh;
    let v = stem.to_solid().unwrap().volume();
    assert!((v - stem.mesh().volume()).abs() < 1e-9 * v, "{v} against {}", stem.mesh().volume());
}

/// The recipes' plants (examples/lsystem_*.rhai, their grammars and options) cross
/// themselves at branch bases (tests_grow counts 513, 791 and 202 faces); their solids cross
/// nowhere.
#[test]
fn the_recipes_plants_become_solids_without_crossings() {
    let cases: [(&str, Lsystem, u32, GrowOptions); 3] = [
        ("shrub", thesis_plant(4), 10, GrowOptions::DEFAULT.with_angle(40.0).with_radius(0.2)),
        ("tree", growing_tree(2), 7, GrowOptions::DEFAULT.with_valence(10).with_angle(35.0)),
        (
            "turtle plant",
            turtle_plant(),
            5,
            GrowOptions::DEFAULT.with_valence(16).with_angle(25.7).with_radius(0.2).with_length(0.6),
        ),
    ];
    for (what, ls, steps, opts) in cases {
        let g = grow(&ls.derive(steps).unwrap(), &opts).unwrap();
        let (before, _) = assert_solid(what, &g.mesh, true, EXCESS);
        assert!(before > 0, "{what}: the polar mesh itself crosses");
    }
}

/// Over many seeds of the thesis's grammar and the growing tree.
#[test]
fn grown_plants_become_solids_over_many_seeds() {
    for seed in 0..6 {
        let g = grow(&thesis_plant(seed).derive(9).unwrap(), &GrowOptions::DEFAULT.with_angle(40.0).with_radius(0.2))
            .unwrap();
        assert_solid(&format!("thesis plant {seed}"), &g.mesh, false, EXCESS);
        let g = grow(&growing_tree(seed).derive(5).unwrap(), &GrowOptions::DEFAULT.with_valence(10).with_angle(35.0))
            .unwrap();
        assert_solid(&format!("tree {seed}"), &g.mesh, false, EXCESS);
    }
}

/// Many more seeds, with wide gaps (the most crossings); release only:
/// `cargo test --release -p blocksmith-kernel --lib to_solid -- --ignored`.
#[test]
#[ignore = "slow in debug; run in release"]
fn grown_plants_become_solids_over_many_more_seeds() {
    for seed in 0..64 {
        for wide in [false, true] {
            let opts = GrowOptions::DEFAULT.with_angle(40.0).with_radius(0.2).with_wide_gaps(wide);
            let g = grow(&thesis_plant(seed).derive(10).unwrap(), &opts).unwrap();
            assert_solid(
                &format!("thesis plant {seed} wide {wide}"),
                &g.mesh,
                false,
                if wide { EXCESS_WIDE } else { EXCESS },
            );
            let opts = GrowOptions::DEFAULT.with_valence(10).with_angle(35.0).with_wide_gaps(wide);
            let g = grow(&growing_tree(seed).derive(7).unwrap(), &opts).unwrap();
            assert_solid(&format!("tree {seed} wide {wide}"), &g.mesh, false, if wide { EXCESS_WIDE } else { EXCESS });
        }
    }
}

/// Two vertices at one point (a zero-length segment) are refused, naming the reason.
#[test]
fn a_zero_length_segment_is_refused() {
    let g = grow(&parse_modules("t", "F F F(0) F").unwrap(), &GrowOptions::DEFAULT.with_sigmoid(false)).unwrap();
    let e = g.mesh.to_solid().unwrap_err().to_string();
    assert!(e.contains("lie at one point"), "{e}");
}

/// The winding number of closed `m` at `p`: the solid angles of its triangles (Van Oosterom and
/// Strackee 1983) over 4π — 1 inside a positively oriented solid, 0 outside.
fn winding_at(m: &Mesh, p: crate::math::Vec3) -> f64 {
    let mut sum = 0.0;
    for f in 0..m.face_count() as u32 {
        for t in m.triangulate_face(f).unwrap() {
            let [a, b, c] = t.map(|v| m.position(v) - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let num = a.dot(b.cross(c));
            let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            sum += 2.0 * num.atan2(den);
        }
    }
    sum / (4.0 * std::f64::consts::PI)
}

/// Bracketed plants in one plane (`F[+F]F[-F]`, the first grammar of most L-system tutorials)
/// grow branches that cross each other, and sibling branches turned the same way at one node
/// (`[-F][-F…]` after two steps), whose second gap faces away from where it grows, so that the
/// branch runs through its parent and comes out everted (its tube bounds negative volume).
/// Their solids were refused (genus 194–295: the everted tubes subtracted instead of added);
/// now each tube faces outwards and the tunnels enclosed between crossing branches are kept:
/// every solid is closed, manifold, in one part, crosses itself nowhere (exact test), and holds
/// the middle of every segment of the plant (each branch is there).
#[test]
fn planar_bracketed_plants_with_crossing_and_coincident_branches_become_solids() {
    let cases: [(&str, u32, f64, u32); 6] = [
        ("F[+F]F[-F]", 3, 40.0, 12),
        ("F[+F]F[-F]", 3, 20.0, 12),
        ("F[+F][-F]F", 3, 25.7, 12),
        ("F[+F]F[-F]F", 2, 20.0, 8),
        ("FF-[-F+F+F]+[+F-F-F]", 2, 22.5, 16),
        ("F[&F][^F]F", 2, 30.0, 8),
    ];
    let mut tunnels = 0;
    for (rule, steps, angle, valence) in cases {
        let what = format!("{rule} at {steps} steps, {angle}°, valence {valence}");
        let ls = Lsystem::new("F", &[crate::lsystem::RuleSpec::deterministic("F", rule)], 0).unwrap();
        let pm = grow(&ls.derive(steps).unwrap(), &GrowOptions::DEFAULT.with_valence(valence).with_angle(angle))
            .unwrap()
            .mesh;
        let before = pm.clone();
        let solid = pm.to_solid().unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(pm, before, "{what}: the polar mesh is unchanged");
        assert!(solid.is_closed() && solid.is_manifold(), "{what}: closed and manifold");
        assert_eq!(solid.component_count(), 1, "{what}: one part");
        assert!(solid.volume() > 0.0, "{what}: positive volume");
        let crossings = crate::diagnose::self_intersections(&solid).unwrap();
        assert!(crossings.is_empty(), "{what}: {} crossing pairs", crossings.len());
        tunnels += solid.genus();
        // All of the union of the tubes is in the solid; the solid exceeds it in the everted
        // tubes (the polar mesh winds -1 there) and the stand-ins (where branches cross, up to
        // 27 % of the volume: 0.69 of 2.54 at 20°), else only where cones poke out (measured at
        // most 1.5e-4 of the volume).
        let pieces = pm.solid_pieces(&mut |_, _| {}).unwrap();
        let (missing, _, _, elsewhere) = compare_with_union(&pm, &solid, &pieces, 48);
        let v = solid.volume();
        assert!(missing <= 1e-9 * v, "{what}: {missing} of the union of the tubes is outside the solid");
        assert!(elsewhere <= 5e-4 * v, "{what}: {elsewhere} in excess outside the stand-ins and everted tubes");
        // Just inside each face of the polar mesh (on the side where its winding number is not
        // 0; an everted branch winds -1): inside the solid.
        let m = pm.mesh();
        let mut checked = 0;
        for f in 0..m.face_count() as u32 {
            let corners: Vec<_> = m.face_vertices(f).map(|v| m.position(v)).collect();
            let centre = corners.iter().copied().sum::<crate::math::Vec3>() / corners.len() as f64;
            let normal = (1..corners.len() - 1)
                .map(|k| (corners[k] - corners[0]).cross(corners[k + 1] - corners[0]))
                .sum::<crate::math::Vec3>();
            let step = normal.normalize() * 1e-3 * normal.length().sqrt();
            for p in [centre - step, centre + step] {
                if winding_at(m, p).abs() > 0.5 {
                    let w = winding_at(&solid, p);
                    assert!((w - 1.0).abs() < 1e-6, "{what}: a point just inside face {f} has winding number {w}");
                    checked += 1;
                }
            }
        }
        assert!(checked >= m.face_count() / 2, "{what}: {checked} points checked");
    }
    assert!(tunnels > 0, "some branches cross each other and enclose tunnels");
}

/// Colours ride on a grown plant's faces into its solid: the trunk's feature in one colour, the
/// rest in another, and every face of the solid in one of the two, each on the side of the plant
/// it came from (trunk faces low, the rest above).
#[test]
fn a_coloured_plant_keeps_its_colours_in_its_solid() {
    let (green, brown) = ([0.0, 0.5, 0.0, 1.0], [0.5, 0.25, 0.0, 1.0]);
    let mut pm = grow(&parse_modules("t", "F[+F][-F]F").unwrap(), &GrowOptions::DEFAULT).unwrap().mesh;
    pm.set_color(green).unwrap();
    let trunk = pm.select_feature(0).unwrap();
    pm.color_faces(&trunk, brown).unwrap();
    let solid = pm.to_solid().unwrap();
    assert!(solid.is_closed() && solid.is_manifold());
    let mut count = [0usize; 2];
    for f in 0..solid.face_count() as u32 {
        match solid.face_color(f) {
            Some(c) if c == green => count[0] += 1,
            Some(c) if c == brown => count[1] += 1,
            other => panic!("face {f} of the solid has colour {other:?}"),
        }
    }
    assert!(count[0] > 0 && count[1] > 0, "{count:?}");
    // The colours are written as they were set: the coloured mesh is the polar mesh's own.
    assert!(pm.to_colored_mesh().vertex_colors().is_none());
    assert!(pm.to_colored_mesh().has_face_colors());
    // Bad input leaves the polar mesh as it was.
    let before = pm.to_mesh();
    assert!(pm.set_color([f32::NAN, 0.0, 0.0, 1.0]).is_err());
    assert!(pm.color_faces(&[u32::MAX], green).is_err());
    assert_eq!(pm.to_mesh().face_part_ids(), before.face_part_ids());
}
