//! A rigged, animated glTF 2.0 file of an [`Animation`] (seed 004 ch. 14's wish to export
//! to standard tools): the rest mesh skinned to the skeleton, one joint per node, and one
//! animation with a key per frame.
//!
//! Joints. Node `i` is the glTF node `node i`, a child of its tree parent's; the skin's joints are
//! these nodes (as many as skeleton nodes), each with the inverse bind matrix T(−rest position),
//! and every vertex has weight 1 on its node's joint — or, for a subdivided rest mesh, up to four
//! joints with the weights the subdivision carried ([`Animation::influences`]) — which moves it
//! as [`Animation::mesh_of`] does. A joint's world transform is T(p)·R·S(thickness); glTF children inherit their parent's
//! scale, so each local transform divides it out (translation and scale over the parent's
//! thickness). A thickness of exactly 0 (a grown plant's first frame) is written as 1e-6, so
//! that the division stays finite: the collapsed rings are a millionth of their size instead of
//! points.
//!
//! Axes. glTF is Y-up: the rest mesh is converted by the mesh writer, and every joint
//! translation, rotation and inverse bind matrix here by the same change of axes
//! ([`UpAxis::Y`]), so the animated file shows what [`Animation::mesh_of`] gives, standing up.

use std::io::Write;
use std::path::Path;

use gltf::json;
use json::validation::{Checked::Valid, USize64};

use super::{Animation, NodeState};
use crate::io::gltf::{accessor, document, internal, push_f32s, push_view, write_glb_document};
use crate::io::{IoError, UpAxis};
use crate::math::{Quat, Vec3};

/// The smallest joint scale written (see the module documentation).
const MIN_SCALE: f64 = 1e-6;

fn push_u16s(out: &mut Vec<u8>, values: &[u16]) {
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

/// A kernel point or direction in glTF's axes, in f32.
fn f3(v: Vec3) -> [f32; 3] {
    let v = UpAxis::Y.to_file(v);
    [v.x as f32, v.y as f32, v.z as f32]
}

/// A kernel rotation in glTF's axes, in f32.
fn q4(q: Quat) -> [f32; 4] {
    let q = UpAxis::Y.rotation_to_file(q.normalize());
    [q.x as f32, q.y as f32, q.z as f32, q.w as f32]
}

/// Writes `anim` as a GLB with the node states of `frames` (one key each, `fps` keys a second)
/// to `out`. `path` is only named in errors.
///
/// # Errors
/// [`IoError::Internal`] for more than 65,535 skeleton nodes (glTF joint indices are 16-bit
/// here) or an empty frame list; the mesh writer's errors.
pub fn write_animation_glb<W: Write>(
    anim: &Animation,
    frames: &[Vec<NodeState>],
    fps: f64,
    out: &mut W,
    path: &Path,
) -> Result<(), IoError> {
    let sk = anim.skeleton();
    let n = sk.node_count();
    if n > usize::from(u16::MAX) {
        return Err(internal(path, &format!("{n} skeleton nodes: at most 65535 joints can be written")));
    }
    if frames.is_empty() {
        return Err(internal(path, "an animation needs at least one frame"));
    }
    let (mut root, bin) = document(anim.rest_mesh(), None, path)?;
    let mut bin = bin.unwrap_or_default();
    let nv = anim.rest_mesh().vertex_count();
    let rest = sk.positions();

    // Skin attributes: each vertex's joints and weights (its node alone, weight 1, unless the
    // rest mesh was subdivided).
    let influences = anim.influences();
    let joints: Vec<u16> = influences.joints.iter().flat_map(|j| j.map(|x| x as u16)).collect();
    let view = push_view(&mut root, &mut bin, Some(json::buffer::Target::ArrayBuffer), |b| push_u16s(b, &joints));
    let joints_acc =
        root.push(accessor(view, nv, json::accessor::ComponentType::U16, json::accessor::Type::Vec4, None));
    let weights: Vec<f32> = influences.weights.iter().flat_map(|w| w.map(|x| x as f32)).collect();
    let view = push_view(&mut root, &mut bin, Some(json::buffer::Target::ArrayBuffer), |b| push_f32s(b, &weights));
    let weights_acc =
        root.push(accessor(view, nv, json::accessor::ComponentType::F32, json::accessor::Type::Vec4, None));
    if let Some(prim) = root.meshes.first_mut().and_then(|m| m.primitives.first_mut()) {
        prim.attributes.insert(Valid(json::mesh::Semantic::Joints(0)), joints_acc);
        prim.attributes.insert(Valid(json::mesh::Semantic::Weights(0)), weights_acc);
    }

    // One glTF node per skeleton node (index base + i), children under their tree parent.
    let base = root.nodes.len() as u32;
    let node_of = |i: u32| json::Index::<json::Node>::new(base + i);
    for i in 0..n as u32 {
        let local = match anim.parent(i) {
            Some(p) => rest[i as usize] - rest[p as usize],
            None => rest[i as usize],
        };
        let children: Vec<_> =
            sk.children(i).iter().filter(|&&c| anim.parent(c) == Some(i)).map(|&c| node_of(c)).collect();
        root.push(json::Node {
            name: Some(format!("node {i}")),
            translation: Some(f3(local)),
            children: if children.is_empty() { None } else { Some(children) },
            ..Default::default()
        });
    }
    let ibm: Vec<f32> = rest
        .iter()
        .flat_map(|p| {
            let m = crate::math::Mat4::from_translation(-UpAxis::Y.to_file(*p));
            m.to_cols_array().map(|x| x as f32)
        })
        .collect();
    let view = push_view(&mut root, &mut bin, None, |b| push_f32s(b, &ibm));
    let ibm_acc = root.push(accessor(view, n, json::accessor::ComponentType::F32, json::accessor::Type::Mat4, None));
    let roots: Vec<u32> = (0..n as u32).filter(|&i| anim.parent(i).is_none()).collect();
    let skin = root.push(json::Skin {
        inverse_bind_matrices: Some(ibm_acc),
        joints: (0..n as u32).map(node_of).collect(),
        skeleton: roots.first().map(|&r| node_of(r)),
        name: Some("skeleton".into()),
        extensions: None,
        extras: None,
    });
    if let Some(mesh_node) = root.nodes.first_mut() {
        mesh_node.skin = Some(skin);
    }
    if let Some(scene) = root.scenes.first_mut() {
        scene.nodes.extend(roots.iter().map(|&r| node_of(r)));
    }

    // The animation: per frame the local transform of every joint.
    let count = frames.len();
    let times: Vec<f32> = (0..count).map(|k| (k as f64 / fps) as f32).collect();
    let view = push_view(&mut root, &mut bin, None, |b| push_f32s(b, &times));
    let mut time_acc = accessor(view, count, json::accessor::ComponentType::F32, json::accessor::Type::Scalar, None);
    time_acc.min = Some(json::Value::from(vec![times[0]]));
    time_acc.max = Some(json::Value::from(vec![times[count - 1]]));
    let input = root.push(time_acc);
    let mut translations = vec![Vec::with_capacity(count * 3); n];
    let mut rotations = vec![Vec::with_capacity(count * 4); n];
    let mut scales = vec![Vec::with_capacity(count * 3); n];
    let scale_of = |s: f64| s.max(MIN_SCALE);
    for states in frames {
        let poses = anim.joint_poses(states);
        for i in 0..n {
            let pose = &poses[i];
            let (t, r, s) = match anim.parent(i as u32) {
                Some(p) => {
                    let parent = &poses[p as usize];
                    let inv = parent.rotation.inverse();
                    let ps = scale_of(parent.scale);
                    (inv * (pose.translation - parent.translation) / ps, inv * pose.rotation, scale_of(pose.scale) / ps)
                }
                None => (pose.translation, pose.rotation, scale_of(pose.scale)),
            };
            translations[i].extend_from_slice(&f3(t));
            rotations[i].extend_from_slice(&q4(r));
            scales[i].extend_from_slice(&[s as f32; 3]);
        }
    }
    let mut channels = Vec::new();
    let mut samplers = Vec::new();
    let mut add = |root: &mut json::Root,
                   bin: &mut Vec<u8>,
                   node: json::Index<json::Node>,
                   property: json::animation::Property,
                   values: &[f32],
                   type_: json::accessor::Type| {
        let view = push_view(root, bin, None, |b| push_f32s(b, values));
        let output = root.push(accessor(view, count, json::accessor::ComponentType::F32, type_, None));
        samplers.push(json::animation::Sampler {
            input,
            interpolation: Valid(json::animation::Interpolation::Linear),
            output,
            extensions: None,
            extras: None,
        });
        channels.push(json::animation::Channel {
            sampler: json::Index::new(samplers.len() as u32 - 1),
            target: json::animation::Target { node, path: Valid(property), extensions: None, extras: None },
            extensions: None,
            extras: None,
        });
    };
    use json::accessor::Type;
    use json::animation::Property;
    for i in 0..n {
        let i32_ = i as u32;
        add(&mut root, &mut bin, node_of(i32_), Property::Translation, &translations[i], Type::Vec3);
        add(&mut root, &mut bin, node_of(i32_), Property::Rotation, &rotations[i], Type::Vec4);
        add(&mut root, &mut bin, node_of(i32_), Property::Scale, &scales[i], Type::Vec3);
    }
    root.push(json::Animation { channels, samplers, name: Some("blocksmith".into()), extensions: None, extras: None });

    bin.resize(bin.len().next_multiple_of(4), 0);
    if let Some(b) = root.buffers.first_mut() {
        b.byte_length = USize64::from(bin.len());
    }
    write_glb_document(&root, Some(bin), out, path)
}
