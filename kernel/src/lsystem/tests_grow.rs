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
    assert!(matches!(e, LsystemError::NoRoomForBranch { valence: 8, .. }), "{e}");
    let e = grow(&modules("F"), &GrowOptions::DEFAULT.with_valence(4)).unwrap_err();
    assert!(matches!(e, LsystemError::InvalidOption(_)), "{e}");
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

/// Branches off the trunk, one level deep, have no folded quad: every face triangulates in its
/// own plane, as a glTF export needs. (Known limitation: branches nested on a branch's first
/// loops can still get twisted quads at their base; see the module notes.)
#[test]
fn one_level_of_branches_has_no_folded_faces() {
    for s in ["F[+F]F", "F[+F][-F]F", "L(0)[L(0)L(1)L(1)P(1)][R(0)L(1)P(1)]P(0)", "F[&F]/[&F]/F"] {
        for valence in [8, 10, 12, 16] {
            let g = grow(&modules(s), &GrowOptions::DEFAULT.with_valence(valence)).unwrap();
            assert_plant(&g);
            if let Err(e) = g.mesh.mesh().triangulate() {
                panic!("{s}, valence {valence}: {e}");
            }
        }
    }
}
