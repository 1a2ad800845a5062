//! Smooth plants that still animate (issue 35): the rest mesh refined by Catmull–Clark
//! subdivision with the branch tips kept pointed, and the skin carried through the refinement.
//!
//! A polar mesh is a coarse control mesh (valence-16 loops of quads, fans of triangles at the
//! poles): the thesis draws it faceted (seed 004, Figs. 12.1–12.3), as it models it. Catmull &
//! Clark's scheme (seed 000 §2.3) smooths it; two things make that the smooth plant a user
//! expects and not a blob:
//!
//! - **Tips stay pointed.** Where the grammar ends a branch the polar mesh has a pole: a leaf
//!   node of the skeleton's tree with one vertex. Those vertices are marked as corners
//!   (infinitely sharp vertices, DeRose, Kass & Truong 1998 §3), which subdivision keeps in
//!   place, so a branch still ends in its tip instead of a rounded stub pulled back along its
//!   axis. The root pole, where the plant stands, is smoothed like any other vertex.
//! - **The skin follows.** Every refined vertex is an affine combination of control vertices (the
//!   subdivision's composed stencils); its skin weights are the same combination of the control
//!   vertices' joints — one joint each, weight 1, as §7.3's binding gives — summed per joint.
//!   The [`MAX_INFLUENCES`] strongest are kept and renormalised, as glTF's one
//!   `JOINTS_0`/`WEIGHTS_0` pair holds, and a pose moves a vertex by the weighted sum of its
//!   joints' transforms (linear blend skinning, what every glTF viewer computes). At rest every
//!   joint's transform is the identity, so the smooth rest pose is the subdivision exactly; in a
//!   pose, a vertex whose stencil reaches one node only moves exactly as that node's rigid
//!   skinning moves it.
//!
//! Cost: linear in the refined vertex count times the stencil width (bounded for bounded
//! valence).

use super::animation::Animation;
use super::AnimError;
use crate::mesh::Mesh;
use crate::subdiv::{Refiner, Scheme, StencilTable, SubdivError};

/// At most this many joints move one vertex: glTF's `JOINTS_0`/`WEIGHTS_0` hold four.
pub const MAX_INFLUENCES: usize = 4;

/// The joints that move each vertex, strongest first, and their weights (each vertex's sum to
/// 1; unused slots have joint 0 and weight 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Influences {
    /// Per vertex, the joints (skeleton node ids).
    pub joints: Vec<[u32; MAX_INFLUENCES]>,
    /// Per vertex, the weight of each joint.
    pub weights: Vec<[f64; MAX_INFLUENCES]>,
}

impl Influences {
    /// One joint per vertex with weight 1: §7.3's binding.
    #[must_use]
    pub fn single(nodes: &[u32]) -> Influences {
        Influences {
            joints: nodes.iter().map(|&n| [n, 0, 0, 0]).collect(),
            weights: vec![[1.0, 0.0, 0.0, 0.0]; nodes.len()],
        }
    }

    /// The influences of the vertices `stencils` makes from vertices with these: each row's
    /// weights times its sources' joint weights, summed per joint; the [`MAX_INFLUENCES`]
    /// largest kept (ties to the lower joint) and scaled to sum to 1. Stencil weights can be
    /// negative (semi-sharp rules); a joint's summed weight below zero is dropped.
    #[must_use]
    pub fn refined(&self, stencils: &StencilTable) -> Influences {
        let rows = stencils.rows();
        let mut out = Influences { joints: Vec::with_capacity(rows), weights: Vec::with_capacity(rows) };
        let mut sums: Vec<(u32, f64)> = Vec::new();
        for i in 0..rows {
            sums.clear();
            let (sources, ws) = stencils.row(i);
            for (&s, &w) in sources.iter().zip(ws) {
                let (joints, weights) = (&self.joints[s as usize], &self.weights[s as usize]);
                for (&j, &jw) in joints.iter().zip(weights) {
                    if jw == 0.0 {
                        continue;
                    }
                    match sums.iter_mut().find(|(k, _)| *k == j) {
                        Some((_, x)) => *x += w * jw,
                        None => sums.push((j, w * jw)),
                    }
                }
            }
            sums.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
            let kept = &sums[..sums.len().min(MAX_INFLUENCES)];
            let total: f64 = kept.iter().map(|&(_, w)| w.max(0.0)).sum();
            let (mut joints, mut weights) = ([0u32; MAX_INFLUENCES], [0.0f64; MAX_INFLUENCES]);
            for (k, &(j, w)) in kept.iter().enumerate() {
                if w > 0.0 && total > 0.0 {
                    joints[k] = j;
                    weights[k] = w / total;
                }
            }
            out.joints.push(joints);
            out.weights.push(weights);
        }
        out
    }
}

/// The most Catmull–Clark levels a plant is refined by (each makes four faces of one).
pub const MAX_LEVELS: u32 = 4;

/// `levels` within 0–[`MAX_LEVELS`], else the error naming it.
fn check_levels(levels: u32) -> Result<(), AnimError> {
    if levels > MAX_LEVELS {
        return Err(AnimError::InvalidParameter {
            name: "levels",
            reason: format!("must be between 0 and {MAX_LEVELS} (each level makes four faces of one), got {levels}"),
        });
    }
    Ok(())
}

impl Animation {
    /// This animation with its rest mesh refined by `levels` Catmull–Clark steps, the branch
    /// tips kept pointed and the skin carried through (see the module documentation). The
    /// skeleton and the modifier stack are the same, so every pose is the smooth plant posed;
    /// face colours ride on their faces and vertex colours (the feature hues) are refined with
    /// the positions. 0 levels returns a copy. Tells a listener ([`crate::limits::listen`]) its
    /// five steps.
    ///
    /// # Errors
    /// [`AnimError::InvalidParameter`] naming `levels` above [`MAX_LEVELS`], or when the result
    /// would exceed the subdivision's face cap (its estimate named); [`AnimError::Limit`] when
    /// stopped.
    pub fn subdivided(&self, levels: u32) -> Result<Animation, AnimError> {
        check_levels(levels)?;
        if levels == 0 {
            return Ok(self.clone());
        }
        if self.is_subdivided() {
            return Err(AnimError::InvalidParameter {
                name: "levels",
                reason: "the animation is already subdivided: subdivide the one made from the polar mesh".into(),
            });
        }
        // Progress: five steps (topology, positions, mesh, weights composed, influences).
        let work = crate::limits::Work::start(5);
        let (mut rest, refiner) = self.smooth_rest(levels, &work)?;
        let stencils = refiner.composed_stencils();
        work.set(4);
        refine_vertex_colors(&mut rest, self.rest_mesh(), &stencils);
        let influences = self.influences().refined(&stencils);
        work.finish();
        Ok(self.with_rest(rest, influences))
    }

    /// The rest mesh refined by `levels` Catmull–Clark steps with the tips held as corners
    /// (cleared after), without vertex colours, and the refiner. Tells `work` its first three
    /// steps.
    fn smooth_rest(&self, levels: u32, work: &crate::limits::Work) -> Result<(Mesh, Refiner), AnimError> {
        let mut control = self.rest_mesh().clone();
        for v in self.tip_vertices() {
            control.set_corner(v, true);
        }
        let subdiv = |e: SubdivError| match e {
            SubdivError::Limit(l) => AnimError::Limit(l),
            e => AnimError::InvalidParameter { name: "levels", reason: e.to_string() },
        };
        let refiner = Refiner::new(&control, Scheme::CatmullClark, levels).map_err(subdiv)?;
        work.set(1);
        let positions = refiner.try_refine_positions(control.positions()).map_err(subdiv)?;
        work.set(2);
        let mut rest = refiner.to_mesh(positions).map_err(subdiv)?;
        work.set(3);
        if control.face_part_ids().is_some() {
            rest.inherit_parts(&control, &refiner.base_faces())
                .map_err(|e| AnimError::InvalidParameter { name: "levels", reason: e.to_string() })?;
        }
        // Corners were marks for the refinement, not part of the plant.
        for v in 0..rest.vertex_count() as u32 {
            if rest.is_corner(v) {
                rest.set_corner(v, false);
            }
        }
        Ok((rest, refiner))
    }

    /// The vertices at the branch tips: poles bound to a leaf node of the tree.
    fn tip_vertices(&self) -> Vec<u32> {
        let sk = self.skeleton();
        (0..self.rest_mesh().vertex_count() as u32)
            .filter(|&v| {
                let n = sk.node_of(v);
                sk.is_pole(n) && self.children(n).is_empty()
            })
            .collect()
    }
}

/// `refined` given the vertex colours of `control` (if any) refined by `stencils` (the
/// composed stencils from `control`'s vertices to `refined`'s), clamped to 0–1.
fn refine_vertex_colors(refined: &mut Mesh, control: &Mesh, stencils: &StencilTable) {
    let Some(colors) = control.vertex_colors() else { return };
    let out = (0..stencils.rows())
        .map(|i| {
            let (sources, ws) = stencils.row(i);
            let mut c = [0.0f64; 4];
            for (&s, &w) in sources.iter().zip(ws) {
                for (k, x) in colors[s as usize].iter().enumerate() {
                    c[k] += w * f64::from(*x);
                }
            }
            c.map(|x| x.clamp(0.0, 1.0) as f32)
        })
        .collect();
    refined.set_vertex_colors(Some(out)).expect("one colour per refined vertex");
}

/// The polar mesh `pm` as a smooth surface: the rest mesh of [`Animation::subdivided`] for the
/// skeleton rooted at the node of vertex `root` (default: the first pole), which decides which
/// poles are tips. The mesh keeps the polar mesh's face colours (not the feature hues an
/// animation's rest mesh shows); no skin is refined. Tells a listener
/// ([`crate::limits::listen`]) its steps, five as [`Animation::subdivided`].
///
/// # Errors
/// As [`Animation::new`] and [`Animation::subdivided`].
pub fn subdivide_polar_mesh(pm: &crate::polar::PolarMesh, root: Option<u32>, levels: u32) -> Result<Mesh, AnimError> {
    check_levels(levels)?;
    let anim = Animation::new(pm, root, super::Skinning::Smooth)?;
    let colors = pm.mesh().vertex_colors().is_some();
    if levels == 0 {
        let mut mesh = anim.rest_mesh().clone();
        if !colors {
            mesh.set_vertex_colors(None).expect("clearing colours");
        }
        return Ok(mesh);
    }
    let work = crate::limits::Work::start(5);
    let (mut mesh, refiner) = anim.smooth_rest(levels, &work)?;
    if colors {
        refine_vertex_colors(&mut mesh, anim.rest_mesh(), &refiner.composed_stencils());
    }
    work.finish();
    Ok(mesh)
}

#[cfg(test)]
#[path = "tests_smooth.rs"]
mod tests;
