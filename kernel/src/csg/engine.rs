//! The one seam between blocksmith and the boolean engine (manifold-rust, the pure-Rust port of
//! Manifold 3.5.4; see the [module documentation](super) for why this engine).
//!
//! Everything the rest of the crate knows of the engine is here: a [`Solid`] is imported from
//! indexed triangles carrying one `u32` tag per triangle — the input face it belongs to, the
//! same for coplanar triangles of one face — combined by [`Solid::boolean`], and exported back
//! to triangles whose tags name the input face each output triangle lies on (Manifold's
//! `faceID`, which its booleans keep and which its simplification never merges across).
//! Swapping the engine means rewriting this file only.

use manifold_rust::manifold::Manifold;
use manifold_rust::types::{Error as EngineStatus, MeshGLP, OpType};

use super::CsgOp;
use crate::math::{Aabb, Vec3};

/// A closed manifold triangle solid inside the engine.
#[derive(Clone)]
pub struct Solid {
    inner: Manifold,
}

/// Triangles out of the engine: positions, corner indices and one tag per triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Triangles {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise (seen from outside) corner indices.
    pub triangles: Vec<[u32; 3]>,
    /// The tag of the input triangle each triangle lies on.
    pub tags: Vec<u32>,
}

impl Solid {
    /// Imports indexed triangles with one tag per triangle (triangles sharing a tag must be
    /// coplanar: the engine treats them as one face).
    ///
    /// # Errors
    /// The engine's reason (e.g. `"Not Manifold"`) when it refuses the triangles.
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]], tags: &[u32]) -> Result<Solid, String> {
        Solid::with_id(positions, triangles, tags, Manifold::reserve_ids(1))
    }

    /// Reserves `n` consecutive engine mesh ids and returns the first. The engine orders its
    /// output by mesh id: importing in parallel with ids reserved beforehand, in a fixed order,
    /// keeps results the same from run to run.
    #[must_use]
    pub fn reserve_ids(n: u32) -> u32 {
        Manifold::reserve_ids(n)
    }

    /// [`Solid::new`] with the engine mesh id `id` (from [`Solid::reserve_ids`]).
    ///
    /// # Errors
    /// As [`Solid::new`].
    pub fn with_id(positions: &[Vec3], triangles: &[[u32; 3]], tags: &[u32], id: u32) -> Result<Solid, String> {
        debug_assert_eq!(triangles.len(), tags.len());
        let mesh = MeshGLP::<f64, u32> {
            num_prop: 3,
            vert_properties: positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
            tri_verts: triangles.as_flattened().to_vec(),
            face_id: tags.to_vec(),
            run_original_id: vec![id],
            ..Default::default()
        };
        let inner = Manifold::from_mesh_glp(&mesh);
        match inner.status() {
            EngineStatus::NoError => Ok(Solid { inner }),
            e => Err(e.to_str().to_string()),
        }
    }

    /// The boolean `self op other`.
    ///
    /// # Errors
    /// The engine's reason when its result is not a valid manifold (it reports, never panics on
    /// manifold input).
    pub fn boolean(&self, other: &Solid, op: CsgOp) -> Result<Solid, String> {
        // Operands whose bounds are apart (not even touching) do not interact: the union is the
        // two side by side, the difference the left one, the intersection empty — as Manifold's
        // own batch union does, without running the intersection pipeline.
        if !self.is_empty()
            && !other.is_empty()
            && aabb(&self.inner.bounding_box()).is_apart(&aabb(&other.inner.bounding_box()))
        {
            return Ok(match op {
                CsgOp::Union => Solid { inner: Manifold::compose(&[self.inner.clone(), other.inner.clone()]) },
                CsgOp::Difference => self.clone(),
                CsgOp::Intersection => Solid { inner: Manifold::empty() },
            });
        }
        let op = match op {
            CsgOp::Union => OpType::Add,
            CsgOp::Difference => OpType::Subtract,
            CsgOp::Intersection => OpType::Intersect,
        };
        let inner = self.inner.boolean(&other.inner, op);
        match inner.status() {
            EngineStatus::NoError => Ok(Solid { inner }),
            e => Err(e.to_str().to_string()),
        }
    }

    /// The solid's bounding box (min, max).
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let b = aabb(&self.inner.bounding_box());
        (b.min, b.max)
    }

    /// Manifold's own sphere (`Manifold::sphere`: a subdivided octahedron, `segments` around),
    /// the very input manifold3d uses — for comparing with it on identical meshes.
    #[must_use]
    pub fn manifold_sphere(radius: f64, segments: i32) -> Solid {
        Solid { inner: Manifold::sphere(radius, segments) }
    }

    /// The union of many solids, as Manifold's batch union does it: the solids are dealt into
    /// groups whose bounds are pairwise apart, each group is put side by side (no boolean
    /// needed), and the groups are unioned pairwise, halves in parallel.
    ///
    /// # Errors
    /// As [`Solid::boolean`].
    pub fn union_all(parts: Vec<Solid>) -> Result<Solid, String> {
        let mut groups: Vec<(Vec<Manifold>, Vec<Aabb>)> = Vec::new();
        for p in parts.into_iter().filter(|p| !p.is_empty()) {
            let b = aabb(&p.inner.bounding_box());
            match groups.iter_mut().find(|(_, boxes)| boxes.iter().all(|q| b.is_apart(q))) {
                Some((members, boxes)) => {
                    members.push(p.inner);
                    boxes.push(b);
                }
                None => groups.push((vec![p.inner], vec![b])),
            }
        }
        let composed: Vec<Solid> = groups
            .into_iter()
            .map(|(members, _)| Solid {
                inner: if members.len() == 1 {
                    members.into_iter().next().unwrap_or_default()
                } else {
                    Manifold::compose(&members)
                },
            })
            .collect();
        union_pairwise(composed)
    }

    /// Whether the solid has no triangles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.inner.is_empty()
    }

    /// The engine's volume of the solid.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.inner.volume()
    }

    /// The triangles of the solid, with their tags.
    #[must_use]
    pub fn triangles(&self) -> Triangles {
        let m = self.inner.get_mesh_glp::<f64, u32>(-1);
        let np = m.num_prop as usize;
        let mut positions: Vec<Vec3> =
            m.vert_properties.chunks_exact(np).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
        let mut triangles: Vec<[u32; 3]> = m.tri_verts.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        // With only positions there are no property seams, but follow the merge vectors in case
        // the engine split a vertex anyway.
        if !m.merge_from_vert.is_empty() {
            let mut to: Vec<u32> = (0..positions.len() as u32).collect();
            for (&f, &t) in m.merge_from_vert.iter().zip(&m.merge_to_vert) {
                to[f as usize] = t;
            }
            for t in &mut triangles {
                t.iter_mut().for_each(|v| *v = to[*v as usize]);
            }
            let mut keep = vec![u32::MAX; positions.len()];
            let mut kept = Vec::with_capacity(positions.len());
            for t in &mut triangles {
                for v in t.iter_mut() {
                    if keep[*v as usize] == u32::MAX {
                        keep[*v as usize] = kept.len() as u32;
                        kept.push(positions[*v as usize]);
                    }
                    *v = keep[*v as usize];
                }
            }
            positions = kept;
        }
        let tags = if m.face_id.len() == triangles.len() { m.face_id } else { vec![u32::MAX; triangles.len()] };
        Triangles { positions, triangles, tags }
    }
}

/// An engine box as ours.
fn aabb(b: &manifold_rust::types::Box) -> Aabb {
    Aabb { min: Vec3::new(b.min.x, b.min.y, b.min.z), max: Vec3::new(b.max.x, b.max.y, b.max.z) }
}

fn union_pairwise(mut parts: Vec<Solid>) -> Result<Solid, String> {
    if parts.len() <= 1 {
        return Ok(parts.pop().unwrap_or(Solid { inner: Manifold::empty() }));
    }
    let right = parts.split_off(parts.len() / 2);
    let (a, b) = rayon::join(|| union_pairwise(parts), || union_pairwise(right));
    a?.boolean(&b?, CsgOp::Union)
}
