//! The skeleton's nodes as the modifiers see them: the rooted [`Tree`] they walk and the
//! [`NodeState`] each node has (§8.1). Shared by the animation, its modifiers and the skinning.

use crate::math::Vec3;
use crate::polar::Skeleton;

/// A node's state: its position in the global frame and its thickness (the scale of its
/// vertices' offsets from it: 0 collapses its ring on the node, 1 keeps it as modelled).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeState {
    pub position: Vec3,
    pub thickness: f64,
}

/// The rooted tree the modifiers walk: parents, children, depths, a depth-first order (parents
/// before children) and the node pairs of the segments that close cycles.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Tree {
    pub parent: Vec<Option<u32>>,
    pub children: Vec<Vec<u32>>,
    pub depth: Vec<u32>,
    pub order: Vec<u32>,
    pub cycle_pairs: Vec<[u32; 2]>,
}

impl Tree {
    /// The tree of an inferred skeleton, rooted where the skeleton is.
    pub(crate) fn of_skeleton(skeleton: &Skeleton) -> Tree {
        let n = skeleton.node_count();
        let parent: Vec<Option<u32>> = (0..n as u32).map(|i| skeleton.parent(i)).collect();
        let children = (0..n as u32).map(|i| skeleton.children(i).to_vec()).collect();
        let depth = (0..n as u32).map(|i| skeleton.depth(i)).collect();
        let order = skeleton.depth_first_order().to_vec();
        let cycle_pairs = skeleton.cycle_segments().iter().map(|&s| skeleton.segments()[s as usize]).collect();
        Tree { parent, children, depth, order, cycle_pairs }
    }
}
