//! The thesis's named models built with the seven operations and low-level moves, kept as
//! regression models: the gear of §4.8 and the ladder of §5.3 (Fig. 7.2). The script recipes in
//! `examples/` replay the same constructions.

use std::f64::consts::TAU;

use super::PolarMesh;
use crate::math::Vec3;

fn verts_where(pm: &PolarMesh, f: impl Fn(Vec3) -> bool) -> Vec<u32> {
    (0..pm.vertex_count() as u32).filter(|&v| f(pm.position(v))).collect()
}

/// Puts each vertex of `verts` at radius `r` from the z axis and height `z`, keeping its angle.
fn to_circle(pm: &mut PolarMesh, verts: &[u32], r: f64, z: f64) {
    for &v in verts {
        let p = pm.position(v);
        let a = p.y.atan2(p.x);
        pm.set_position(v, Vec3::new(r * a.cos(), r * a.sin(), z)).unwrap();
    }
}

fn loop_edge_at(pm: &PolarMesh, v: u32) -> u32 {
    pm.mesh().outgoing(v).find(|&h| pm.is_loop(h)).unwrap()
}

/// The gear of §4.8 with `teeth` hexagonal teeth; returns it with the tooth poles.
fn gear(teeth: usize) -> (PolarMesh, Vec<u32>, u32) {
    let (big, small, h) = (1.0, 0.35, 0.15);
    // 1–3: octahedron, a loop near each pole, the equator removed.
    let mut pm = PolarMesh::octahedron();
    pm.add_refinement(i64::from(pm.fan_of(0)[0])).unwrap();
    pm.add_refinement(i64::from(pm.fan_of(5)[0])).unwrap();
    pm.remove_refinement(i64::from(pm.mesh().find_halfedge(1, 2).unwrap())).unwrap();
    pm.check().unwrap();
    // 4: those loops become the disk's outer edges.
    let low = verts_where(&pm, |p| (p.z + 0.5).abs() < 1e-9);
    let high = verts_where(&pm, |p| (p.z - 0.5).abs() < 1e-9);
    to_circle(&mut pm, &low, big, -h);
    to_circle(&mut pm, &high, big, h);
    // 5–6: two more loops, the hole's edges.
    let (s, n) = (pm.poles()[0], pm.poles()[1]);
    let rs = pm.add_refinement(i64::from(pm.fan_of(s)[0])).unwrap();
    let rn = pm.add_refinement(i64::from(pm.fan_of(n)[0])).unwrap();
    let (zs, zn) = (pm.position(s).z, pm.position(n).z);
    to_circle(&mut pm, &rs.vertices, small, zs.signum() * h);
    to_circle(&mut pm, &rn.vertices, small, zn.signum() * h);
    // 7: merge the poles: the hole.
    pm.merge_features(i64::from(s), i64::from(n)).unwrap();
    pm.check().unwrap();
    assert_eq!(pm.mesh().genus(), 1);
    // 8–11, 13–14: backbones until the valency is 4 per tooth, always splitting the longest
    // edge of the outer top loop, then every meridian set to an even angle.
    let top = verts_where(&pm, |p| (p.z - h).abs() < 1e-9 && p.truncate().length() > 0.9)[0];
    while pm.walk_of(loop_edge_at(&pm, top)).len() < 4 * teeth {
        let walk = pm.walk_of(loop_edge_at(&pm, top));
        let longest = walk
            .iter()
            .copied()
            .max_by(|&a, &b| {
                let len = |x: u32| pm.position(pm.ends(x)[0]).distance(pm.position(pm.ends(x)[1]));
                len(a).total_cmp(&len(b))
            })
            .unwrap();
        pm.add_refinement(i64::from(longest)).unwrap();
    }
    let walk = pm.walk_of(loop_edge_at(&pm, top));
    let n_loop = walk.len();
    for (k, &x) in walk.iter().enumerate() {
        let v = pm.ends(x)[0];
        let b = pm.mesh().outgoing(v).find(|&y| !pm.is_loop(y)).unwrap();
        let a = TAU * k as f64 / n_loop as f64;
        let meridian = pm.walk_vertices(&pm.walk_of(b));
        for m in meridian {
            let p = pm.position(m);
            let r = if p.truncate().length() > (big + small) / 2.0 { big } else { small };
            pm.set_position(m, Vec3::new(r * a.cos(), r * a.sin(), p.z)).unwrap();
        }
    }
    // 12: the middle loop of the rim, which will carry the teeth.
    let rim = pm.mesh().outgoing(top).find(|&y| !pm.is_loop(y) && pm.position(pm.ends(y)[1]).z < 0.0).unwrap();
    let m = pm.add_refinement(i64::from(rim)).unwrap();
    let mut ring = pm.walk_vertices(&m.halfedges);
    // 15–23: a tooth on every fourth run of 4 rim vertices, opening towards +z.
    let first = m.halfedges[0];
    let opens_up = pm.mesh().face_vertices(pm.face_of(first)).any(|v| pm.position(v).z > 1e-9);
    if !opens_up {
        ring.reverse();
    }
    let mut poles = Vec::new();
    let (depth, height) = (0.6 * h, 0.25);
    for j in 0..teeth {
        let run: Vec<u32> = (0..4).map(|i| ring[(4 * j + i) % ring.len()]).collect();
        let p = pm.add_feature(&run).unwrap();
        // The base hexagon: v1, v2 down, the new far-side vertices up.
        let far: Vec<u32> = pm.fan_of(p).iter().map(|&x| pm.ends(x)[1]).filter(|v| !run.contains(v)).collect();
        for &v in &run[1..3] {
            let q = pm.position(v);
            pm.set_position(v, Vec3::new(q.x, q.y, -depth)).unwrap();
        }
        for &v in &far {
            let q = pm.position(v);
            pm.set_position(v, Vec3::new(q.x, q.y, depth)).unwrap();
        }
        // The tip: a loop near the pole, placed as the base pushed out radially and narrowed,
        // with the pole in its middle (a flat top); then a loop halfway up.
        let axis = (pm.position(run[0]) + pm.position(run[3])).truncate().normalize().extend(0.0);
        let tip = pm.add_refinement(i64::from(pm.fan_of(p)[0])).unwrap();
        let mut centre = Vec3::ZERO;
        for &t in &tip.vertices {
            // The base vertex below t: along the backbone from t away from the pole.
            let down = pm.mesh().outgoing(t).find(|&y| !pm.is_loop(y) && pm.ends(y)[1] != p).unwrap();
            let b = pm.position(pm.ends(down)[1]);
            let radial = axis * b.dot(axis);
            let q = radial + (b - radial) * 0.7 + axis * height;
            pm.set_position(t, q).unwrap();
            centre += q;
        }
        pm.set_position(p, centre / tip.vertices.len() as f64).unwrap();
        let base_to_tip = pm.mesh().outgoing(run[1]).find(|&y| tip.vertices.contains(&pm.ends(y)[1])).unwrap();
        pm.add_refinement(i64::from(base_to_tip)).unwrap();
        poles.push(p);
    }
    (pm, poles, ring[0])
}

/// The node reached from `from` by `steps` segments, never stepping back (a chain).
fn walk_chain(sk: &super::Skeleton, from: u32, steps: usize) -> u32 {
    let (mut prev, mut n) = (u32::MAX, from);
    for _ in 0..steps {
        let next = sk.neighbors(n).iter().map(|&(_, o)| o).find(|&o| o != prev && o != n).unwrap();
        prev = n;
        n = next;
    }
    n
}

#[test]
fn gear_is_a_polar_torus_with_one_feature_per_tooth() {
    for teeth in [5, 12] {
        let (pm, poles, rim) = gear(teeth);
        pm.check().unwrap();
        let m = pm.mesh();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!(m.genus(), 1, "a gear is a torus");
        assert!(m.volume() > 0.0);
        // One feature per tooth, plus the disk.
        assert_eq!(pm.features().len(), teeth + 1);
        assert_eq!(poles.len(), teeth);
        assert!(poles.iter().all(|&p| pm.is_pole(p) && pm.valence(p) == 6), "hexagonal teeth");
        // The skeleton has exactly one cycle, around the hole; each tooth is a chain pole → tip
        // loop → middle loop → the rim's nesting loop.
        let sk = pm.skeleton(None).unwrap();
        assert_eq!(sk.cycle_count(), 1);
        for &p in &poles {
            let pn = sk.node_of(p);
            assert_eq!(sk.neighbors(pn).len(), 1);
            assert_eq!(walk_chain(&sk, pn, 3), sk.node_of(rim));
        }
        // The disk cannot be removed: it wraps around the hole.
        let mut copy = pm.clone();
        let disk_face = pm.features().into_iter().max_by_key(Vec::len).unwrap()[0];
        assert!(copy.remove_feature(i64::from(disk_face)).is_err());
        assert_eq!(copy, pm);
    }
}
/// The ladder of §5.3 (Fig. 7.2): one tube of valency 8 laid out as two rails side by side and
/// cut in two with `split_feature`; each rung is a feature on one rail merged with a feature on
/// the other.
fn ladder(rungs: usize) -> PolarMesh {
    let width = 1.5;
    let mut pm = PolarMesh::octahedron();
    for _ in 0..4 {
        let eq = pm.walk_of(loop_edge_at(&pm, 1));
        let longest = eq.iter().copied().max_by(|&a, &b| {
            let len = |x: u32| pm.position(pm.ends(x)[0]).distance(pm.position(pm.ends(x)[1]));
            len(a).total_cmp(&len(b))
        });
        pm.add_refinement(i64::from(longest.unwrap())).unwrap();
    }
    // 2·rungs + 5 loops: rail A gets loops 0..=rungs+1, the loop rungs+2 is cut out, rail B gets
    // the rest.
    let wanted = 2 * rungs + 5;
    while pm.loops().len() < wanted {
        pm.add_refinement(i64::from(pm.fan_of(0)[0])).unwrap();
    }
    let loops = loops_from_pole(&pm, 0);
    assert_eq!(loops.len(), wanted);
    let cut = rungs + 2;
    for (i, verts) in loops.iter().enumerate() {
        let (x, z) = if i < cut { (0.0, i as f64) } else { (width, i as f64 - cut as f64 - 1.0) };
        for &v in verts {
            let d = pm.position(v).truncate().normalize_or_zero() * 0.12;
            pm.set_position(v, Vec3::new(x + d.x, d.y, z)).unwrap();
        }
    }
    let cut_edge = loop_edge_at(&pm, loops[cut][0]);
    pm.split_feature(i64::from(cut_edge)).unwrap();
    // Each pole closes its rail 0.3 beyond its loop, on the side away from the rail.
    for pole in pm.poles() {
        let spine = pm.walk_of(pm.fan_of(pole)[0]);
        let (a, b) = (pm.position(pm.ends(spine[0])[1]), pm.position(pm.ends(spine[1])[1]));
        let c = pm.fan_of(pole).iter().map(|&x| pm.position(pm.ends(x)[1])).sum::<Vec3>() / 8.0;
        pm.set_position(pole, c + (a - b).normalize() * 0.3).unwrap();
    }
    assert_eq!(pm.mesh().component_count(), 2);
    // Rungs at heights 1..=rungs: on each rail the three vertices facing the other rail.
    for r in 1..=rungs {
        let z = r as f64;
        let mut feature_poles = Vec::new();
        for (x, facing) in [(0.0, 1.0), (width, -1.0)] {
            let ring = verts_where(&pm, |p| (p.z - z).abs() < 1e-9 && (p.x - x).abs() < 0.5);
            let ring = pm.walk_vertices(&pm.walk_of(loop_edge_at(&pm, ring[0])));
            let n = ring.len();
            let k = (0..n)
                .max_by(|&a, &b| (pm.position(ring[a]).x * facing).total_cmp(&(pm.position(ring[b]).x * facing)))
                .unwrap();
            let mut run = vec![ring[(k + n - 1) % n], ring[k], ring[(k + 1) % n]];
            let opens_up = pm
                .mesh()
                .face_vertices(pm.face_of(pm.mesh().find_halfedge(run[0], run[1]).unwrap()))
                .any(|v| pm.position(v).z > z + 1e-9);
            if !opens_up {
                run.reverse();
            }
            feature_poles.push(pm.add_feature(&run).unwrap());
        }
        pm.merge_features(i64::from(feature_poles[0]), i64::from(feature_poles[1])).unwrap();
    }
    pm
}

/// The loops met walking a backbone from pole `p`, each as its vertices.
fn loops_from_pole(pm: &PolarMesh, p: u32) -> Vec<Vec<u32>> {
    let spine = pm.walk_of(pm.fan_of(p)[0]);
    spine[..spine.len() - 1].iter().map(|&x| pm.walk_vertices(&pm.walk_of(pm.mesh().next(x)))).collect()
}

#[test]
fn ladder_genus_and_cycles_follow_the_rungs() {
    for rungs in [5, 7] {
        let pm = ladder(rungs);
        pm.check().unwrap();
        let m = pm.mesh();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!(m.component_count(), 1);
        assert_eq!(m.genus(), rungs as i64 - 1);
        let sk = pm.skeleton(None).unwrap();
        assert_eq!(sk.cycle_count(), rungs - 1);
        assert!(m.volume() > 0.0);
    }
}

/// Writes the models with their feature colours to `target/polar/*.glb` to look at them
/// (`cargo test -p blocksmith-kernel --lib -- --ignored export_polar_models`).
#[test]
#[ignore = "writes files for viewing"]
fn export_polar_models() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/polar");
    std::fs::create_dir_all(&dir).unwrap();
    crate::io::save(&gear(12).0.to_colored_mesh(), dir.join("gear.glb")).unwrap();
    crate::io::save(&ladder(5).to_colored_mesh(), dir.join("ladder.glb")).unwrap();
}
