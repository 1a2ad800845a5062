//! Growth tests: every grown mesh is a valid polar mesh (closed, manifold, genus 0) whose
//! skeleton has one node per drawn module (§11.1, §7.1) and one leaf per branch end.

use super::*;
use crate::math::Vec3;
use crate::polar::PolarMesh;

fn modules(s: &str) -> Vec<Module> {
    parse_modules("test", s).unwrap()
}

/// Checks the polar invariants, the topology and the skeleton counts of a grown plant.
fn assert_plant(g: &Grown) {
    let pm: &PolarMesh = &g.mesh;
    pm.check().unwrap();
    let m = pm.mesh();
    assert!(m.is_closed() && m.is_manifold());
    assert_eq!(m.euler(), 2, "genus 0");
    let sk = pm.skeleton(Some(g.root)).unwrap();
    // One node for the root pole, one per drawn module, one per tip pole not drawn by `P`.
    assert_eq!(sk.node_count(), 1 + g.segments + g.open_ends, "nodes");
    assert_eq!(sk.cycle_count(), 0);
    let leaves = (0..sk.node_count() as u32).filter(|&n| sk.children(n).is_empty()).count();
    assert_eq!(leaves, g.branches, "one leaf per branch end");
    assert!(m.volume() > 0.0, "outward faces");
}

#[test]
fn a_straight_stem_is_a_chain_of_loops_between_two_poles() {
    let opts = GrowOptions::DEFAULT.with_sigmoid(false);
    let g = grow(&modules("F F F"), &opts).unwrap();
    assert_plant(&g);
    assert_eq!((g.segments, g.branches, g.open_ends, g.features), (3, 1, 1, 0));
    // 3 loops of 8 and 2 poles.
    assert_eq!(g.mesh.vertex_count(), 26);
    // The loops are circles of radius 0.25 at heights 1, 2, 3 (the turtle heads up +z).
    let sk = g.mesh.skeleton(Some(g.root)).unwrap();
    let mut heights: Vec<f64> =
        (0..sk.node_count() as u32).filter(|&n| !sk.is_pole(n)).map(|n| sk.position(n).z).collect();
    heights.sort_by(f64::total_cmp);
    for (z, want) in heights.iter().zip([1.0, 2.0, 3.0]) {
        assert!((z - want).abs() < 1e-12, "loop at z {z}, want {want}, off by {}", z - want);
    }
    for v in 0..g.mesh.vertex_count() as u32 {
        if !g.mesh.is_pole(v) {
            let p = g.mesh.position(v);
            let r = (p.x * p.x + p.y * p.y).sqrt();
            assert!((r - 0.25).abs() < 1e-12, "vertex {v} at radius {r}");
        }
    }
}

#[test]
fn turtle_branches_nest_features_on_the_current_loop() {
    let g = grow(&modules("F[+F][-F]F"), &GrowOptions::DEFAULT).unwrap();
    assert_plant(&g);
    assert_eq!((g.segments, g.branches, g.open_ends, g.features), (4, 3, 3, 2));
    // Two branches share the loop of 8: runs of 4 vertices each, poles of valence 2(4 − 1) = 6.
    let mut valences: Vec<usize> = g.mesh.poles().iter().map(|&p| g.mesh.valence(p)).collect();
    valences.sort_unstable();
    assert_eq!(valences, [6, 6, 8, 8]);
    // A lone branch keeps the valence: a run of 5 of the 8 vertices.
    let g = grow(&modules("F[+F]F"), &GrowOptions::DEFAULT).unwrap();
    let mut valences: Vec<usize> = g.mesh.poles().iter().map(|&p| g.mesh.valence(p)).collect();
    valences.sort_unstable();
    assert_eq!(valences, [8, 8, 8]);
}

#[test]
fn a_branch_opens_where_the_turtle_points() {
    // `+(90)` turns the heading from +z to +x (the turtle's left): the branch's tip lies on the
    // +x side; `-(90)` on the −x side.
    for (s, sign) in [("F[+(90)F]", 1.0), ("F[-(90)F]", -1.0)] {
        let g = grow(&modules(s), &GrowOptions::DEFAULT.with_sigmoid(false)).unwrap();
        assert_plant(&g);
        let tips: Vec<Vec3> = g.mesh.poles().iter().map(|&p| g.mesh.position(p)).collect();
        let side = tips.iter().map(|p| p.x * sign).fold(f64::MIN, f64::max);
        assert!(side > 1.0, "{s}: tips {tips:?}");
        // The gap's centroid faces +x too: every vertex of the branch's first loop is beyond the
        // trunk's surface.
        let far = (0..g.mesh.vertex_count() as u32).filter(|&v| g.mesh.position(v).x * sign > 0.5).count();
        assert!(far >= 8, "{s}: {far} vertices on the branch side");
    }
}

#[test]
fn the_thesis_symbols_draw_loops_poles_and_side_branches() {
    // One application of L0 → [L L0 L P][R L0 L P] to "L L0 P" (§11, both branches).
    let s = "L(0) [L L0(1) L(1) P(1)] [R L0(1) L(1) P(1)] P(0)";
    let g = grow(&modules(s), &GrowOptions::DEFAULT).unwrap();
    assert_plant(&g);
    // Drawn: L, [L, L0, L, P, [R, L0, L, P, P = 10; every branch ended by P.
    assert_eq!((g.segments, g.branches, g.open_ends, g.features), (10, 3, 0, 2));
}

#[test]
fn the_fig_12_2_grammar_doubles_its_branches_every_step() {
    let rules = [RuleSpec::deterministic("L0(s)", "[L(s) L0(s+1) L(s+1) P(s+1)][R(s) L0(s+1) L(s+1) P(s+1)]")];
    let ls = Lsystem::new("L(0) L0(0) P(0)", &rules, 1).unwrap();
    for steps in 0..5 {
        let g = grow(&ls.derive(steps).unwrap(), &GrowOptions::DEFAULT).unwrap();
        assert_plant(&g);
        // 2 + 4 + … + 2^steps nested branches.
        assert_eq!(g.features, (1 << (steps + 1)) - 2, "steps {steps}");
    }
}

/// With wide gaps every branch keeps its parent's valence, as in the thesis (§4.3.1: a run of
/// valence/2 + 1 vertices gives a pole of the same valence), so the Fig. 12.2 case grows to the
/// thesis's size: every tip pole has the trunk's valence 32. By default runs that cannot be
/// slid span at most 135° and valences fall with depth (tip poles of 24 and fewer). Both are
/// valid plants.
#[test]
fn wide_gaps_keep_every_branch_at_the_trunk_valence() {
    let rules = [RuleSpec::deterministic("L0(s)", "[L(s) L0(s+1) L(s+1) P(s+1)][R(s) L0(s+1) L(s+1) P(s+1)]")];
    let s = Lsystem::new("L(0) L0(0) P(0)", &rules, 0).unwrap().derive(4).unwrap();
    let tip_valences = |wide: bool| {
        let g = grow(&s, &GrowOptions::DEFAULT.with_valence(32).with_wide_gaps(wide)).unwrap();
        assert_plant(&g);
        let pm = &g.mesh;
        let mut v: Vec<usize> = pm.poles().into_iter().filter(|&p| p != g.root).map(|p| pm.valence(p)).collect();
        v.sort_unstable();
        (v, pm.vertex_count())
    };
    let (wide, wide_count) = tip_valences(true);
    let (narrow, narrow_count) = tip_valences(false);
    assert_eq!(wide.len(), 31, "31 branch ends");
    assert!(wide.iter().all(|&x| x == 32), "wide gaps: tip valences {wide:?}");
    assert!(narrow[0] <= 24, "default gaps: tip valences {narrow:?}");
    assert!(wide_count > narrow_count, "{wide_count} vertices with wide gaps, {narrow_count} without");
}

#[test]
fn runaway_growth_stops_at_the_caps_saying_what_was_reached() {
    let s = modules("F[+F][-F]F[+F]F");
    let e = grow(&s, &GrowOptions::DEFAULT.with_caps(20, 100)).unwrap_err();
    assert!(matches!(e, LsystemError::GrowthCap { cap_name: "max_vertices", cap: 20, .. }), "{e}");
    assert!(e.to_string().contains("the vertex count reached"), "{e}");
    let e = grow(&s, &GrowOptions::DEFAULT.with_caps(1000, 1)).unwrap_err();
    assert!(e.to_string().contains("the number of nested branches reached 1"), "{e}");
    assert!(e.to_string().contains("max_features = 1"), "{e}");
}

#[test]
fn bad_strings_are_refused() {
    assert!(matches!(grow(&modules("+-A"), &GrowOptions::DEFAULT), Err(LsystemError::NothingDrawn)));
    let e = grow(&modules("F P F"), &GrowOptions::DEFAULT).unwrap_err();
    assert!(matches!(e, LsystemError::DrawAfterPole { module: 2, ended: 1, .. }), "{e}");
    let e = grow(&modules("F]"), &GrowOptions::DEFAULT).unwrap_err();
    assert!(matches!(e, LsystemError::UnbalancedBrackets { .. }), "{e}");
    // Three branches on one loop of 8 need three runs of at least 3 vertices: 9 > 8.
    let e = grow(&modules("F[+F][-F][&F]"), &GrowOptions::DEFAULT).unwrap_err();
    assert!(matches!(e, LsystemError::NoRoomForBranch { valence: 8, works: Some(_), .. }), "{e}");
    let e = grow(&modules("F"), &GrowOptions::DEFAULT.with_valence(4)).unwrap_err();
    assert!(matches!(e, LsystemError::InvalidOption(_)), "{e}");
    // NaN and huge sizes are refused with what was wrong, never grown into non-finite positions.
    for (opts, want) in [
        (GrowOptions::DEFAULT.with_radius(f64::NAN), "radius must be a positive number up to 1e100, got NaN"),
        (GrowOptions::DEFAULT.with_length(1e200), "length must be a positive number up to 1e100, got 1000"),
        (GrowOptions::DEFAULT.with_angle(f64::INFINITY), "angle and divergence must be finite"),
    ] {
        let e = grow(&modules("F[+F]F"), &opts).unwrap_err();
        assert!(e.to_string().contains(want), "{e}");
    }
    let e = grow(&modules("F F(1e200)"), &GrowOptions::DEFAULT).unwrap_err();
    assert!(e.to_string().contains("`F(1e200)`: length 1e200 and radius"), "{e}");
    assert!(e.to_string().contains("must be at most 1e100 (positions would overflow)"), "{e}");
}

#[test]
fn three_d_turtle_symbols_grow_a_valid_plant() {
    // ABOP Fig. 1.25-like bush: pitch, rolls, three branches per loop. Three siblings share a
    // loop of n vertices with runs of n/3, so valences fall 24 → 14 → 6 with depth.
    let rules = [RuleSpec::deterministic("A", "[&FA]/////[&FA]///////[&FA]"), RuleSpec::deterministic("F", "S/////F")];
    let ls = Lsystem::new("FA", &rules, 0).unwrap();
    let g = grow(&ls.derive(2).unwrap(), &GrowOptions::DEFAULT.with_valence(24).with_angle(22.5)).unwrap();
    assert_plant(&g);
    assert_eq!(g.features, 3 + 9);
    let mut valences: Vec<usize> = g.mesh.poles().iter().map(|&p| g.mesh.valence(p)).collect();
    valences.sort_unstable();
    valences.dedup();
    assert_eq!(valences, [6, 14, 24]);
}

/// Faces that fold: any face that does not triangulate in its own plane (a self-crossing
/// polygon, as the glTF writer refuses), any quad whose two triangulations disagree on its normal
/// (a quad folded along a diagonal) or whose corners stand off its best-fit plane by more than a
/// quarter of its longer diagonal (a twisted quad). Returns (face, why) for the first few.
fn folded_faces(m: &crate::mesh::Mesh) -> Vec<(u32, String)> {
    let mut bad = Vec::new();
    for f in 0..m.face_count() as u32 {
        if let Err(e) = m.triangulate_face(f) {
            bad.push((f, e.to_string()));
            continue;
        }
        let p: Vec<Vec3> = m.face_vertices(f).map(|v| m.position(v)).collect();
        if p.len() != 4 {
            continue;
        }
        let tri = |a: usize, b: usize, c: usize| (p[b] - p[a]).cross(p[c] - p[a]).normalize_or_zero();
        let agree = tri(0, 1, 2).dot(tri(0, 2, 3)).min(tri(1, 2, 3).dot(tri(1, 3, 0)));
        if agree <= 0.0 {
            bad.push((f, format!("folded along a diagonal (triangle normals at cosine {agree:.3})")));
        }
        let n = m.face_vector_area(f).normalize_or_zero();
        let c = (p[0] + p[1] + p[2] + p[3]) / 4.0;
        let diag = p[0].distance(p[2]).max(p[1].distance(p[3]));
        let off = p.iter().map(|q| (*q - c).dot(n).abs()).fold(0.0, f64::max);
        if off > 0.25 * diag {
            bad.push((f, format!("twisted: a corner {off:.3e} off its plane, diagonal {diag:.3e}")));
        }
    }
    bad
}

fn assert_unfolded(what: &str, m: &crate::mesh::Mesh) {
    let bad = folded_faces(m);
    assert!(
        bad.is_empty(),
        "{what}: {} folded faces of {}, first {:?}",
        bad.len(),
        m.face_count(),
        &bad[..bad.len().min(3)]
    );
}

/// The thesis's stochastic grammar of §11 (as stdlib/plants.rhai writes it).
pub(crate) fn thesis_plant(seed: u64) -> Lsystem {
    let pr = "(1 - 1/(1 + exp(5.2 - s)))";
    let (left, right) = ("[L(s) L0(s+1) L(s+1) P(s+1)]", "[R(s) L0(s+1) L(s+1) P(s+1)]");
    let c = |to: String, p: String| ChoiceSpec { to, p: Probability::Expression(p) };
    let choices = vec![
        c(left.into(), format!("{pr} - {pr}^2")),
        c(right.into(), format!("{pr} - {pr}^2")),
        c(format!("{left}{right}"), format!("{pr}^2")),
        c("L(s)".into(), format!("1 - 2*{pr} + {pr}^2")),
    ];
    Lsystem::new("L(0) L0(0) P(0)", &[RuleSpec { key: "L0(s)".into(), choices }], seed).unwrap()
}

/// A tree whose apex grows on after it branches (examples/lsystem_tree.rhai).
pub(crate) fn growing_tree(seed: u64) -> Lsystem {
    let pr = "(1 - 1/(1 + exp(4.5 - s)))";
    let c = |to: &str, p: String| ChoiceSpec { to: to.into(), p: Probability::Expression(p) };
    let choices = vec![c("L(s) [L(s) A(s+1)] [R(s) A(s+1)] A(s+1)", pr.into()), c("L(s) P(s)", format!("1 - {pr}"))];
    Lsystem::new("A(0)", &[RuleSpec { key: "A(s)".into(), choices }], seed).unwrap()
}

/// The turtle plant's bracketed grammar (examples/lsystem_turtle_plant.rhai).
pub(crate) fn turtle_plant() -> Lsystem {
    Lsystem::new("X", &[RuleSpec::deterministic("X", "F[&+X]/[&-X]///FX"), RuleSpec::deterministic("F", "FF")], 0)
        .unwrap()
}

/// Branches nested on branches, many levels deep, over many seeds: every face triangulates in
/// its own plane, no quad folds or twists, and every plant is a valid polar mesh with its
/// skeleton counts (the recipes' grammars with the recipes' options).
#[test]
fn nested_branches_have_no_folded_faces_across_seeds() {
    for seed in 0..16 {
        let g = grow(
            &thesis_plant(seed).derive(10).unwrap(),
            &GrowOptions::DEFAULT.with_valence(8).with_angle(40.0).with_radius(0.2),
        )
        .unwrap();
        assert_plant(&g);
        assert_unfolded(&format!("thesis plant, seed {seed}"), g.mesh.mesh());
        let g = grow(&growing_tree(seed).derive(7).unwrap(), &GrowOptions::DEFAULT.with_valence(10).with_angle(35.0))
            .unwrap();
        assert_plant(&g);
        assert_unfolded(&format!("growing tree, seed {seed}"), g.mesh.mesh());
    }
    // The benchmark's Fig. 12.2 case (two nested features per bud and step), 7 steps.
    let rule = RuleSpec::deterministic("L0(s)", "[L(s) L0(s+1) L(s+1) P(s+1)][R(s) L0(s+1) L(s+1) P(s+1)]");
    let fig = Lsystem::new("L(0) L0(0) P(0)", &[rule], 0).unwrap();
    let g = grow(&fig.derive(7).unwrap(), &GrowOptions::DEFAULT.with_valence(32)).unwrap();
    assert_plant(&g);
    assert_unfolded("Fig. 12.2 grammar, 7 steps, valence 32", g.mesh.mesh());
    let ls =
        Lsystem::new("X", &[RuleSpec::deterministic("X", "F[&+X]/[&-X]///FX"), RuleSpec::deterministic("F", "FF")], 0)
            .unwrap();
    for (steps, valence) in [(4, 12), (5, 16), (4, 20)] {
        let opts = GrowOptions::DEFAULT.with_valence(valence).with_angle(25.7).with_radius(0.2).with_length(0.6);
        let g = grow(&ls.derive(steps).unwrap(), &opts).unwrap();
        assert_plant(&g);
        assert_unfolded(&format!("turtle plant, {steps} steps, valence {valence}"), g.mesh.mesh());
    }
    for s in ["F[+F]F", "F[+F][-F]F", "L(0)[L(0)L(1)L(1)P(1)][R(0)L(1)P(1)]P(0)", "F[&F]/[&F]/F", "F[&+F/[&-F]]"] {
        for valence in [8, 10, 12, 16] {
            let g = grow(&modules(s), &GrowOptions::DEFAULT.with_valence(valence)).unwrap();
            assert_plant(&g);
            assert_unfolded(&format!("{s}, valence {valence}"), g.mesh.mesh());
        }
    }
}

/// The check can fail: a quad twisted by swapping two corners' positions is caught.
#[test]
fn the_fold_check_catches_a_twisted_quad() {
    let mut g = grow(&modules("F F"), &GrowOptions::DEFAULT).unwrap();
    assert!(folded_faces(g.mesh.mesh()).is_empty());
    let m = g.mesh.mesh();
    let f = (0..m.face_count() as u32).find(|&f| m.face_arity(f) == 4).unwrap();
    let vs: Vec<u32> = m.face_vertices(f).collect();
    let (a, b) = (g.mesh.position(vs[2]), g.mesh.position(vs[3]));
    g.mesh.set_position(vs[2], b).unwrap();
    g.mesh.set_position(vs[3], a).unwrap();
    assert!(folded_faces(g.mesh.mesh()).iter().any(|&(x, _)| x == f));
}

/// The same seed grows the same plant; different seeds grow different plants.
#[test]
fn seeds_choose_the_plant() {
    let grow_seed = |seed| grow(&thesis_plant(seed).derive(9).unwrap(), &GrowOptions::DEFAULT).unwrap();
    let plants: Vec<Grown> = (0..8).map(grow_seed).collect();
    for (seed, p) in plants.iter().enumerate() {
        assert_eq!(*p, grow_seed(seed as u64), "seed {seed} grew two different plants");
        for q in &plants[..seed] {
            assert_ne!(p.mesh, q.mesh, "seed {seed} grew the same plant as an earlier seed");
        }
    }
}

/// The height of the trunk's tip: the pole on the trunk's axis (the turtle's +z; rolls and the
/// branches' turns leave it) furthest from the root.
fn trunk_height(g: &Grown) -> f64 {
    g.mesh
        .poles()
        .iter()
        .map(|&p| g.mesh.position(p))
        .filter(|p| p.x.hypot(p.y) < 1e-9)
        .map(|p| p.z)
        .fold(f64::MIN, f64::max)
}

/// §12's shrub limitation lifted: with an apex that survives its branches, the trunk (and every
/// branch) keeps growing in later steps — the trunk's tip rises every step, and a branch's own
/// segments after its side branches are drawn at its tip — whereas in the thesis's grammar the
/// parent stops where it branches and the trunk's height is that of step 1 forever.
#[test]
fn an_apex_that_survives_its_branches_keeps_growing() {
    let tree =
        Lsystem::new("A(0)", &[RuleSpec::deterministic("A(s)", "L(s) [L(s) A(s+1)] [R(s) A(s+1)] A(s+1)")], 0).unwrap();
    let shrub = Lsystem::new("L(0) L0(0) P(0)", &[RuleSpec::deterministic("L0(s)", "[L(s) L0(s+1) L(s+1) P(s+1)]")], 0)
        .unwrap();
    let (mut tree_h, mut shrub_h) = (Vec::new(), Vec::new());
    for steps in 1..6 {
        let g = grow(&tree.derive(steps).unwrap(), &GrowOptions::DEFAULT).unwrap();
        assert_plant(&g);
        // The branches opened before the last step draw (the last step's apexes draw nothing
        // yet): 1 + Σ_{j<n} 2·3^(j−1) = 3^(n−1) open ends, the trunk's among them.
        assert_eq!(g.open_ends, 3usize.pow(steps - 1), "steps {steps}");
        assert_eq!(g.branches, g.open_ends);
        tree_h.push(trunk_height(&g));
        let g = grow(&shrub.derive(steps).unwrap(), &GrowOptions::DEFAULT).unwrap();
        assert_plant(&g);
        shrub_h.push(trunk_height(&g));
    }
    for (k, h) in tree_h.iter().enumerate() {
        // After n steps the trunk has drawn L(s), [L(s), [R(s) for s < n, each S(s) long
        // (Eq. 11.2), and its tip pole stands half the last length beyond: it rose every step.
        let n = k + 1;
        let want = 3.0 * (0..n).map(|s| sigmoid(s as f64)).sum::<f64>() + 0.5 * sigmoid((n - 1) as f64);
        assert!((h - want).abs() < 1e-9, "steps {n}: trunk tip at {h}, want {want} (heights {tree_h:?})");
    }
    for k in 1..shrub_h.len() {
        assert!((shrub_h[k] - shrub_h[0]).abs() < 1e-12, "the shrub's trunk moved: heights {shrub_h:?}");
    }
}

/// Small nested strings whose meshes must not cross themselves where branches are nested (the
/// branch bases, §4.3): two branches on one loop, a branch on a branch, pitched pairs, nested
/// twice, at valences 8, 12 and 16. Crossings counted by Möller's triangle–triangle test
/// (tests_selfint); on the strings pymeshlab measured it agrees (`F F [+F F F] [-F F F] F F` at
/// valence 12: 2 quads here, 4 triangles there).
const NESTED: [&str; 9] = [
    "F F F F",
    "F F [+F F F] F F",
    "F F [+F F F] [-F F F] F F",
    "F [+F] [-F] F",
    "F [&F] [^F] F",
    "F F [&F F] /(180) [&F F] F",
    "F F [+F [-F [+F F] F] F] F",
    "F F [+F [+F F] F F] F F",
    "F F [&F F] /(90) [&F F] F",
];

/// (string, valence, self-intersecting faces, faces) for each of `strings` at valences 8, 12, 16.
fn nested_crossings(strings: &[&str]) -> Vec<(String, u32, usize, usize)> {
    let mut out = Vec::new();
    for s in strings {
        for valence in [8, 12, 16] {
            let opts = GrowOptions::DEFAULT.with_valence(valence).with_radius(0.2).with_length(1.0);
            let g = grow(&modules(s), &opts).unwrap();
            assert_plant(&g);
            let m = g.mesh.mesh();
            out.push((s.to_string(), valence, super::tests_selfint::self_intersecting_faces(m), m.face_count()));
        }
    }
    out
}

/// The nested strings that no longer cross themselves (before gaps were held to 135°, the pairs
/// on one loop crossed at valences 12 and 16 and the twice-nested string at every valence: 9
/// cases, e.g. `F [+F] [-F] F` at valence 16 in 4 of 104 faces).
#[test]
fn nested_branches_do_not_cross_themselves() {
    let counts = nested_crossings(&NESTED[..7]);
    let bad: Vec<_> = counts.iter().filter(|c| c.2 > 0).collect();
    assert!(bad.is_empty(), "self-intersecting faces (string, valence, faces, of): {bad:?}");
}

/// Every nested string, the last two included. Ignored until they pass. Measured now: a branch
/// nested on a branch's first loop, `F F [+F [+F F] F F] F F`, crosses in 3 of 90 faces at
/// valence 8 (at the inner gap's far side the outer branch's next quad and the inner branch's
/// first quad leave the same edge in nearly the same direction and overlap); two pitched
/// branches a quarter turn apart, `F F [&F F] /(90) [&F F] F`, in 6 of 68 and 8 of 136 faces at
/// valences 8 and 16 (none at 12): at valence 8 the first branch (−y) takes the run
/// 225°…0° of its sector {225°…45°}, the tie vertex nearer the second branch's heading (−x,
/// 180°), which is left 45°…180°, centred 67.5° off its heading; its first quads from 45°
/// sweep through the trunk's next segment. The two runs are now chosen together
/// (grow::paired_runs), which does not help here: at valence 8 two runs of 4 are the loop's
/// two halves, whose centroids are opposite, so for headings a quarter turn apart the best
/// pair is 22.5° and 67.5° off whichever way (not "each 22.5° off", as an earlier note
/// hoped); only runs of 3 (valence 4 branches) could face both. Before the first loops
/// cleared the parent's tube and siblings opened on their own sides: 9, 8 and 12.
/// Re-measured 2026-12-02 with paired runs, unchanged (3/90 at valence 8; 6/68, 0/96, 8/136).
/// The wide gaps of `GrowOptions::wide_gaps` do not help: 8/5/7 and 6/16/22 at valences
/// 8/12/16.
#[test]
#[ignore = "two nested strings still cross: see the doc comment for the counts"]
fn every_nested_string_is_free_of_crossings() {
    let counts = nested_crossings(&NESTED);
    let bad: Vec<_> = counts.iter().filter(|c| c.2 > 0).collect();
    assert!(bad.is_empty(), "self-intersecting faces (string, valence, faces, of): {bad:?}");
}

/// A branch's first loop lies outside its parent's tube, which goes on beyond the loop the
/// branch nests on (as the parent's next segments or its tip): for a branch leaving at 15°,
/// 20°, 30° or 45° to its parent, no first-loop vertex lies nearer the parent's axis than the
/// parent's radius, and the branch's tube does not run through the parent's. A first segment of
/// R + r along the heading (as before) crossed 16, 18 and 23 faces at 15° (valences 8, 12,
/// 16). Left: at 15° and 20° the two quads at one sharp end of the gap (run edge v0 v1 and far
/// edge n1 v0, n1 lifted straight above v1 and so seen end on along the heading) cross each
/// other — 2 faces.
#[test]
fn a_branch_first_loop_lies_outside_the_parent_tube() {
    let trunk_radius = 0.25 * sigmoid(0.0);
    for angle in [15.0, 20.0, 30.0, 45.0] {
        for valence in [8, 12, 16] {
            let opts = GrowOptions::DEFAULT.with_valence(valence).with_angle(angle);
            let g = grow(&modules("F F [+F F] F F"), &opts).unwrap();
            assert_plant(&g);
            let crossing = super::tests_selfint::self_intersecting_faces(g.mesh.mesh());
            let allowed = if angle < 30.0 { 2 } else { 0 };
            assert!(crossing <= allowed, "angle {angle}, valence {valence}: {crossing} faces cross");
            // The branch's first loop: its node nearest the root off the trunk's axis (the loop
            // it nests on has the gap's far side in its node, a little off the axis).
            let sk = g.mesh.skeleton(Some(g.root)).unwrap();
            let first = (0..sk.node_count() as u32)
                .filter(|&n| !sk.is_pole(n) && sk.position(n).x.hypot(sk.position(n).y) > 0.5 * trunk_radius)
                .min_by_key(|&n| sk.depth(n))
                .unwrap();
            for &v in sk.vertices(first) {
                let p = g.mesh.position(v);
                let d = p.x.hypot(p.y);
                assert!(d >= trunk_radius - 1e-9, "angle {angle}, valence {valence}: vertex {v} at {d} from the axis");
            }
        }
    }
}

/// Siblings share a loop by where they point: in `F F [&F F] /(90) [&F F] F` the second branch
/// heads to −x, a quarter turn from the first (−y); taking turns, the first took the run on its
/// side reaching round to −x and left the second a run facing +y (112° from its heading at
/// valence 8). With sectors each run's centroid lies within 90° of its own heading.
#[test]
fn sibling_branches_open_on_their_own_sides() {
    for valence in [8, 12, 16] {
        let g = grow(&modules("F F [&F F] /(90) [&F F] F"), &GrowOptions::DEFAULT.with_valence(valence)).unwrap();
        assert_plant(&g);
        let sk = g.mesh.skeleton(Some(g.root)).unwrap();
        // The trunk's second loop, which both branches nest on (two segments of S(0) up).
        let host_z = 2.0 * sigmoid(0.0);
        for heading in [Vec3::NEG_Y, Vec3::NEG_X] {
            let side = |p: Vec3| p.dot(heading) > 0.15;
            // The branch's first loop and the segment faces down to its gap.
            let first = (0..sk.node_count() as u32)
                .filter(|&n| !sk.is_pole(n) && side(sk.position(n)))
                .min_by_key(|&n| sk.depth(n))
                .unwrap();
            let seg = sk.parent_segment(first).unwrap();
            let m = g.mesh.mesh();
            let mut run: Vec<u32> = sk
                .segment_faces(seg)
                .iter()
                .flat_map(|&f| m.face_vertices(f).collect::<Vec<_>>())
                .filter(|&v| (m.position(v).z - host_z).abs() < 1e-9)
                .collect();
            run.sort_unstable();
            run.dedup();
            assert!(run.len() >= 3, "valence {valence}: run {run:?}");
            let c = run.iter().map(|&v| m.position(v)).sum::<Vec3>() / run.len() as f64;
            let c = Vec3::new(c.x, c.y, 0.0).normalize();
            let off = c.dot(heading).clamp(-1.0, 1.0).acos().to_degrees();
            assert!(
                off < 90.0,
                "valence {valence}: the gap of the branch heading {heading} is centred {off:.1}° off it"
            );
        }
    }
}

/// The recipes' plants (examples/lsystem_*.rhai, their grammars and options) still cross
/// themselves, all at branch bases (every crossing pair lies within four vertex rings: no two
/// distant branches pass through each other): this holds the counts measured when the first
/// loops began to clear their parents' tubes and siblings to open on their own sides, so that
/// they only fall. Before those changes: 483 of 1516 faces (shrub), 1180 of 4830 (tree), 533
/// of 4528 (turtle plant); the turtle plant's 202 since two siblings' runs are chosen together
/// (220 when the first sibling chose first).
#[test]
fn the_recipes_cross_themselves_no_more_than_measured() {
    let turtle = turtle_plant();
    let cases = [
        ("shrub", thesis_plant(4).derive(10).unwrap(), GrowOptions::DEFAULT.with_angle(40.0).with_radius(0.2), 513),
        ("tree", growing_tree(2).derive(7).unwrap(), GrowOptions::DEFAULT.with_valence(10).with_angle(35.0), 791),
        (
            "turtle plant",
            turtle.derive(5).unwrap(),
            GrowOptions::DEFAULT.with_valence(16).with_angle(25.7).with_radius(0.2).with_length(0.6),
            202,
        ),
    ];
    for (what, s, opts, measured) in cases {
        let g = grow(&s, &opts).unwrap();
        assert_plant(&g);
        let n = super::tests_selfint::self_intersecting_faces(g.mesh.mesh());
        assert!(n <= measured, "{what}: {n} self-intersecting faces of {}, measured {measured}", g.mesh.face_count());
    }
}

#[test]
fn the_refusal_for_want_of_room_names_a_valence_that_grows_the_string() {
    // Three branches on every node, three deep: at valence 8, 16 and 24 the third level's
    // loops are too small for three runs of 3 vertices. The valence the error names grows it,
    // and it is more than the refused one.
    let s = "F[+F[+F[+F][-F][&F]][-F[+F][-F][&F]][&F[+F][-F][&F]]][-F[+F[+F][-F][&F]][-F][&F]][&F[+F][-F][&F]]";
    for v in [8, 16, 24] {
        let Err(LsystemError::NoRoomForBranch { works: Some(named), .. }) =
            grow(&modules(s), &GrowOptions::DEFAULT.with_valence(v))
        else {
            panic!("valence {v} should run out of room");
        };
        assert!(named > v, "{named} at {v}");
        let grown = grow(&modules(s), &GrowOptions::DEFAULT.with_valence(named));
        assert!(grown.is_ok(), "valence {named}: {:?}", grown.err());
        let e = grow(&modules(s), &GrowOptions::DEFAULT.with_valence(v)).unwrap_err().to_string();
        assert!(e.contains(&format!("`valence: {named}` grows this string")), "{e}");
    }
}

#[test]
fn a_flat_base_stands_the_plant_on_a_disk() {
    // The turtle starts at the origin heading +z: with a flat base the root pole and a loop of
    // the trunk's first radius lie in z = 0, every face of the root's fan in that plane facing
    // down; the base loop is one more skeleton node. Without, the root is a cone's tip.
    // (At the default 30° and radius 0.25 the thesis plant's branches cross each other and
    // to_solid refuses it, flat base or not: the shrub recipe's 40° and 0.2 here.)
    let opts = GrowOptions::DEFAULT.with_flat_base(true).with_angle(40.0).with_radius(0.2);
    for plant in
        [grow(&modules("F[+F][-F]F"), &opts).unwrap(), grow(&thesis_plant(3).derive(8).unwrap(), &opts).unwrap()]
    {
        let pm = &plant.mesh;
        pm.check().unwrap();
        let m = pm.mesh();
        assert!(m.is_closed() && m.is_manifold() && m.euler() == 2 && m.volume() > 0.0);
        assert_eq!(pm.position(plant.root), Vec3::ZERO);
        let fan = pm.fan(i64::from(plant.root)).unwrap();
        for h in fan {
            let f = m.face(h);
            assert!(m.face_vertices(f).all(|v| pm.position(v).z.abs() < 1e-12), "a fan face off the ground");
            assert!(m.face_normal(f).z < -0.999, "the base faces down");
            let rim = pm.position(m.target(h));
            assert!((rim.length() - 0.2 * sigmoid(0.0)).abs() < 1e-12, "the base loop has the trunk's radius");
        }
        assert!(m.positions().iter().all(|p| p.z >= -1e-12), "nothing below the ground");
        let sk = pm.skeleton(Some(plant.root)).unwrap();
        assert_eq!(sk.node_count(), 2 + plant.segments + plant.open_ends, "the base loop is one more node");
        let solid = pm.to_solid().unwrap();
        assert!(solid.is_closed() && solid.is_manifold() && solid.genus() == 0);
    }
    let pointed = grow(&modules("F"), &GrowOptions::DEFAULT).unwrap();
    assert_eq!(pointed.mesh.fan(i64::from(pointed.root)).unwrap().len(), 8);
    assert!(pointed.mesh.mesh().positions().iter().filter(|p| p.z.abs() < 1e-12).count() == 1, "a point");
}
