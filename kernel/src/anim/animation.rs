//! The animation of a polar mesh (seed 004, §8.1): the skeleton inferred from the mesh and
//! reduced to a tree at a chosen root; per node a state (position, thickness); a stack of
//! modifiers, each applied to every node and receiving the states the previous one produced;
//! and the skinning that turns node states into vertex positions.

use super::gravity::GravityState;
use super::minimum_size::hold_minimum_size;
use super::nodes::Tree;
use super::skinning::{joint_poses, skin, skin_blended};
use super::smooth::Influences;
use super::{AnimError, Gravity, Growth, JointPose, NodeState, Skinning};
use crate::math::Vec3;
use crate::mesh::Mesh;
use crate::polar::{PolarMesh, Skeleton};

/// One entry of the modifier stack.
#[derive(Clone, Debug, PartialEq)]
pub enum Modifier {
    /// Growth from the root (§9.1); time-pure.
    Growth(Growth),
    /// Gravity (§9.2); simulated step by step.
    Gravity(Gravity),
    /// A modifier evaluated by the caller (e.g. a script closure), identified by the caller's
    /// number; time-pure.
    Custom(usize),
}

impl Modifier {
    fn kind(&self) -> &'static str {
        match self {
            Modifier::Growth(_) => "growth",
            Modifier::Gravity(_) => "gravity",
            Modifier::Custom(_) => "custom",
        }
    }
}

/// A caller-evaluated modifier: `(caller id, node, t, state in)` → state out, or a message.
pub type CustomModifier<'a> = dyn FnMut(usize, u32, f64, NodeState) -> Result<NodeState, String> + 'a;

/// Simulation steps per time unit when a simulated stack is posed at a time
/// ([`Animation::states_at`]): 24, the frames per second `save` writes by default.
pub const POSE_STEPS_PER_UNIT: f64 = 24.0;

/// The most simulation steps a pose at one time may take (see [`Animation::states_at`]).
pub const MAX_POSE_STEPS: usize = 100_000;

/// A polar mesh ready to be posed.
#[derive(Clone, Debug)]
pub struct Animation {
    rest: Mesh,
    skeleton: Skeleton,
    tree: Tree,
    skinning: Skinning,
    modifiers: Vec<Modifier>,
    /// The joints of each rest vertex when they are more than its node (a subdivided rest
    /// mesh, see [`Animation::subdivided`]); `None`: each vertex follows its node alone.
    influences: Option<Influences>,
}

impl Animation {
    /// Infers the skeleton of `pm` (§7.1) rooted at the node of vertex `root` (default: the
    /// first pole's node) and binds every vertex to its node.
    ///
    /// # Errors
    /// [`AnimError::NoSuchElement`] for a root vertex not on the mesh; [`AnimError::Skeleton`]
    /// when inference fails.
    pub fn new(pm: &PolarMesh, root: Option<u32>, skinning: Skinning) -> Result<Animation, AnimError> {
        let nv = pm.mesh().vertex_count();
        if let Some(r) = root {
            if r as usize >= nv {
                return Err(AnimError::NoSuchElement { what: "vertex", id: i64::from(r), count: nv });
            }
        }
        let skeleton = pm.skeleton(root).map_err(|e| AnimError::Skeleton(e.to_string()))?;
        let tree = Tree::of_skeleton(&skeleton);
        // The rest mesh carries the feature colours (appendix B.1.3), so poses and the
        // animated file show the structure as the polar mesh's own file does.
        Ok(Animation { rest: pm.to_colored_mesh(), skeleton, tree, skinning, modifiers: Vec::new(), influences: None })
    }

    /// The node of vertex `v`'s binding, to pick a root by a face: see [`Skeleton::node_of`].
    #[must_use]
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// The mesh as modelled (the rest pose), with the polar mesh's feature colours.
    #[must_use]
    pub fn rest_mesh(&self) -> &Mesh {
        &self.rest
    }

    /// The joints that move each rest vertex, with their weights: the vertex's node alone
    /// unless the rest mesh was subdivided ([`Animation::subdivided`]).
    #[must_use]
    pub fn influences(&self) -> Influences {
        self.influences.clone().unwrap_or_else(|| Influences::single(self.skeleton.vertex_nodes()))
    }

    /// Whether the rest mesh is a subdivision of the polar mesh ([`Animation::subdivided`]).
    #[must_use]
    pub fn is_subdivided(&self) -> bool {
        self.influences.is_some()
    }

    /// This animation with another rest mesh and its influences (one per vertex).
    pub(super) fn with_rest(&self, rest: Mesh, influences: Influences) -> Animation {
        debug_assert_eq!(rest.vertex_count(), influences.joints.len());
        Animation { rest, influences: Some(influences), ..self.clone() }
    }

    /// The children of node `i` in the animation's tree.
    pub(super) fn children(&self, i: u32) -> &[u32] {
        &self.tree.children[i as usize]
    }

    /// The skinning mode.
    #[must_use]
    pub fn skinning(&self) -> Skinning {
        self.skinning
    }

    /// The modifier stack, in order.
    #[must_use]
    pub fn modifiers(&self) -> &[Modifier] {
        &self.modifiers
    }

    /// The parent of node `i` in the animation's tree.
    #[must_use]
    pub fn parent(&self, i: u32) -> Option<u32> {
        self.tree.parent[i as usize]
    }

    /// The depth of node `i` (segments from the root).
    #[must_use]
    pub fn depth(&self, i: u32) -> u32 {
        self.tree.depth[i as usize]
    }

    /// The nodes, parents before children.
    #[must_use]
    pub fn order(&self) -> &[u32] {
        &self.tree.order
    }

    /// The deepest node's depth.
    #[must_use]
    pub fn max_depth(&self) -> u32 {
        self.tree.depth.iter().copied().max().unwrap_or(0)
    }

    /// The time at which every growth modifier has finished (0 without one).
    #[must_use]
    pub fn duration(&self) -> f64 {
        let d = self.max_depth();
        self.modifiers
            .iter()
            .filter_map(|m| if let Modifier::Growth(g) = m { Some(g.end(d)) } else { None })
            .fold(0.0, f64::max)
    }

    /// Appends `modifier` to the stack after checking its parameters.
    ///
    /// # Errors
    /// [`AnimError::InvalidParameter`]; the stack is unchanged.
    pub fn add(&mut self, modifier: Modifier) -> Result<(), AnimError> {
        match &modifier {
            Modifier::Growth(g) => g.validate()?,
            Modifier::Gravity(g) => g.validate()?,
            Modifier::Custom(_) => {}
        }
        self.modifiers.push(modifier);
        Ok(())
    }

    /// The rest state of every node: its inferred position, thickness 1.
    #[must_use]
    pub fn rest_states(&self) -> Vec<NodeState> {
        self.skeleton.positions().iter().map(|&position| NodeState { position, thickness: 1.0 }).collect()
    }

    /// Node states at time `t`. A stack of time-pure modifiers (growth, custom) is evaluated
    /// at `t`; a stack with a simulated modifier (gravity) is stepped from rest at time 0 to
    /// `t` in equal steps of at most 1/[`POSE_STEPS_PER_UNIT`] (the frames `save` writes at its
    /// default 24 fps, so a pose at a frame's time is that frame). Every part is held at
    /// [`super::MIN_SIZE`] (see `minimum_size`), so the pose is a valid mesh at every time.
    ///
    /// # Errors
    /// A custom modifier's error; [`AnimError::BadState`] for a NaN or a negative thickness;
    /// [`AnimError::InvalidParameter`] naming `t` for a time that is not finite or, with a
    /// simulated stack, needs more than [`MAX_POSE_STEPS`] steps.
    pub fn states_at(&self, t: f64, custom: &mut CustomModifier<'_>) -> Result<Vec<NodeState>, AnimError> {
        if !t.is_finite() {
            return Err(AnimError::InvalidParameter { name: "t", reason: format!("must be a finite time, got {t}") });
        }
        if !self.modifiers.iter().any(|m| matches!(m, Modifier::Gravity(_))) {
            return self.run_stack(t, 0.0, &mut [], custom);
        }
        let steps = (t.max(0.0) * POSE_STEPS_PER_UNIT).ceil();
        if steps > MAX_POSE_STEPS as f64 {
            return Err(AnimError::InvalidParameter {
                name: "t",
                reason: format!(
                    "{} needs {} simulation steps from rest (gravity is stepped {POSE_STEPS_PER_UNIT} times per \
                     time unit), over the cap of {MAX_POSE_STEPS}",
                    crate::math::fmt_num(t),
                    crate::math::fmt_num(steps)
                ),
            });
        }
        let steps = steps as usize;
        let dt = if steps == 0 { 1.0 / POSE_STEPS_PER_UNIT } else { t / steps as f64 };
        let mut frames = self.frame_states(steps + 1, dt, custom)?;
        Ok(frames.pop().unwrap_or_default())
    }

    /// The posed mesh at time `t` (vertex ids kept), for any stack: see
    /// [`Animation::states_at`].
    ///
    /// # Errors
    /// As [`Animation::states_at`].
    pub fn pose(&self, t: f64, custom: &mut CustomModifier<'_>) -> Result<Mesh, AnimError> {
        let states = self.states_at(t, custom)?;
        Ok(self.mesh_of(&states))
    }

    /// Node states of `count` frames at times 0, dt, 2·dt, …: the simulated modifiers step once
    /// per frame (starting at rest on their input), the others are evaluated at each time.
    ///
    /// # Errors
    /// [`AnimError::InvalidParameter`] for a `dt` that is not finite and > 0; as
    /// [`Animation::states_at`] otherwise.
    pub fn frame_states(
        &self,
        count: usize,
        dt: f64,
        custom: &mut CustomModifier<'_>,
    ) -> Result<Vec<Vec<NodeState>>, AnimError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(AnimError::InvalidParameter {
                name: "dt",
                reason: format!("must be a finite number > 0, got {dt}"),
            });
        }
        let mut sims = vec![GravityState::default(); self.modifiers.len()];
        let mut out = Vec::with_capacity(count);
        for i in 0..count {
            let t = i as f64 * dt;
            // The first frame is the start: the simulation takes its first step after it.
            let step = if i == 0 { 0.0 } else { dt };
            out.push(self.run_stack(t, step, &mut sims, custom)?);
        }
        Ok(out)
    }

    /// The posed meshes of [`Animation::frame_states`].
    ///
    /// # Errors
    /// As [`Animation::frame_states`].
    pub fn frames(&self, count: usize, dt: f64, custom: &mut CustomModifier<'_>) -> Result<Vec<Mesh>, AnimError> {
        Ok(self.frame_states(count, dt, custom)?.iter().map(|s| self.mesh_of(s)).collect())
    }

    /// The joint transforms for node `states` under this animation's skinning.
    #[must_use]
    pub fn joint_poses(&self, states: &[NodeState]) -> Vec<JointPose> {
        joint_poses(self.skinning, &self.tree, self.skeleton.positions(), states)
    }

    /// The vertex positions (indexed by vertex id) moved by the joints of `states`. Linear in
    /// the vertex count; one rotation per vertex.
    #[must_use]
    pub fn skinned_positions(&self, states: &[NodeState]) -> Vec<Vec3> {
        let poses = self.joint_poses(states);
        match &self.influences {
            None => skin(self.rest.positions(), self.skeleton.vertex_nodes(), self.skeleton.positions(), &poses),
            Some(i) => skin_blended(self.rest.positions(), i, self.skeleton.positions(), &poses),
        }
    }

    /// The rest mesh with its vertices moved by the joints of `states`.
    #[must_use]
    pub fn mesh_of(&self, states: &[NodeState]) -> Mesh {
        let positions = self.skinned_positions(states);
        let mut mesh = self.rest.clone();
        mesh.set_positions(positions).expect("skinned positions are checked finite by the modifier stack");
        mesh
    }

    /// Runs the stack at time `t`; `step` is the simulation's time step this frame (0: none),
    /// `sims` the simulated modifiers' states (empty: none may be simulated).
    fn run_stack(
        &self,
        t: f64,
        step: f64,
        sims: &mut [GravityState],
        custom: &mut CustomModifier<'_>,
    ) -> Result<Vec<NodeState>, AnimError> {
        let mut states = self.rest_states();
        for (index, m) in self.modifiers.iter().enumerate() {
            match m {
                Modifier::Growth(g) => g.apply(&self.tree, t, &mut states),
                Modifier::Gravity(g) => {
                    let sim = &mut sims[index];
                    if step > 0.0 {
                        g.apply(&self.tree, step, sim, &mut states)?;
                    } else {
                        // The first frame: the simulation starts at rest on its input.
                        g.apply(&self.tree, 0.0, sim, &mut states)?;
                    }
                }
                Modifier::Custom(id) => {
                    for &n in &self.tree.order {
                        let s = states[n as usize];
                        states[n as usize] =
                            custom(*id, n, t, s).map_err(|message| AnimError::Custom { index, node: n, message })?;
                    }
                }
            }
            if let Some((node, s)) = states
                .iter()
                .enumerate()
                .find(|(_, s)| !s.position.is_finite() || !s.thickness.is_finite() || s.thickness < 0.0)
            {
                return Err(AnimError::BadState {
                    index,
                    kind: m.kind(),
                    node: node as u32,
                    what: format!(
                        "position {} and thickness {} (finite, thickness ≥ 0 needed)",
                        s.position, s.thickness
                    ),
                });
            }
        }
        hold_minimum_size(&self.tree, self.skeleton.positions(), &mut states);
        Ok(states)
    }
}
