//! Smooth plants: subdivided rest meshes with pointed tips, and skins carried through.

use super::super::{write_animation_glb, Animation, Curve, Gravity, Growth, Modifier, NodeState, Skinning};
use super::*;
use crate::mesh::Mesh;
use crate::polar::PolarMesh;

fn no_custom() -> impl FnMut(usize, u32, f64, NodeState) -> Result<NodeState, String> {
    |_, _, _, s| Ok(s)
}

/// A grown plant of the thesis's grammar (§11) with its root.
fn plant() -> (PolarMesh, u32) {
    let opts = crate::lsystem::GrowOptions::DEFAULT.with_angle(40.0).with_radius(0.2);
    let grown = crate::lsystem::grow(&crate::lsystem::tests_grow::thesis_plant(3).derive(8).unwrap(), &opts).unwrap();
    (grown.mesh, grown.root)
}

fn check_solid(m: &Mesh, what: &str) {
    assert!(m.is_closed() && m.is_manifold(), "{what}: closed and manifold");
    assert_eq!(m.genus(), 0, "{what}: genus");
    assert!(m.volume() > 0.0, "{what}: faces outward");
}

#[test]
fn a_smooth_plant_keeps_its_tips_pointed_and_its_skin_sums_to_one() {
    let (pm, root) = plant();
    let anim = Animation::new(&pm, Some(root), Skinning::Smooth).unwrap();
    let smooth = anim.subdivided(2).unwrap();
    let (coarse, fine) = (anim.rest_mesh(), smooth.rest_mesh());
    check_solid(fine, "subdivided plant");
    // Two Catmull–Clark steps: every face of arity n makes n quads, then four each.
    let arity: usize = (0..coarse.face_count() as u32).map(|f| coarse.face_arity(f)).sum();
    assert_eq!(fine.face_count(), 4 * arity);
    // Control vertices keep their ids; a tip (a pole at a leaf node) stays exactly where it was,
    // while every other pole and every loop vertex moves (the surface is smoothed).
    let sk = anim.skeleton();
    let tips: Vec<u32> = (0..coarse.vertex_count() as u32)
        .filter(|&v| sk.is_pole(sk.node_of(v)) && anim.children(sk.node_of(v)).is_empty())
        .collect();
    assert!(tips.len() >= 3, "the plant has branch tips: {tips:?}");
    let mut moved = 0;
    for v in 0..coarse.vertex_count() as u32 {
        if tips.contains(&v) {
            assert_eq!(fine.position(v), coarse.position(v), "tip {v} stays put");
        } else if fine.position(v).distance(coarse.position(v)) > 1e-9 {
            moved += 1;
        }
    }
    assert!(moved > coarse.vertex_count() / 2, "the surface is smoothed ({moved} of {} moved)", coarse.vertex_count());
    // No corner marks left on the result, and the smooth plant lies inside the control mesh's
    // hull of volume (subdivision shrinks a convex-ish tube): smaller volume, same bounds order.
    assert!((0..fine.vertex_count() as u32).all(|v| !fine.is_corner(v)));
    assert!(fine.volume() < coarse.volume() && fine.volume() > 0.7 * coarse.volume());
    // Skin: at most four joints a vertex, weights positive and summing to 1; a control tip is
    // bound to its own node alone.
    let inf = smooth.influences();
    assert_eq!(inf.joints.len(), fine.vertex_count());
    for (v, (j, w)) in inf.joints.iter().zip(&inf.weights).enumerate() {
        let sum: f64 = w.iter().sum();
        assert!((sum - 1.0).abs() < 1e-12, "vertex {v}: weights sum to {sum}");
        assert!(w.iter().all(|&x| x >= 0.0) && w[0] > 0.0, "vertex {v}: {w:?}");
        assert!(j.iter().all(|&n| (n as usize) < sk.node_count()));
    }
    for &t in &tips {
        assert_eq!((inf.joints[t as usize][0], inf.weights[t as usize][0]), (sk.node_of(t), 1.0), "tip {t}");
    }
    // Vertices blended between nodes exist (else the skin would tear at the loops).
    assert!(inf.weights.iter().filter(|w| w[1] > 0.0).count() > fine.vertex_count() / 4);
}

#[test]
fn the_smooth_rest_pose_is_the_subdivision_and_every_growth_pose_is_valid() {
    let (pm, root) = plant();
    let mut anim = Animation::new(&pm, Some(root), Skinning::Smooth).unwrap();
    anim.add(Modifier::Growth(Growth { curve: Curve::Sigmoid, ..Growth::default() })).unwrap();
    let smooth = anim.subdivided(1).unwrap();
    let rest = smooth.mesh_of(&smooth.rest_states());
    let worst =
        rest.positions().iter().zip(smooth.rest_mesh().positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
    assert!(worst < 1e-12, "the rest pose moves a vertex by {worst}");
    let end = smooth.duration();
    for k in 0..=10 {
        let t = end * f64::from(k) / 10.0;
        let pose = smooth.pose(t, &mut no_custom()).unwrap();
        let tri = pose.triangulate().unwrap_or_else(|e| panic!("t = {t}: {e}"));
        assert!(tri.is_closed() && tri.is_manifold(), "t = {t}");
    }
    // The end of the growth is the smooth model.
    let last = smooth.pose(end, &mut no_custom()).unwrap();
    assert!(last.positions().iter().zip(smooth.rest_mesh().positions()).all(|(a, b)| a.distance(*b) < 1e-9));
}

#[test]
fn a_vertex_bound_to_one_node_moves_as_that_node_rigidly() {
    // Linear blend skinning with one joint of weight 1 is §7.3's rigid skinning: bend the stalk
    // by gravity and compare the blended positions of single-joint vertices with the rigid ones.
    let (pm, root) = plant();
    let mut anim = Animation::new(&pm, Some(root), Skinning::Simple).unwrap();
    anim.add(Modifier::Gravity(Gravity { drag: 0.5, ..Gravity::default() })).unwrap();
    let states = anim.states_at(0.5, &mut no_custom()).unwrap();
    let rigid = anim.skinned_positions(&states);
    let single = Influences::single(anim.skeleton().vertex_nodes());
    let poses = anim.joint_poses(&states);
    let blended = super::super::skinning::skin_blended(
        anim.rest_mesh().positions(),
        &single,
        anim.skeleton().positions(),
        &poses,
    );
    let worst = rigid.iter().zip(&blended).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
    assert!(worst < 1e-12, "{worst}");
    assert!(rigid.iter().zip(anim.rest_mesh().positions()).any(|(a, b)| a.distance(*b) > 1e-3), "gravity bends it");
}

#[test]
fn the_smooth_file_skins_as_mesh_of() {
    // glTF 2.0 §3.7.3: a vertex's world position is Σ wⱼ · (world joint matrix × inverse bind
    // matrix)ⱼ · rest position. Read the file's joints and weights, skin its rest positions at
    // a frame, and compare with the kernel's pose in glTF's Y-up axes.
    let (pm, root) = plant();
    let mut anim = Animation::new(&pm, Some(root), Skinning::Smooth).unwrap();
    anim.add(Modifier::Growth(Growth::default())).unwrap();
    anim.add(Modifier::Gravity(Gravity { drag: 0.5, ..Gravity::default() })).unwrap();
    let smooth = anim.subdivided(2).unwrap();
    let frames = smooth.frame_states(30, 1.0 / 24.0, &mut no_custom()).unwrap();
    let mut bytes = Vec::new();
    write_animation_glb(&smooth, &frames, 24.0, &mut bytes, std::path::Path::new("plant.glb")).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let prim = gltf.meshes().next().unwrap().primitives().next().unwrap();
    let reader = prim.reader(|_| Some(blob));
    let joints: Vec<[u16; 4]> = reader.read_joints(0).unwrap().into_u16().collect();
    let weights: Vec<[f32; 4]> = reader.read_weights(0).unwrap().into_f32().collect();
    assert_eq!(joints.len(), smooth.rest_mesh().vertex_count());
    assert!(weights.iter().any(|w| w[1] > 0.0), "blended weights are written");
    for w in &weights {
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6, "{w:?}");
    }
    let frame = 29;
    let world = super::super::tests::file_joint_matrices(&gltf, blob, frame);
    let rest: Vec<glam::Vec3> = reader.read_positions().unwrap().map(glam::Vec3::from).collect();
    let posed = smooth.mesh_of(&frames[frame]);
    let mut worst = 0.0f32;
    for (v, p) in rest.iter().enumerate() {
        let mut got = glam::Vec3::ZERO;
        for k in 0..4 {
            got += world[joints[v][k] as usize].transform_point3(*p) * weights[v][k];
        }
        let want = crate::io::UpAxis::Y.to_file(posed.position(v as u32)).as_vec3();
        worst = worst.max((got - want).length());
    }
    assert!(worst < 1e-5, "largest difference {worst}");
}

#[test]
fn subdividing_refuses_too_many_levels_and_twice_and_leaves_the_animation() {
    let (pm, root) = plant();
    let anim = Animation::new(&pm, Some(root), Skinning::Smooth).unwrap();
    let e = anim.subdivided(5).unwrap_err().to_string();
    assert!(e.contains("levels") && e.contains("5"), "{e}");
    let once = anim.subdivided(1).unwrap();
    let e = once.subdivided(1).unwrap_err().to_string();
    assert!(e.contains("already subdivided"), "{e}");
    assert!(!anim.is_subdivided() && once.is_subdivided());
    assert_eq!(anim.subdivided(0).unwrap().rest_mesh().positions(), anim.rest_mesh().positions());
}
