//! Skeleton-driven animation of polar meshes (seed 004, part II): the inferred skeleton as a
//! rooted tree of nodes with a position and a thickness each, vertices in skeleton coordinates
//! (§7.2), simple and smooth skinning (§7.3), and a stack of modifiers applied to every node in
//! order (§8.1) — growth (§9.1), gravity (§9.2) and modifiers supplied by the caller.
//!
//! - [`Animation`]: the rest state, the modifier stack, [`Animation::pose`] at any time (a
//!   simulated stack stepped from rest) and [`Animation::frames`];
//! - `minimum_size`: every pose held at a minimum size, so that it is a valid mesh;
//! - `nodes`: the rooted node tree the modifiers walk and each node's [`NodeState`];
//! - `skinning`: joint transforms and vertex positions from node states;
//! - `smooth`: the rest mesh subdivided with pointed tips, and the skin carried through it;
//! - `growth`, `gravity`: the thesis's two behaviours;
//! - `export`: a glTF 2.0 file with the skeleton as joints, skin weights and one animation.

mod animation;
mod error;
mod export;
mod gravity;
mod growth;
mod minimum_size;
mod nodes;
mod skinning;
mod smooth;

pub use animation::{Animation, CustomModifier, Modifier, MAX_POSE_STEPS, POSE_STEPS_PER_UNIT};
pub use error::AnimError;
pub use export::write_animation_glb;
pub use gravity::Gravity;
pub use growth::{Curve, Growth};
pub use minimum_size::MIN_SIZE;
pub use nodes::NodeState;
pub use skinning::{JointPose, Skinning};
pub use smooth::{subdivide_polar_mesh, Influences, MAX_INFLUENCES, MAX_LEVELS};

#[cfg(test)]
mod tests;
