//! Skinning (seed 004, §7.3): how vertices follow the posed skeleton.
//!
//! Every node has a joint transform x ↦ p + s·R(x − p₀): its posed position p, its thickness s
//! and a rotation R, about its rest position p₀. A vertex bound to the node (§7.1's binding)
//! is moved by that transform.
//! - [`Skinning::Simple`]: R turns the node's rest segment (from its parent) into the posed one —
//!   "every vertex is attached to exactly one joint" (the thesis's simple skinning).
//! - [`Skinning::Smooth`]: R is halfway (slerp ½) between the rotation of the segment arriving at
//!   the node and the mean rotation of the segments leaving it, so the ring at a bent joint
//!   lies in the bisecting plane of the two segments — the relative-angle blend of Fig. 7.5,
//!   which keeps the elbow from collapsing. Both reproduce the rest pose bit for bit.

use super::nodes::{NodeState, Tree};
use crate::math::{Quat, Vec3};

/// How vertices follow the skeleton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Skinning {
    /// One joint per vertex, turned with the segment that arrives at it.
    Simple,
    /// The joint turned halfway between its arriving and leaving segments.
    #[default]
    Smooth,
}

/// The world transform of one node's joint: x ↦ `translation` + `scale`·`rotation`(x − rest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointPose {
    /// The posed node position.
    pub translation: Vec3,
    /// The joint's rotation.
    pub rotation: Quat,
    /// The node's thickness.
    pub scale: f64,
}

/// The rotation turning `from` into `to` (identity when either is degenerate).
fn arc(from: Vec3, to: Vec3) -> Option<Quat> {
    let (a, b) = (from.try_normalize()?, to.try_normalize()?);
    if a == b {
        return Some(Quat::IDENTITY);
    }
    Some(Quat::from_rotation_arc(a, b))
}

/// The joint poses of every node for `states` (posed) against `rest` (rest node positions).
pub(crate) fn joint_poses(skinning: Skinning, tree: &Tree, rest: &[Vec3], states: &[NodeState]) -> Vec<JointPose> {
    let n = states.len();
    // The rotation of each node's arriving segment; a collapsed segment inherits its parent's.
    let mut segment = vec![Quat::IDENTITY; n];
    for &i in &tree.order {
        let i = i as usize;
        if let Some(p) = tree.parent[i] {
            let p = p as usize;
            segment[i] = arc(rest[i] - rest[p], states[i].position - states[p].position).unwrap_or(segment[p]);
        }
    }
    (0..n)
        .map(|i| {
            let arriving = if tree.parent[i].is_some() { segment[i] } else { Quat::IDENTITY };
            let rotation = match skinning {
                Skinning::Simple => arriving,
                Skinning::Smooth => {
                    let children = &tree.children[i];
                    if children.is_empty() {
                        arriving
                    } else {
                        // The mean of the leaving rotations, signs aligned with the arriving one.
                        let mut sum = Quat::from_xyzw(0.0, 0.0, 0.0, 0.0);
                        for &c in children {
                            let q = segment[c as usize];
                            sum += if q.dot(arriving) < 0.0 { -q } else { q };
                        }
                        let len = sum.length();
                        let leaving = if len > 1e-12 { sum / len } else { arriving };
                        if leaving == arriving {
                            arriving
                        } else {
                            arriving.slerp(leaving, 0.5)
                        }
                    }
                }
            };
            JointPose { translation: states[i].position, rotation, scale: states[i].thickness }
        })
        .collect()
}

/// Vertex positions: each rest vertex moved by its node's joint. Written as
/// v + (p − p₀) + (s·R(o) − o) with o = v − p₀, which is exactly v at rest.
pub(crate) fn skin(rest_vertices: &[Vec3], vertex_node: &[u32], rest_nodes: &[Vec3], poses: &[JointPose]) -> Vec<Vec3> {
    rest_vertices
        .iter()
        .zip(vertex_node)
        .map(|(&v, &node)| {
            let j = &poses[node as usize];
            let p0 = rest_nodes[node as usize];
            let o = v - p0;
            v + (j.translation - p0) + (j.scale * (j.rotation * o) - o)
        })
        .collect()
}

/// Vertex positions by linear blend skinning: each rest vertex moved by the weighted sum of its
/// joints' transforms, Σ wⱼ (tⱼ + sⱼ·Rⱼ(v − p₀ⱼ)) — what a glTF viewer computes from the
/// skin — written per joint as v + (tⱼ − p₀ⱼ) + (sⱼ·Rⱼ(oⱼ) − oⱼ) so that the rest pose gives v
/// exactly when the weights sum to 1.
pub(crate) fn skin_blended(
    rest_vertices: &[Vec3],
    influences: &super::smooth::Influences,
    rest_nodes: &[Vec3],
    poses: &[JointPose],
) -> Vec<Vec3> {
    rest_vertices
        .iter()
        .zip(influences.joints.iter().zip(&influences.weights))
        .map(|(&v, (joints, weights))| {
            let mut shift = Vec3::ZERO;
            for (&n, &w) in joints.iter().zip(weights) {
                if w == 0.0 {
                    continue;
                }
                let j = &poses[n as usize];
                let p0 = rest_nodes[n as usize];
                let o = v - p0;
                shift += ((j.translation - p0) + (j.scale * (j.rotation * o) - o)) * w;
            }
            v + shift
        })
        .collect()
}
