//! Every pose is a mesh that can be triangulated, saved and drawn: after the modifier stack,
//! each node's state is held at a minimum size.
//!
//! A growth (§9.1) starts with every node collapsed on its root — length and thickness factors
//! 0 — and a node waits for its delay before it grows, so before the end of a growth segments
//! have length 0 and rings thickness 0: loops fall onto their nodes, faces onto points, and the
//! pose has faces whose corners coincide (`triangulate` refuses them, writers emit degenerate
//! triangles, renderers draw nothing). The thesis shows such poses only as they look on screen
//! (Figs. 9.2–9.3), where a collapsed part is simply invisible; a careful implementer who must
//! also *save* every pose holds each part at a small size instead:
//!
//! - a node's thickness is at least [`MIN_SIZE`] (of its modelled ring: thickness 1);
//! - a segment is at least [`MIN_SIZE`] of its modelled length. A shorter one is lengthened
//!   along its posed direction, or, when it has none (length exactly 0), along its modelled
//!   direction turned as its parent's segment is turned; the node's whole subtree moves with
//!   it, so that the rest of the branch keeps its shape.
//!
//! At the start of a growth the plant is therefore its model scaled by [`MIN_SIZE`] about the
//! root (a seed a thousandth of the plant's size), not a point. A state already at least that
//! size is left bit for bit as it is, so the rest pose and the end of a growth are the model
//! exactly. Linear in the node count.

use super::nodes::{NodeState, Tree};
use crate::math::{Quat, Vec3};

/// The smallest size a part of a pose is held at: a node's thickness, and a segment's length
/// as a fraction of its modelled length.
pub const MIN_SIZE: f64 = 1e-3;

/// Holds `states` (posed) at [`MIN_SIZE`] against the modelled node positions `rest` (see the
/// module documentation).
pub(crate) fn hold_minimum_size(tree: &Tree, rest: &[Vec3], states: &mut [NodeState]) {
    let n = states.len();
    // How far each node's subtree has been moved, and how each node's arriving segment is
    // turned from its modelled direction (a collapsed one inherits its parent's turn).
    let mut shift = vec![Vec3::ZERO; n];
    let mut turn = vec![Quat::IDENTITY; n];
    for &i in &tree.order {
        let i = i as usize;
        if states[i].thickness < MIN_SIZE {
            states[i].thickness = MIN_SIZE;
        }
        let Some(p) = tree.parent[i] else { continue };
        let p = p as usize;
        if shift[p] != Vec3::ZERO {
            states[i].position += shift[p];
        }
        shift[i] = shift[p];
        let modelled = rest[i] - rest[p];
        let d = states[i].position - states[p].position;
        let (want, len) = (MIN_SIZE * modelled.length(), d.length());
        turn[i] = match (modelled.try_normalize(), d.try_normalize()) {
            (Some(a), Some(b)) if len > 1e-6 * want => Quat::from_rotation_arc(a, b),
            _ => turn[p],
        };
        if len < want {
            // A collapsed segment's posed direction is rounding noise (a growth's offset × 0
            // subtracted from sums of positions): below a millionth of the minimum it is not
            // trusted, and the modelled direction, turned as the parent's segment is, is used.
            let dir = if len > 1e-6 * want { d / len } else { (turn[p] * modelled).normalize_or_zero() };
            let moved = states[p].position + dir * want;
            shift[i] += moved - states[i].position;
            states[i].position = moved;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain 0 → 1 → 2 along x, each segment of length 1.
    fn chain() -> (Tree, Vec<Vec3>) {
        let tree = Tree {
            parent: vec![None, Some(0), Some(1)],
            children: vec![vec![1], vec![2], vec![]],
            depth: vec![0, 1, 2],
            order: vec![0, 1, 2],
            cycle_pairs: vec![],
        };
        (tree, vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X])
    }

    #[test]
    fn a_collapsed_chain_becomes_the_model_scaled_by_the_minimum() {
        let (tree, rest) = chain();
        let mut s = vec![NodeState { position: Vec3::new(5.0, 0.0, 0.0), thickness: 0.0 }; 3];
        hold_minimum_size(&tree, &rest, &mut s);
        for (i, st) in s.iter().enumerate() {
            let want = Vec3::new(5.0, 0.0, 0.0) + MIN_SIZE * rest[i];
            assert!(st.position.distance(want) < 1e-15, "node {i}: {} not {want}", st.position);
            assert_eq!(st.thickness, MIN_SIZE);
        }
    }

    #[test]
    fn a_short_segment_keeps_its_direction_and_moves_its_subtree() {
        let (tree, rest) = chain();
        // Node 1 a hair above node 0, node 2 a full segment beyond node 1.
        let mut s = vec![
            NodeState { position: Vec3::ZERO, thickness: 1.0 },
            NodeState { position: Vec3::new(0.0, 0.0, 1e-6), thickness: 1.0 },
            NodeState { position: Vec3::new(1.0, 0.0, 1e-6), thickness: 1.0 },
        ];
        hold_minimum_size(&tree, &rest, &mut s);
        assert!(s[1].position.distance(Vec3::new(0.0, 0.0, MIN_SIZE)) < 1e-15);
        assert!(s[2].position.distance(Vec3::new(1.0, 0.0, MIN_SIZE)) < 1e-15, "the subtree moved along");
    }

    #[test]
    fn states_at_least_the_minimum_are_kept_bit_for_bit() {
        let (tree, rest) = chain();
        let before: Vec<NodeState> = rest.iter().map(|&position| NodeState { position, thickness: 0.7 }).collect();
        let mut s = before.clone();
        hold_minimum_size(&tree, &rest, &mut s);
        assert_eq!(s, before);
    }

    #[test]
    fn a_collapsed_segment_s_rounding_noise_is_not_taken_for_a_direction() {
        let (tree, rest) = chain();
        // Node 1 off node 0 by 1e-17 sideways (what x + 0 · offset leaves): it leaves along +x.
        let mut s = vec![
            NodeState { position: Vec3::ZERO, thickness: 0.0 },
            NodeState { position: Vec3::new(0.0, 1e-17, 0.0), thickness: 0.0 },
            NodeState { position: Vec3::new(0.0, 1e-17, 0.0), thickness: 0.0 },
        ];
        hold_minimum_size(&tree, &rest, &mut s);
        assert!(s[1].position.distance(MIN_SIZE * Vec3::X) < 1e-15, "{}", s[1].position);
        assert!(s[2].position.distance(2.0 * MIN_SIZE * Vec3::X) < 1e-15, "{}", s[2].position);
    }

    #[test]
    fn a_collapsed_segment_follows_its_parents_turn() {
        let (tree, rest) = chain();
        // Segment 0 → 1 turned to +y; node 2 collapsed on node 1: it leaves along +y too.
        let mut s = vec![
            NodeState { position: Vec3::ZERO, thickness: 1.0 },
            NodeState { position: Vec3::Y, thickness: 1.0 },
            NodeState { position: Vec3::Y, thickness: 1.0 },
        ];
        hold_minimum_size(&tree, &rest, &mut s);
        assert!(s[2].position.distance(Vec3::new(0.0, 1.0 + MIN_SIZE, 0.0)) < 1e-15, "{}", s[2].position);
    }
}
