//! Animation tests on two plants: a horizontal stalk (a chain skeleton) and the stalk with a
//! branch nested on one of its loops.

use super::*;
use crate::math::{Quat, Vec3};
use crate::mesh::Mesh;
use crate::polar::PolarMesh;

/// A stalk of radius 0.2 along x from x = −1 (the root pole, vertex 0) to x = 1: 8 segments
/// around, 10 bands (9 loops), so 11 skeleton nodes in a chain.
fn stalk() -> PolarMesh {
    let m = Mesh::uv_sphere(0.2, 8, 10).scale(Vec3::new(1.0, 1.0, 5.0)).rotate(Vec3::Y, 90.0);
    let north = m.vertex_count() as u32 - 1;
    PolarMesh::from_mesh(m, &[0, north], &[]).unwrap()
}

/// The stalk with a branch on its middle loop (vertices 41–43 are consecutive on loop 5).
fn branched() -> PolarMesh {
    let mut pm = stalk();
    let pole = pm.add_feature(&[41, 42, 43]).unwrap();
    pm.move_vertices(&[pole], Vec3::new(0.0, 0.0, 0.3), crate::polar::Frame::Global).unwrap();
    pm.check().unwrap();
    pm
}

fn no_custom() -> impl FnMut(usize, u32, f64, NodeState) -> Result<NodeState, String> {
    |_, _, _, s| Ok(s)
}

#[test]
fn both_skinnings_reproduce_the_rest_pose_bit_for_bit() {
    for skinning in [Skinning::Simple, Skinning::Smooth] {
        let pm = branched();
        let anim = Animation::new(&pm, Some(0), skinning).unwrap();
        let posed = anim.pose(0.0, &mut no_custom()).unwrap();
        assert_eq!(posed.positions(), pm.mesh().positions());
        assert_eq!(posed.face_count(), pm.mesh().face_count());
    }
}

#[test]
fn growth_starts_on_the_root_and_ends_on_the_model() {
    for curve in [Curve::Linear, Curve::Sigmoid] {
        let pm = branched();
        let mut anim = Animation::new(&pm, Some(0), Skinning::Smooth).unwrap();
        anim.add(Modifier::Growth(Growth { curve, ..Growth::default() })).unwrap();
        let root = anim.skeleton().position(anim.skeleton().root());
        let start = anim.pose(0.0, &mut no_custom()).unwrap();
        // At t = 0 the plant is its model scaled by MIN_SIZE about the root: a seed, not a point.
        for (p, q) in start.positions().iter().zip(pm.mesh().positions()) {
            let want = root + MIN_SIZE * (*q - root);
            assert!(p.distance(want) < 1e-12, "{curve:?}: a vertex at {p}, not {want}, at t = 0");
        }
        let end = anim.pose(anim.duration(), &mut no_custom()).unwrap();
        assert_eq!(end.positions(), pm.mesh().positions(), "{curve:?}: the end pose is the model");
        // Past the end nothing changes.
        assert_eq!(anim.pose(anim.duration() + 5.0, &mut no_custom()).unwrap().positions(), pm.mesh().positions());
    }
}

#[test]
fn each_node_starts_growing_at_its_delay() {
    let pm = stalk();
    let mut anim = Animation::new(&pm, Some(0), Skinning::Simple).unwrap();
    let g = Growth { delay: 0.5, speed: 1.0, curve: Curve::Linear, ..Growth::default() };
    anim.add(Modifier::Growth(g)).unwrap();
    for &n in anim.order() {
        let Some(p) = anim.parent(n) else { continue };
        let onset = g.onset(anim.depth(n));
        let before = anim.states_at(onset - 1e-3, &mut no_custom()).unwrap();
        let after = anim.states_at(onset + 0.25, &mut no_custom()).unwrap();
        let len = |s: &[NodeState]| s[n as usize].position.distance(s[p as usize].position);
        let full = anim.rest_states()[n as usize].position.distance(anim.rest_states()[p as usize].position);
        // Before its onset a segment is held at the minimum size.
        assert!((len(&before) - MIN_SIZE * full).abs() < 1e-12, "node {n} grows before its onset {onset}");
        // Linear: a quarter of the way a quarter after onset.
        assert!((len(&after) - 0.25 * full).abs() < 1e-9, "node {n}: {} vs {}", len(&after), 0.25 * full);
    }
}

#[test]
fn gravity_bends_the_stalk_keeps_its_segments_and_stays_bounded() {
    for drag in [0.1, 0.5, 1.0] {
        let pm = stalk();
        let mut anim = Animation::new(&pm, Some(0), Skinning::Smooth).unwrap();
        anim.add(Modifier::Gravity(Gravity { drag, ..Gravity::default() })).unwrap();
        let rest = anim.rest_states();
        let frames = anim.frame_states(1000, 1.0 / 24.0, &mut no_custom()).unwrap();
        let root = anim.skeleton().root() as usize;
        let tip = *anim.order().last().unwrap() as usize;
        let reach: f64 = anim
            .order()
            .iter()
            .filter_map(|&n| anim.parent(n).map(|p| (n, p)))
            .map(|(n, p)| rest[n as usize].position.distance(rest[p as usize].position))
            .sum();
        for (k, states) in frames.iter().enumerate() {
            assert_eq!(states[root].position, rest[root].position, "frame {k}: the root moved");
            for &n in anim.order() {
                let Some(p) = anim.parent(n) else { continue };
                let l0 = rest[n as usize].position.distance(rest[p as usize].position);
                let l = states[n as usize].position.distance(states[p as usize].position);
                assert!((l - l0).abs() <= 0.01 * l0, "drag {drag} frame {k}: segment {n} is {l}, rest {l0}");
                assert!(states[n as usize].position.distance(rest[root].position) <= reach * 1.01 + 1e-9);
            }
        }
        let sunk = rest[tip].position.z - frames.last().unwrap()[tip].position.z;
        assert!(sunk > 0.05, "drag {drag}: the tip sank only {sunk}");
        let posed = anim.mesh_of(frames.last().unwrap());
        assert!(posed.is_closed() && posed.is_manifold());
    }
}

#[test]
fn a_gravity_pose_is_the_frame_at_its_time() {
    let mut anim = Animation::new(&stalk(), None, Skinning::Simple).unwrap();
    anim.add(Modifier::Gravity(Gravity::default())).unwrap();
    // Frames at 24 fps: the pose at frame 12's time is frame 12, stepped from rest.
    let frames = anim.frame_states(13, 1.0 / POSE_STEPS_PER_UNIT, &mut no_custom()).unwrap();
    let at = anim.states_at(12.0 / POSE_STEPS_PER_UNIT, &mut no_custom()).unwrap();
    for (a, b) in at.iter().zip(&frames[12]) {
        assert!(a.position.distance(b.position) < 1e-12, "{} vs {}", a.position, b.position);
    }
    // At 0 (or before) the rest; a time too far to step to is refused by name.
    assert_eq!(anim.states_at(-1.0, &mut no_custom()).unwrap(), frames[0]);
    let e = anim.states_at(1e9, &mut no_custom()).unwrap_err();
    assert!(matches!(e, AnimError::InvalidParameter { name: "t", .. }), "{e}");
    assert!(matches!(anim.states_at(f64::NAN, &mut no_custom()), Err(AnimError::InvalidParameter { name: "t", .. })));
    assert!(matches!(anim.frame_states(3, 0.0, &mut no_custom()), Err(AnimError::InvalidParameter { name: "dt", .. })));
}

/// Whether `m` triangulates into a closed manifold mesh whose edges all have length.
fn assert_valid_pose(m: &Mesh, what: &str) {
    let t = m.triangulate().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(t.is_closed() && t.is_manifold(), "{what}: not closed and manifold");
    let shortest =
        t.edges().map(|h| t.position(t.origin(h)).distance(t.position(t.target(h)))).fold(f64::MAX, f64::min);
    assert!(shortest > 0.0, "{what}: an edge of length 0");
}

#[test]
fn every_pose_of_a_growth_is_a_valid_mesh() {
    // The case: a growing polar sphere (pose(t) for t = 0..5 of 7 failed to
    // triangulate), the branched stalk, and a grown plant with branches on branches.
    let sphere = {
        let m = Mesh::uv_sphere(0.2, 8, 6);
        let north = m.vertex_count() as u32 - 1;
        PolarMesh::from_mesh(m, &[0, north], &[]).unwrap()
    };
    let opts = crate::lsystem::GrowOptions::DEFAULT.with_angle(40.0).with_radius(0.2);
    let grown = crate::lsystem::grow(&crate::lsystem::tests_grow::thesis_plant(3).derive(8).unwrap(), &opts).unwrap();
    let plant = grown.mesh;
    for (name, pm) in [("sphere", sphere), ("branched", branched()), ("thesis plant", plant)] {
        for (curve, delays) in [(Curve::Sigmoid, (1.0, 1.0)), (Curve::Linear, (0.5, 1.5)), (Curve::Linear, (1.5, 0.2))]
        {
            let root = if name == "thesis plant" { Some(grown.root) } else { None };
            let mut anim = Animation::new(&pm, root, Skinning::Smooth).unwrap();
            let g = Growth { curve, delay: delays.0, thickness_delay: delays.1, ..Growth::default() };
            anim.add(Modifier::Growth(g)).unwrap();
            let end = anim.duration();
            for k in 0..=40 {
                let t = end * f64::from(k) / 40.0;
                let pose = anim.pose(t, &mut no_custom()).unwrap();
                assert_valid_pose(&pose, &format!("{name} {curve:?} {delays:?} t = {t}"));
            }
        }
    }
}

#[test]
fn custom_modifiers_see_the_previous_state_and_their_failures_are_named() {
    let pm = stalk();
    let mut anim = Animation::new(&pm, Some(0), Skinning::Simple).unwrap();
    anim.add(Modifier::Growth(Growth::default())).unwrap();
    anim.add(Modifier::Custom(7)).unwrap();
    // A modifier lifting every node by t: it receives the grown state and adds to it.
    let mut lift = |id: usize, _n: u32, t: f64, s: NodeState| {
        assert_eq!(id, 7);
        Ok(NodeState { position: s.position + Vec3::Z * t, ..s })
    };
    let t = anim.duration();
    let posed = anim.pose(t, &mut lift).unwrap();
    for (a, b) in posed.positions().iter().zip(pm.mesh().positions()) {
        assert!((a.z - b.z - t).abs() < 1e-12 && (a.x - b.x).abs() < 1e-12);
    }
    let mut fails = |_: usize, n: u32, _: f64, s: NodeState| if n == 3 { Err("no".to_string()) } else { Ok(s) };
    assert!(matches!(anim.pose(1.0, &mut fails), Err(AnimError::Custom { index: 1, node: 3, .. })));
    let mut nan = |_: usize, _: u32, _: f64, s: NodeState| Ok(NodeState { thickness: f64::NAN, ..s });
    assert!(matches!(anim.pose(1.0, &mut nan), Err(AnimError::BadState { index: 1, kind: "custom", .. })));
}

#[test]
fn smooth_skinning_turns_the_joint_ring_halfway() {
    // Bend the stalk at its middle node by a custom modifier that rotates every node past it
    // 60° about y around the middle node: simple skinning turns the middle ring by 0 (its
    // arriving segment is unchanged), smooth by 30°.
    let pm = stalk();
    let rest = Animation::new(&pm, Some(0), Skinning::Simple).unwrap();
    let mid = rest.order()[5];
    let pivot = rest.rest_states()[mid as usize].position;
    let after: Vec<u32> = rest.order()[6..].to_vec();
    let turn = Quat::from_axis_angle(Vec3::Y, 60f64.to_radians());
    let bend = |_: usize, n: u32, _: f64, s: NodeState| {
        Ok(if after.contains(&n) { NodeState { position: pivot + turn * (s.position - pivot), ..s } } else { s })
    };
    for (skinning, expected) in [(Skinning::Simple, 0.0), (Skinning::Smooth, 30.0)] {
        let mut anim = Animation::new(&pm, Some(0), skinning).unwrap();
        anim.add(Modifier::Custom(0)).unwrap();
        let states = anim.states_at(0.0, &mut bend.clone()).unwrap();
        let poses = anim.joint_poses(&states);
        let angle = poses[mid as usize].rotation.angle_between(Quat::IDENTITY).to_degrees();
        assert!((angle - expected).abs() < 1e-9, "{skinning:?}: {angle}° (expected {expected}°)");
        let posed = anim.mesh_of(&states);
        assert!(posed.is_closed() && posed.is_manifold());
    }
}

#[test]
fn export_writes_one_joint_per_node_and_a_key_per_frame() {
    let pm = branched();
    let mut anim = Animation::new(&pm, Some(0), Skinning::Smooth).unwrap();
    anim.add(Modifier::Growth(Growth::default())).unwrap();
    anim.add(Modifier::Gravity(Gravity { drag: 0.5, ..Gravity::default() })).unwrap();
    let frames = anim.frame_states(48, 1.0 / 24.0, &mut no_custom()).unwrap();
    let mut bytes = Vec::new();
    write_animation_glb(&anim, &frames, 24.0, &mut bytes, std::path::Path::new("plant.glb")).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).expect("a valid glTF");
    let n = anim.skeleton().node_count();
    let skin = gltf.skins().next().expect("a skin");
    assert_eq!(skin.joints().count(), n);
    let animation = gltf.animations().next().expect("an animation");
    assert_eq!(animation.channels().count(), 3 * n);
    let input = animation.samplers().next().unwrap().input();
    assert_eq!(input.count(), 48);
    assert_eq!(input.max().unwrap()[0].as_f64().unwrap() as f32, (47.0 / 24.0) as f32);
}

#[test]
fn exported_animation_stands_up_and_poses_as_mesh_of() {
    // Skinning the file's rest positions by the file's joints at a frame (glTF 2.0 §3.7.3:
    // world joint matrix × inverse bind matrix) must give that frame's mesh in glTF's Y-up
    // axes: kernel (x, y, z) as (x, z, −y), to f32 precision.
    let pm = branched();
    let mut anim = Animation::new(&pm, Some(0), Skinning::Simple).unwrap();
    anim.add(Modifier::Gravity(Gravity { drag: 0.5, ..Gravity::default() })).unwrap();
    let frames = anim.frame_states(6, 1.0 / 24.0, &mut no_custom()).unwrap();
    let mut bytes = Vec::new();
    write_animation_glb(&anim, &frames, 24.0, &mut bytes, std::path::Path::new("plant.glb")).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let prim = gltf.meshes().next().unwrap().primitives().next().unwrap();
    let rest: Vec<glam::Vec3> = prim.reader(|_| Some(blob)).read_positions().unwrap().map(glam::Vec3::from).collect();
    let frame = 5;
    let joint = file_joint_matrices(&gltf, blob, frame);
    let posed = anim.mesh_of(&frames[frame]);
    let nodes = anim.skeleton().vertex_nodes();
    let mut worst = 0.0f32;
    for (v, p) in rest.iter().enumerate() {
        let got = joint[nodes[v] as usize].transform_point3(*p);
        let want = crate::io::UpAxis::Y.to_file(posed.position(v as u32)).as_vec3();
        worst = worst.max((got - want).length());
    }
    assert!(worst < 1e-5, "largest difference {worst}");
    // Upright: the file's y extent is the kernel's z extent.
    let top = anim.rest_mesh().bounds().max.z as f32;
    assert_eq!(rest.iter().map(|p| p.y).fold(f32::MIN, f32::max), top);
}

/// The skinning matrix of every joint of the file's skin at animation key `frame` (glTF 2.0
/// §3.7.3: the joint node's world matrix times its inverse bind matrix), indexed by joint.
pub(super) fn file_joint_matrices(gltf: &gltf::Gltf, blob: &[u8], frame: usize) -> Vec<glam::Mat4> {
    let skin = gltf.skins().next().unwrap();
    let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
    let ibm: Vec<glam::Mat4> = skin
        .reader(|_| Some(blob))
        .read_inverse_bind_matrices()
        .unwrap()
        .map(|m| glam::Mat4::from_cols_array_2d(&m))
        .collect();
    let node_count = gltf.nodes().count();
    let mut local = vec![glam::Mat4::IDENTITY; node_count];
    let (mut t, mut r, mut s) =
        (vec![glam::Vec3::ZERO; node_count], vec![glam::Quat::IDENTITY; node_count], vec![glam::Vec3::ONE; node_count]);
    for ch in gltf.animations().next().unwrap().channels() {
        let i = ch.target().node().index();
        use gltf::animation::util::{ReadOutputs, Rotations};
        match ch.reader(|_| Some(blob)).read_outputs().unwrap() {
            ReadOutputs::Translations(mut v) => t[i] = glam::Vec3::from(v.nth(frame).unwrap()),
            ReadOutputs::Rotations(Rotations::F32(mut v)) => r[i] = glam::Quat::from_array(v.nth(frame).unwrap()),
            ReadOutputs::Scales(mut v) => s[i] = glam::Vec3::from(v.nth(frame).unwrap()),
            _ => panic!("unexpected channel"),
        }
    }
    for i in 0..node_count {
        local[i] = glam::Mat4::from_scale_rotation_translation(s[i], r[i], t[i]);
    }
    let mut world = local.clone();
    let mut stack: Vec<gltf::Node> = gltf.scenes().next().unwrap().nodes().collect();
    while let Some(n) = stack.pop() {
        for c in n.children() {
            world[c.index()] = world[n.index()] * local[c.index()];
            stack.push(c);
        }
    }
    joints.iter().zip(&ibm).map(|(&j, m)| world[j] * *m).collect()
}
