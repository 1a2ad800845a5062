//! Gravity (seed 004, §9.2): each node follows Newton's laws by a Verlet step — a constant
//! gravity, a Hooke force pulling its offset from its parent back to the nominal one, and the
//! velocity it had, damped by the drag (Eqs. 9.1–9.2) — then Jakobsen's relaxation ("Advanced
//! Character Physics") restores the length of every tree segment; the root is fixed.
//!
//! Two readings of the thesis's text, chosen as a careful implementer would: the Hooke force
//! opposes the displacement (−kΔl; the text writes +kΔl with Δl = current − nominal, which would
//! push the node further away), and the drag multiplies the inherited velocity (0.1 keeps a
//! tenth of it), so it must lie in (0, 1]. The relaxation projects each segment in depth-first
//! order onto its nominal length, moving only the child end: the parent's end has just been
//! placed (or is the fixed root), which makes one sweep exact for a tree; the further iterations
//! settle the segments that close cycles.

use super::nodes::{NodeState, Tree};
use super::AnimError;
use crate::math::{fmt_num, Vec3};

/// The gravity modifier's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gravity {
    /// Acceleration of gravity (length units per time²). Default 9.81.
    pub g: f64,
    /// The direction of gravity (normalised). Default −z.
    pub down: Vec3,
    /// Stiffness of the Hooke force towards the nominal offset. Default 20.
    pub k: f64,
    /// The share of the velocity a node keeps from one step to the next, in (0, 1]. Default 0.5.
    pub drag: f64,
    /// Relaxation sweeps per step. Default 10, as in the thesis.
    pub iterations: u32,
    /// The simulation time step; `None` steps once per frame. A frame longer than `dt` takes
    /// several steps.
    pub dt: Option<f64>,
}

impl Default for Gravity {
    fn default() -> Self {
        Gravity { g: 9.81, down: Vec3::NEG_Z, k: 20.0, drag: 0.5, iterations: 10, dt: None }
    }
}

/// The most simulation steps one frame may take (`frame dt / dt`): more is refused up front.
pub const MAX_SUBSTEPS: u64 = 100_000;

/// The simulated positions of every node: the current and the previous step's.
#[derive(Clone, Debug, Default)]
pub(crate) struct GravityState {
    position: Vec<Vec3>,
    previous: Vec<Vec3>,
}

impl Gravity {
    /// Checks the parameters.
    ///
    /// # Errors
    /// [`AnimError::InvalidParameter`] naming the parameter: `g`, `k` finite (k ≥ 0), `down` a
    /// finite non-zero vector, `drag` in (0, 1], `dt` finite and > 0, `iterations` ≤ 1000.
    pub fn validate(&self) -> Result<(), AnimError> {
        let bad = |name, reason: String| Err(AnimError::InvalidParameter { name, reason });
        if !self.g.is_finite() {
            return bad("g", format!("must be finite, got {}", self.g));
        }
        if !(self.k.is_finite() && self.k >= 0.0) {
            return bad("k", format!("must be a finite number ≥ 0, got {}", self.k));
        }
        if !(self.drag > 0.0 && self.drag <= 1.0) {
            return bad("drag", format!("must lie in (0, 1], got {}", self.drag));
        }
        if !(self.down.is_finite() && self.down.length() > 0.0) {
            return bad("down", format!("must be a finite non-zero vector, got {}", self.down));
        }
        if let Some(dt) = self.dt {
            if !(dt.is_finite() && dt > 0.0) {
                return bad("dt", format!("must be a finite number > 0, got {dt}"));
            }
        }
        if self.iterations > 1000 {
            return bad("iterations", format!("must be at most 1000, got {}", self.iterations));
        }
        Ok(())
    }

    /// Advances `state` by a frame of length `frame_dt` towards the nominal `states` (the
    /// output of the modifiers before this one), then writes the simulated positions into
    /// `states`. The first call starts at rest on the nominal positions.
    ///
    /// # Errors
    /// [`AnimError::InvalidParameter`] naming `dt` when the frame would take more than
    /// [`MAX_SUBSTEPS`] steps (refused before stepping); [`AnimError::Limit`] when the
    /// cancellation token stops the simulation (checked every step).
    pub(crate) fn apply(
        &self,
        tree: &Tree,
        frame_dt: f64,
        state: &mut GravityState,
        states: &mut [NodeState],
    ) -> Result<(), AnimError> {
        let steps = match self.dt {
            Some(dt) => (frame_dt / dt).ceil().max(1.0),
            None => 1.0,
        };
        if steps > MAX_SUBSTEPS as f64 {
            return Err(AnimError::InvalidParameter {
                name: "dt",
                reason: format!(
                    "{} makes {} simulation steps per frame of {}, over the cap of {MAX_SUBSTEPS}: use a larger `dt`",
                    fmt_num(self.dt.unwrap_or(frame_dt)),
                    fmt_num(steps),
                    fmt_num(frame_dt)
                ),
            });
        }
        let steps = steps as usize;
        let nominal: Vec<Vec3> = states.iter().map(|s| s.position).collect();
        if state.position.len() != nominal.len() {
            state.position.clone_from(&nominal);
            state.previous.clone_from(&nominal);
        }
        let h = frame_dt / steps as f64;
        let down = self.down.normalize();
        let work = (nominal.len() as u64 + 1) * u64::from(self.iterations.max(1));
        for _ in 0..steps {
            crate::limits::charge(work)?;
            self.step(tree, &nominal, h, down, state);
        }
        for (s, p) in states.iter_mut().zip(&state.position) {
            s.position = *p;
        }
        Ok(())
    }

    fn step(&self, tree: &Tree, nominal: &[Vec3], h: f64, down: Vec3, state: &mut GravityState) {
        let (pos, prev) = (&mut state.position, &mut state.previous);
        let current = pos.clone();
        for &n in &tree.order {
            let n = n as usize;
            let Some(p) = tree.parent[n] else {
                // The root is fixed on its nominal position.
                pos[n] = nominal[n];
                prev[n] = nominal[n];
                continue;
            };
            let p = p as usize;
            let dl = (current[n] - current[p]) - (nominal[n] - nominal[p]);
            let a = self.g * down - self.k * dl;
            pos[n] = current[n] + self.drag * (current[n] - prev[n]) + a * (h * h);
            prev[n] = current[n];
        }
        for _ in 0..self.iterations.max(1) {
            project_tree(tree, nominal, pos);
            for &[a, b] in &tree.cycle_pairs {
                let (a, b) = (a as usize, b as usize);
                let rest = (nominal[b] - nominal[a]).length();
                let d = pos[b] - pos[a];
                let len = d.length();
                if len > 0.0 {
                    let corr = d * (0.5 * (len - rest) / len);
                    if tree.parent[a].is_some() {
                        pos[a] += corr;
                    }
                    if tree.parent[b].is_some() {
                        pos[b] -= corr;
                    }
                }
            }
        }
        // Segments closing cycles were settled above; a last tree sweep keeps every tree
        // segment at its length exactly.
        project_tree(tree, nominal, pos);
    }
}

/// One relaxation sweep over the tree segments, parents first: each child end moved onto its
/// segment's nominal length from the (already placed) parent end.
fn project_tree(tree: &Tree, nominal: &[Vec3], pos: &mut [Vec3]) {
    for &n in &tree.order {
        let n = n as usize;
        let Some(p) = tree.parent[n] else { continue };
        let p = p as usize;
        let rest = (nominal[n] - nominal[p]).length();
        let d = pos[n] - pos[p];
        let len = d.length();
        pos[n] = if len > 0.0 { pos[p] + d * (rest / len) } else { pos[p] + (nominal[n] - nominal[p]) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_parameters_are_named() {
        for (g, name) in [
            (Gravity { drag: 0.0, ..Gravity::default() }, "drag"),
            (Gravity { drag: 1.5, ..Gravity::default() }, "drag"),
            (Gravity { k: -1.0, ..Gravity::default() }, "k"),
            (Gravity { down: Vec3::ZERO, ..Gravity::default() }, "down"),
            (Gravity { dt: Some(0.0), ..Gravity::default() }, "dt"),
            (Gravity { g: f64::NAN, ..Gravity::default() }, "g"),
        ] {
            assert!(matches!(g.validate(), Err(AnimError::InvalidParameter { name: n, .. }) if n == name), "{name}");
        }
        assert!(Gravity::default().validate().is_ok());
    }
}
