//! The one seam between blocksmith and the boolean engine (manifold-rust, the pure-Rust port of
//! Manifold 3.5.4; see the [module documentation](super) for why this engine).
//!
//! Everything the rest of the crate knows of the engine is here: a [`Solid`] is imported from
//! indexed triangles carrying one `u32` tag per triangle — the input face it belongs to, the
//! same for coplanar triangles of one face — combined by [`Solid::boolean`], and exported back
//! to triangles whose tags name the input face each output triangle lies on (Manifold's
//! `faceID`, which its booleans keep and which its simplification never merges across).
//! Swapping the engine means rewriting this file only.
//!
//! The engine's booleans stop early when asked ([`Stop`], the engine's own cooperative
//! cancellation, checked at its stage boundaries and inside its long loops: per intersection,
//! per face triangulated). [`watching`] sets that flag from a kernel [`CancelToken`] (Ctrl-C, a
//! deadline, the operation limit) within [`WATCH_PERIOD`] of the token stopping.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use manifold_rust::manifold::Manifold;
use manifold_rust::types::{BooleanConfig, Error as EngineStatus, MeshGLP, OpType};

use super::CsgOp;
use crate::limits::CancelToken;
use crate::math::{Aabb, Vec3};

/// How often [`watching`] reads the kernel token while the engine works.
pub const WATCH_PERIOD: Duration = Duration::from_millis(5);

/// The engine's stop flag: once set, every boolean run with it ends early with
/// [`EngineError::Stopped`]. Clones share the flag.
#[derive(Clone, Debug, Default)]
pub struct Stop(manifold_rust::cancel::CancelToken);

impl Stop {
    /// A flag not set.
    #[must_use]
    pub fn new() -> Stop {
        Stop::default()
    }

    /// Sets the flag (for good).
    pub fn stop(&self) {
        self.0.cancel();
    }

    /// Whether the flag is set.
    #[must_use]
    pub fn is_stopped(&self) -> bool {
        self.0.is_cancelled()
    }
}

/// Why the engine gave no solid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EngineError {
    /// Its [`Stop`] flag was set.
    Stopped,
    /// The engine's reason (e.g. `"Not Manifold"`).
    Failed(String),
}

impl std::fmt::Display for EngineError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EngineError::Stopped => f.write_str("stopped"),
            EngineError::Failed(reason) => f.write_str(reason),
        }
    }
}

/// Runs `work` with a [`Stop`] flag that is set as soon as `token` stops (read every
/// [`WATCH_PERIOD`] by a watching thread while `work` runs; no thread when the token can never
/// stop).
pub fn watching<R>(token: &CancelToken, work: impl FnOnce(&Stop) -> R) -> R {
    let stop = Stop::new();
    if !token.is_active() {
        return work(&stop);
    }
    let done = AtomicBool::new(false);
    std::thread::scope(|s| {
        let watcher = s.spawn(|| {
            while !done.load(Ordering::Acquire) {
                if token.stopped().is_some() {
                    stop.stop();
                    return;
                }
                std::thread::park_timeout(WATCH_PERIOD);
            }
        });
        let result = work(&stop);
        done.store(true, Ordering::Release);
        watcher.thread().unpark();
        result
    })
}

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
        Solid::with_id_until(positions, triangles, tags, id, &Stop::new()).map_err(|e| e.to_string())
    }

    /// [`Solid::with_id`], ending early when `stop` is set.
    ///
    /// # Errors
    /// [`EngineError::Stopped`] when `stop` was set before the import finished, else as
    /// [`Solid::new`].
    pub fn with_id_until(
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        tags: &[u32],
        id: u32,
        stop: &Stop,
    ) -> Result<Solid, EngineError> {
        debug_assert_eq!(triangles.len(), tags.len());
        if stop.is_stopped() {
            return Err(EngineError::Stopped);
        }
        let mesh = MeshGLP::<f64, u32> {
            num_prop: 3,
            vert_properties: positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
            tri_verts: triangles.as_flattened().to_vec(),
            face_id: tags.to_vec(),
            run_original_id: vec![id],
            ..Default::default()
        };
        let inner = Manifold::from_mesh_glp_with_token(&mesh, Some(&stop.0));
        match inner.status() {
            EngineStatus::NoError => Ok(Solid { inner }),
            EngineStatus::Cancelled => Err(EngineError::Stopped),
            e => Err(EngineError::Failed(e.to_str().to_string())),
        }
    }

    /// The boolean `self op other`.
    ///
    /// # Errors
    /// The engine's reason when its result is not a valid manifold (it reports, never panics on
    /// manifold input).
    pub fn boolean(&self, other: &Solid, op: CsgOp) -> Result<Solid, String> {
        self.boolean_until(other, op, &Stop::new()).map_err(|e| e.to_string())
    }

    /// [`Solid::boolean`], ending early when `stop` is set.
    ///
    /// # Errors
    /// [`EngineError::Stopped`] when `stop` was set before the engine finished, else as
    /// [`Solid::boolean`].
    pub fn boolean_until(&self, other: &Solid, op: CsgOp, stop: &Stop) -> Result<Solid, EngineError> {
        if stop.is_stopped() {
            return Err(EngineError::Stopped);
        }
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
        let inner =
            self.inner.boolean_with_engine_and_token(&other.inner, op, BooleanConfig::default_engine(), Some(&stop.0));
        match inner.status() {
            EngineStatus::NoError => Ok(Solid { inner }),
            EngineStatus::Cancelled => Err(EngineError::Stopped),
            e => Err(EngineError::Failed(e.to_str().to_string())),
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
        Solid::union_all_until(parts, &Stop::new()).map_err(|e| e.to_string())
    }

    /// [`Solid::union_all`], ending early when `stop` is set.
    ///
    /// # Errors
    /// As [`Solid::boolean_until`].
    pub fn union_all_until(parts: Vec<Solid>, stop: &Stop) -> Result<Solid, EngineError> {
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
        union_pairwise(composed, stop)
    }

    /// The number of the solid's triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.inner.num_tri()
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

fn union_pairwise(mut parts: Vec<Solid>, stop: &Stop) -> Result<Solid, EngineError> {
    if parts.len() <= 1 {
        return Ok(parts.pop().unwrap_or(Solid { inner: Manifold::empty() }));
    }
    let right = parts.split_off(parts.len() / 2);
    let (a, b) = rayon::join(|| union_pairwise(parts, stop), || union_pairwise(right, stop));
    a?.boolean_until(&b?, CsgOp::Union, stop)
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    use super::*;
    use crate::mesh::Mesh;

    fn solid(m: &Mesh) -> Solid {
        let t = m.triangulate().unwrap();
        let tris: Vec<[u32; 3]> = (0..t.face_count() as u32)
            .map(|f| {
                let v: Vec<u32> = t.face_vertices(f).collect();
                [v[0], v[1], v[2]]
            })
            .collect();
        let tags = (0..tris.len() as u32).collect::<Vec<_>>();
        Solid::new(t.positions(), &tris, &tags).unwrap()
    }

    #[test]
    fn a_set_stop_flag_ends_imports_and_booleans_and_a_clear_one_changes_nothing() {
        let a = Mesh::icosphere(1.0, 2);
        let b = a.translate(Vec3::new(0.5, 0.0, 0.0));
        let (sa, sb) = (solid(&a), solid(&b));
        let clear = Stop::new();
        let with = sa.boolean_until(&sb, CsgOp::Difference, &clear).unwrap();
        assert_eq!(with.triangles(), sa.boolean(&sb, CsgOp::Difference).unwrap().triangles());
        let set = Stop::new();
        set.stop();
        assert_eq!(sa.boolean_until(&sb, CsgOp::Difference, &set).err(), Some(EngineError::Stopped));
        assert_eq!(Solid::union_all_until(vec![sa.clone(), sb.clone()], &set).err(), Some(EngineError::Stopped));
        let t = sa.triangles();
        let e = Solid::with_id_until(&t.positions, &t.triangles, &t.tags, Solid::reserve_ids(1), &set).err();
        assert_eq!(e, Some(EngineError::Stopped));
    }

    #[test]
    fn a_boolean_stops_inside_the_engine_soon_after_the_token_does() {
        // 82k triangles a side: far longer than the few milliseconds before the flag is set.
        let a = Mesh::icosphere(1.0, 6);
        let (sa, sb) = (solid(&a), solid(&a.translate(Vec3::new(0.3, 0.2, 0.1))));
        let flag = Arc::new(AtomicBool::new(false));
        let token = CancelToken::with(Some(flag.clone()), None, None);
        let setter = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(5));
            flag.store(true, Ordering::Relaxed);
            Instant::now()
        });
        let result = watching(&token, |stop| sa.boolean_until(&sb, CsgOp::Difference, stop));
        let latency = setter.join().unwrap().elapsed();
        assert_eq!(result.err(), Some(EngineError::Stopped));
        // The engine checks its flag at every stage and inside its long loops; a generous
        // bound for a loaded debug build (the release figure is in the hardening notes).
        assert!(latency < Duration::from_secs(2), "stopped {latency:?} after the flag was set");
    }

    #[test]
    fn no_watcher_runs_for_a_token_that_cannot_stop() {
        let token = CancelToken::new();
        let stop = watching(&token, Stop::clone);
        assert!(!stop.is_stopped());
        let passed = CancelToken::with(None, Some((Instant::now(), 0.0)), None);
        let seen = watching(&passed, |stop| {
            let start = Instant::now();
            while !stop.is_stopped() && start.elapsed() < Duration::from_secs(5) {
                std::thread::sleep(Duration::from_millis(1));
            }
            stop.is_stopped()
        });
        assert!(seen, "a passed deadline sets the flag");
    }
}
