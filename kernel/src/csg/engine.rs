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

use std::borrow::Cow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use manifold_rust::cross_section::CrossSection;
use manifold_rust::linalg::{Vec2 as EVec2, Vec3 as EVec3};
use manifold_rust::manifold::Manifold;
use manifold_rust::types::{BooleanConfig, BooleanEngine, Error as EngineStatus, MeshGLP, OpType, Polygons};
use rayon::prelude::*;

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

/// Triangles laid out as the engine's import reads them ([`Solid::from_flat_until`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlatTriangles {
    /// x, y, z of each vertex.
    pub coordinates: Vec<f64>,
    /// Three corner indices per triangle, counter-clockwise seen from outside.
    pub corners: Vec<u32>,
    /// One tag per triangle (triangles sharing a tag must be coplanar: the engine treats them
    /// as one face).
    pub tags: Vec<u32>,
    /// The pairing of the half-edges, when known (else empty): `pairs[3 * t + i]` is the
    /// half-edge opposite triangle `t`'s edge from corner `i` to corner `i + 1`, numbered the
    /// same way. It spares the engine's import its sort of every half-edge; the engine checks
    /// it, and sorts as before where it does not hold.
    pub pairs: Vec<u32>,
    /// The engine's epsilon for the import's clean-up, when above the automatic one (else
    /// 0): points closer than it merge. [`Solid::compose_apart`] needs its parts cleaned at the
    /// epsilon of the whole they will form.
    pub tolerance: f64,
}

/// One part of [`Solid::compose_apart`].
pub struct ApartSolid<'a> {
    /// The part.
    pub solid: &'a Solid,
    /// Where its vertices go, for a translated copy (every vertex moved by one vector, within
    /// the engine's epsilon): positions, and for each vertex in [`Solid::vertex_positions`]'
    /// order the index of its position there. `None` leaves the part where it is.
    pub moved_to: Option<(&'a [Vec3], &'a [u32])>,
    /// Added to each of its triangles' tags.
    pub tag_shift: i32,
}

/// Triangles out of the engine with the engine's pairing of their half-edges
/// ([`Solid::paired_triangles`]), for building a half-edge mesh without searching for twins.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PairedTriangles {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Three corner indices per triangle, counter-clockwise seen from outside.
    pub corners: Vec<u32>,
    /// For half-edge `3t + i` (corner `i` to corner `i + 1` of triangle `t`), the half-edge
    /// running back along its edge.
    pub pairs: Vec<u32>,
    /// The tag of the input triangle each triangle lies on.
    pub tags: Vec<u32>,
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
        let flat = FlatTriangles {
            coordinates: positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
            corners: triangles.as_flattened().to_vec(),
            tags: tags.to_vec(),
            pairs: Vec::new(),
            tolerance: 0.0,
        };
        Solid::from_flat_until(flat, id, stop)
    }

    /// [`Solid::with_id_until`] from triangles already laid out as the engine reads them, which
    /// it takes without copying them again (the engine's import makes its own arrays).
    ///
    /// # Errors
    /// As [`Solid::with_id_until`].
    pub fn from_flat_until(flat: FlatTriangles, id: u32, stop: &Stop) -> Result<Solid, EngineError> {
        debug_assert_eq!(flat.corners.len(), 3 * flat.tags.len());
        if stop.is_stopped() {
            return Err(EngineError::Stopped);
        }
        let mesh = MeshGLP::<f64, u32> {
            num_prop: 3,
            vert_properties: flat.coordinates,
            tri_verts: flat.corners,
            face_id: flat.tags,
            run_original_id: vec![id],
            tolerance: flat.tolerance,
            ..Default::default()
        };
        let inner = if flat.pairs.is_empty() {
            Manifold::from_mesh_glp_with_token(&mesh, Some(&stop.0))
        } else {
            Manifold::from_mesh_glp_paired_with_token(&mesh, &flat.pairs, Some(&stop.0))
        };
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
        boolean_of(Cow::Borrowed(self), Cow::Borrowed(other), op, stop, true)
    }

    /// [`Solid::boolean_until`] on operands it takes: the engine frees each as soon as the
    /// result no longer reads it, before the result's triangulation, simplification and sort
    /// (engine patch 18), so the peak of a large boolean does not hold both operands and their
    /// colliders beside the result. The same result as [`Solid::boolean_until`].
    ///
    /// # Errors
    /// As [`Solid::boolean_until`].
    pub fn into_boolean_until(self, other: Solid, op: CsgOp, stop: &Stop) -> Result<Solid, EngineError> {
        boolean_of(Cow::Owned(self), Cow::Owned(other), op, stop, true)
    }

    /// [`Solid::into_boolean_until`] for a result that is only exported
    /// ([`Solid::paired_triangles`], [`Solid::triangles`]), never an operand again: the engine
    /// leaves it in the order it makes it, without its spatial sort (engine patch 17; a sixth
    /// of a large boolean's time) and without the vertex normals only an operand needs (engine
    /// patch 23; a tenth).
    ///
    /// # Errors
    /// As [`Solid::boolean_until`].
    pub fn into_boolean_for_export_until(self, other: Solid, op: CsgOp, stop: &Stop) -> Result<Solid, EngineError> {
        boolean_of(Cow::Owned(self), Cow::Owned(other), op, stop, false)
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

    /// The union of `parts`, whose bounds are pairwise apart, by copying them side by side
    /// (engine patch 16: no import again, no sort, the parts' colliders joined), each part
    /// optionally a translated copy ([`ApartSolid`]). Linear in their size.
    ///
    /// `None` when a condition does not hold: bounds not apart, positions of the wrong count
    /// or not one translation, or a part imported at an epsilon finer than the whole's (see
    /// [`FlatTriangles::tolerance`]); the caller then imports or composes another way.
    #[must_use]
    pub fn compose_apart(parts: &[ApartSolid<'_>]) -> Option<Solid> {
        let parts: Vec<manifold_rust::manifold::ApartPart<'_>> = parts
            .par_iter()
            .map(|p| manifold_rust::manifold::ApartPart {
                part: &p.solid.inner,
                moved_to: p.moved_to.map(|(positions, order)| {
                    order.iter().map(|&v| positions[v as usize]).map(|v| EVec3::new(v.x, v.y, v.z)).collect()
                }),
                face_id_shift: p.tag_shift,
            })
            .collect();
        Manifold::compose_apart(&parts).map(|inner| Solid { inner })
    }

    /// The positions of the solid's vertices, in the engine's order.
    #[must_use]
    pub fn vertex_positions(&self) -> Vec<Vec3> {
        self.inner.as_impl().vert_pos.iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect()
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

    /// The triangles of the solid with their tags and the engine's pairing of their half-edges,
    /// in the order and numbering of [`Solid::triangles`] (engine patch 8,
    /// `Manifold::get_mesh_halfedges`): one pass over the engine's half-edges, no copy beyond
    /// the one out of the engine (the positions change type in place).
    #[must_use]
    pub fn paired_triangles(&self) -> PairedTriangles {
        let m = self.inner.get_mesh_halfedges();
        // Both are three f64s: the collect reuses the engine's allocation.
        let positions = m.vert_pos.into_iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect();
        PairedTriangles { positions, corners: m.tri_verts, pairs: m.paired_halfedge, tags: m.face_id }
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

// ---------------------------------------------------------------------------------------------
// 2D regions and the solids made from them (the profile module's side of the seam)
// ---------------------------------------------------------------------------------------------

/// How overlapping or self-intersecting contours fill, given to [`Section::from_contours`]:
/// a point is inside when its winding number (the sum over every contour) is
/// non-zero ([`Fill::NonZero`]), odd ([`Fill::EvenOdd`]) or positive ([`Fill::Positive`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fill {
    /// Winding number ≠ 0.
    NonZero,
    /// Winding number odd.
    EvenOdd,
    /// Winding number > 0.
    Positive,
}

/// How an offset joins the offset edges at a corner ([`Section::offset`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Join {
    /// An arc of the offset distance.
    Round,
    /// The offset edges extended to meet, squared off beyond the miter limit.
    Miter,
    /// Squared off at the offset distance from the corner.
    Square,
    /// A straight cut between the ends of the two offset edges.
    Bevel,
}

/// A 2D region inside the engine (Manifold's `CrossSection`, on Clipper2): contours with outer
/// ones counter-clockwise and holes clockwise, coordinates on a grid of 1e-8.
#[derive(Clone, Debug, Default)]
pub struct Section {
    inner: CrossSection,
}

/// Decimal digits of the engine's 2D grid (Manifold's `CrossSection` precision: 1e-8).
const ENGINE_PRECISION: i32 = 8;

/// Contours as the engine's polygons.
fn engine_polygons(contours: &[Vec<glam::DVec2>]) -> Polygons {
    contours.iter().map(|c| c.iter().map(|p| EVec2::new(p.x, p.y)).collect()).collect()
}

impl Section {
    /// The region `contours` fill under `fill` (self-intersections and overlaps resolved).
    ///
    /// The contours go to Clipper2 together as the subjects of one union under the rule (as
    /// the engine's own constructor does for one path), on the engine's grid of 1e-8; its clean
    /// result (outer contours counter-clockwise, holes clockwise) is the region. Joining the
    /// contours into one path by bridges instead would let a bridge's zero-width corridor merge
    /// separate contours into one in the result.
    #[must_use]
    pub fn from_contours(contours: &[Vec<glam::DVec2>], fill: Fill) -> Section {
        use clipper2_rust::{FillRule, PathD, PathsD, Point};
        let paths: PathsD = contours
            .iter()
            .filter(|c| !c.is_empty())
            .map(|c| c.iter().map(|p| Point::new(p.x, p.y)).collect::<PathD>())
            .collect();
        let rule = match fill {
            Fill::EvenOdd => FillRule::EvenOdd,
            Fill::NonZero => FillRule::NonZero,
            Fill::Positive => FillRule::Positive,
        };
        let clean = clipper2_rust::union_subjects_d(&paths, rule, ENGINE_PRECISION);
        let polygons: Polygons = clean.iter().map(|path| path.iter().map(|p| EVec2::new(p.x, p.y)).collect()).collect();
        // Clean contours, outer counter-clockwise and holes clockwise: the positive rule of the
        // engine's constructor keeps exactly that region.
        Section { inner: CrossSection::new(polygons) }
    }

    /// The region's contours (outer ones counter-clockwise, holes clockwise).
    #[must_use]
    pub fn contours(&self) -> Vec<Vec<glam::DVec2>> {
        self.inner
            .to_polygons()
            .into_iter()
            .filter(|c| c.len() >= 3)
            .map(|c| c.into_iter().map(|p| glam::DVec2::new(p.x, p.y)).collect())
            .collect()
    }

    /// `self op other`.
    #[must_use]
    pub fn boolean(&self, other: &Section, op: CsgOp) -> Section {
        let inner = match op {
            CsgOp::Union => self.inner.union(&other.inner),
            CsgOp::Difference => self.inner.difference(&other.inner),
            CsgOp::Intersection => self.inner.intersection(&other.inner),
        };
        Section { inner }
    }

    /// The region grown by `delta` (shrunk when negative), corners joined by `join`; `miter_limit`
    /// (in multiples of `delta`) for [`Join::Miter`], `segments` per full turn for
    /// [`Join::Round`].
    #[must_use]
    pub fn offset(&self, delta: f64, join: Join, miter_limit: f64, segments: u32) -> Section {
        let code = match join {
            Join::Square => 0,
            Join::Round => 1,
            Join::Miter => 2,
            Join::Bevel => 3,
        };
        let segments = i32::try_from(segments).unwrap_or(i32::MAX);
        Section { inner: self.inner.offset_with_params(delta, code, miter_limit, segments) }
    }

    /// The region with vertices nearer than `epsilon` to the line through their neighbours
    /// removed, and contours of area below `epsilon` times their size dropped.
    #[must_use]
    pub fn simplify(&self, epsilon: f64) -> Section {
        Section { inner: self.inner.simplify(epsilon) }
    }

    /// The convex hull of `points` (Andrew's monotone chain).
    #[must_use]
    pub fn hull(points: &[glam::DVec2]) -> Section {
        let pts: Vec<EVec2> = points.iter().map(|p| EVec2::new(p.x, p.y)).collect();
        Section { inner: CrossSection::hull_points(&pts) }
    }

    /// The region's signed area (holes subtract).
    #[must_use]
    pub fn area(&self) -> f64 {
        self.inner.area()
    }
}

/// Triangles covering the region bounded by `contours` (outer counter-clockwise, holes
/// clockwise, none crossing): corner indices into the contours' points numbered one after the
/// other, counter-clockwise (Manifold's ear clipping).
#[must_use]
pub fn triangulate_contours(contours: &[Vec<glam::DVec2>]) -> Vec<[u32; 3]> {
    manifold_rust::polygon::triangulate(&engine_polygons(contours), -1.0, true)
        .into_iter()
        .map(|t| [t.x as u32, t.y as u32, t.z as u32])
        .collect()
}

/// The engine's status as a result.
fn checked(inner: Manifold) -> Result<Solid, EngineError> {
    match inner.status() {
        EngineStatus::NoError => Ok(Solid { inner }),
        EngineStatus::Cancelled => Err(EngineError::Stopped),
        e => Err(EngineError::Failed(e.to_str().to_string())),
    }
}

/// A closed surface of triangles (counter-clockwise seen from outside) built by one of the
/// engine's constructors before it becomes a [`Solid`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surface {
    /// The vertices' positions.
    pub positions: Vec<Vec3>,
    /// Three vertex ids a triangle.
    pub corners: Vec<u32>,
}

impl Surface {
    /// The engine's construction as ours.
    fn from_engine((positions, triangles): (Vec<EVec3>, Vec<manifold_rust::linalg::IVec3>)) -> Surface {
        Surface {
            positions: positions.iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect(),
            corners: triangles.iter().flat_map(|t| [t.x as u32, t.y as u32, t.z as u32]).collect(),
        }
    }

    /// The closed surface of the region of `contours` (clean: outer counter-clockwise, holes
    /// clockwise, none crossing, as [`Section::contours`] gives) extruded from z = 0 to `height`
    /// through `divisions` intermediate layers, the top turned by `twist_degrees`
    /// (counter-clockwise seen from above) and scaled by `scale_top` (x, y) about the origin,
    /// every layer in between interpolated; the sides' quads split as Manifold's `Extrude` splits
    /// them, the caps by its ear clipping, a top scaled to (0, 0) one apex per contour. The
    /// contours go in as they are (not snapped to the section grid). `None` for no contours or a
    /// height not positive.
    ///
    /// The engine's own construction without the solid's sort, normals and collider, which
    /// nothing needs until the surface takes part in a boolean (and then its import builds them).
    #[must_use]
    pub fn extruded(
        contours: &[Vec<glam::DVec2>],
        height: f64,
        divisions: u32,
        twist_degrees: f64,
        scale_top: glam::DVec2,
    ) -> Option<Surface> {
        let divisions = i32::try_from(divisions).unwrap_or(i32::MAX);
        let scale = EVec2::new(scale_top.x, scale_top.y);
        manifold_rust::constructors::extrude_triangles(
            &engine_polygons(contours),
            height,
            divisions,
            twist_degrees,
            scale,
        )
        .map(Surface::from_engine)
    }

    /// The closed surface of the region of clean `contours` (as for [`Surface::extruded`];
    /// x the radius, y the height, the parts at x < 0 cut off) turned `degrees` about the z axis
    /// in `segments` steps, capped when partial (Manifold's `Revolve`): a point on the axis is
    /// one vertex. `None` when no part of the region lies at x ≥ 0.
    #[must_use]
    pub fn revolved(contours: &[Vec<glam::DVec2>], segments: u32, degrees: f64) -> Option<Surface> {
        let segments = i32::try_from(segments).unwrap_or(i32::MAX);
        manifold_rust::constructors::revolve_triangles(&engine_polygons(contours), segments, degrees)
            .map(Surface::from_engine)
    }
}

impl Solid {
    /// The engine's solid of [`Surface::extruded`] (its surface sorted, with normals and a
    /// collider), to compare with.
    ///
    /// # Errors
    /// The engine's reason when it builds no valid solid.
    #[cfg(test)]
    pub fn extrude(
        contours: &[Vec<glam::DVec2>],
        height: f64,
        divisions: u32,
        twist_degrees: f64,
        scale_top: glam::DVec2,
    ) -> Result<Solid, EngineError> {
        let polygons = engine_polygons(contours);
        let divisions = i32::try_from(divisions).unwrap_or(i32::MAX);
        checked(Manifold::extrude(&polygons, height, divisions, twist_degrees, EVec2::new(scale_top.x, scale_top.y)))
    }

    /// The engine's solid of [`Surface::revolved`], to compare with.
    ///
    /// # Errors
    /// The engine's reason when it builds no valid solid.
    #[cfg(test)]
    pub fn revolve(contours: &[Vec<glam::DVec2>], segments: u32, degrees: f64) -> Result<Solid, EngineError> {
        let polygons = engine_polygons(contours);
        let segments = i32::try_from(segments).unwrap_or(i32::MAX);
        checked(Manifold::revolve(&polygons, segments, degrees))
    }

    /// The convex hull of `points` (quickhull).
    ///
    /// # Errors
    /// The engine's reason when the points span no volume.
    pub fn hull(points: &[Vec3]) -> Result<Solid, EngineError> {
        let pts: Vec<EVec3> = points.iter().map(|p| EVec3::new(p.x, p.y, p.z)).collect();
        checked(Manifold::hull(&pts))
    }

    /// The Minkowski sum `self ⊕ other` (convex parts summed by hulls, then unioned), ending early
    /// when `stop` is set.
    ///
    /// # Errors
    /// [`EngineError::Stopped`] when `stop` was set, else the engine's reason.
    pub fn minkowski_until(&self, other: &Solid, stop: &Stop) -> Result<Solid, EngineError> {
        if stop.is_stopped() {
            return Err(EngineError::Stopped);
        }
        checked(self.inner.minkowski_sum_with_progress(&other.inner, Some(&stop.0), None))
    }

    /// The solid cut by the plane `normal · x = offset`: (the part below, the part above), above
    /// meaning on the side `normal` points to. Either may be empty.
    ///
    /// # Errors
    /// The engine's reason when a part is not a valid solid.
    pub fn split_by_plane(&self, normal: Vec3, offset: f64) -> Result<(Solid, Solid), EngineError> {
        let (above, below) = self.inner.split_by_plane(EVec3::new(normal.x, normal.y, normal.z), offset);
        Ok((checked(below)?, checked(above)?))
    }

    /// The part of the solid on the side of the plane `normal · x = offset` that `normal` points
    /// to.
    ///
    /// # Errors
    /// The engine's reason when the part is not a valid solid.
    pub fn trim_by_plane(&self, normal: Vec3, offset: f64) -> Result<Solid, EngineError> {
        checked(self.inner.trim_by_plane(EVec3::new(normal.x, normal.y, normal.z), offset))
    }

    /// The section of the solid by the plane z = `z`.
    #[must_use]
    pub fn slice(&self, z: f64) -> Section {
        Section { inner: self.inner.slice(z) }
    }

    /// The solid's shadow on the xy plane.
    #[must_use]
    pub fn project(&self) -> Section {
        Section { inner: self.inner.project() }
    }
}

/// An engine box as ours.
fn aabb(b: &manifold_rust::types::Box) -> Aabb {
    Aabb { min: Vec3::new(b.min.x, b.min.y, b.min.z), max: Vec3::new(b.max.x, b.max.y, b.max.z) }
}

/// The boolean `a op b`, its result sorted (usable as an operand) when `sorted`; operands
/// borrowed, or owned and freed by the engine once read (see [`Solid::into_boolean_until`]).
fn boolean_of(
    a: Cow<'_, Solid>,
    b: Cow<'_, Solid>,
    op: CsgOp,
    stop: &Stop,
    sorted: bool,
) -> Result<Solid, EngineError> {
    if stop.is_stopped() {
        return Err(EngineError::Stopped);
    }
    // Operands whose bounds are apart (not even touching) do not interact: the union is the
    // two side by side, the difference the left one, the intersection empty — as Manifold's
    // own batch union does, without running the intersection pipeline.
    if !a.is_empty() && !b.is_empty() && aabb(&a.inner.bounding_box()).is_apart(&aabb(&b.inner.bounding_box())) {
        return Ok(match op {
            CsgOp::Union => Solid { inner: Manifold::compose(&[a.into_owned().inner, b.into_owned().inner]) },
            CsgOp::Difference => a.into_owned(),
            CsgOp::Intersection => Solid { inner: Manifold::empty() },
        });
    }
    let op = match op {
        CsgOp::Union => OpType::Add,
        CsgOp::Difference => OpType::Subtract,
        CsgOp::Intersection => OpType::Intersect,
    };
    let engine = BooleanConfig::default_engine();
    let token = Some(&stop.0);
    let inner = match (a, b) {
        (Cow::Owned(a), Cow::Owned(b)) if engine == BooleanEngine::Exact => {
            a.inner.into_boolean_with_token(b.inner, op, token, sorted)
        }
        (a, b) if sorted || engine != BooleanEngine::Exact => {
            a.inner.boolean_with_engine_and_token(&b.inner, op, engine, token)
        }
        (a, b) => a.inner.boolean_for_export_with_token(&b.inner, op, token),
    };
    match inner.status() {
        EngineStatus::NoError => Ok(Solid { inner }),
        EngineStatus::Cancelled => Err(EngineError::Stopped),
        e => Err(EngineError::Failed(e.to_str().to_string())),
    }
}

fn union_pairwise(mut parts: Vec<Solid>, stop: &Stop) -> Result<Solid, EngineError> {
    if parts.len() <= 1 {
        return Ok(parts.pop().unwrap_or(Solid { inner: Manifold::empty() }));
    }
    let right = parts.split_off(parts.len() / 2);
    let (a, b) = rayon::join(|| union_pairwise(parts, stop), || union_pairwise(right, stop));
    a?.into_boolean_until(b?, CsgOp::Union, stop)
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn separate_contours_stay_separate_whatever_their_order() {
        // Two end panels a unit apart beside a holed panel: once joined into one bridged path,
        // Clipper kept a zero-width corridor between the panels and returned one contour for
        // two (a flat-pack layout written to DXF read back with 6 contours of 7).
        let square = |x: f64, y: f64, w: f64| {
            vec![
                glam::DVec2::new(x, y),
                glam::DVec2::new(x + w, y),
                glam::DVec2::new(x + w, y + w),
                glam::DVec2::new(x, y + w),
            ]
        };
        let mut hole = square(2.0, 2.0, 1.0);
        hole.reverse();
        let contours = [square(0.0, 0.0, 5.0), square(6.0, 0.0, 5.0), hole, square(0.0, 6.0, 5.0)];
        for fill in [Fill::EvenOdd, Fill::NonZero] {
            let s = Section::from_contours(&contours, fill);
            assert_eq!(s.contours().len(), 4, "{fill:?}");
            assert!((s.area() - 74.0).abs() < 1e-9, "{fill:?}: {}", s.area());
        }
        // Even-odd: a contour inside another is a hole whichever way it runs.
        let nested = [square(0.0, 0.0, 5.0), square(2.0, 2.0, 1.0)];
        assert!((Section::from_contours(&nested, Fill::EvenOdd).area() - 24.0).abs() < 1e-9);
        assert!((Section::from_contours(&nested, Fill::NonZero).area() - 25.0).abs() < 1e-9);
    }

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

    /// A given half-edge pairing spares the import its sort and changes nothing; a wrong one
    /// (not mutual, between other vertices, or joining opposed triangles) is not trusted.
    #[test]
    fn a_given_pairing_imports_the_same_solid_and_a_wrong_one_is_not_trusted() {
        let t = Mesh::icosphere(1.0, 2).translate(Vec3::new(0.25, 0.0, 0.0)).triangulate().unwrap();
        let corners: Vec<u32> = (0..t.face_count() as u32).flat_map(|f| t.face_vertices(f)).collect();
        let flat = |pairs: Vec<u32>| FlatTriangles {
            coordinates: t.positions().iter().flat_map(|p| p.to_array()).collect(),
            corners: corners.clone(),
            tags: (0..t.face_count() as u32).collect(),
            pairs,
            tolerance: 0.0,
        };
        let edge: std::collections::HashMap<(u32, u32), u32> =
            (0..corners.len()).map(|h| ((corners[h], corners[h / 3 * 3 + (h + 1) % 3]), h as u32)).collect();
        let pairs: Vec<u32> =
            (0..corners.len()).map(|h| edge[&(corners[h / 3 * 3 + (h + 1) % 3], corners[h])]).collect();
        let import = |pairs: Vec<u32>| Solid::from_flat_until(flat(pairs), 7, &Stop::new()).unwrap();
        let sorted = import(Vec::new());
        let cutter = solid(&Mesh::cuboid(Vec3::splat(-0.5), Vec3::splat(0.5)));
        let result = |s: &Solid| s.boolean(&cutter, CsgOp::Difference).unwrap().triangles();
        assert_eq!(import(pairs.clone()).triangles(), sorted.triangles());
        assert_eq!(result(&import(pairs.clone())), result(&sorted));
        let mut swapped = pairs.clone();
        swapped.swap(0, 1);
        let mut one_way = pairs.clone();
        one_way[pairs[0] as usize] = 1;
        for wrong in [swapped, one_way, vec![0; pairs.len()], vec![u32::MAX; pairs.len()], pairs[1..].to_vec()] {
            assert_eq!(import(wrong).triangles(), sorted.triangles());
        }
        // Opposed triangles (a closed pair of two, beside a tetrahedron), which the sorting
        // import removes: a true pairing joins them, and is not trusted.
        let coordinates = vec![0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 2., 0., 0., 3., 0., 0., 2., 1., 0.];
        let corners: Vec<u32> = vec![0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2, 4, 5, 6, 4, 6, 5];
        let ends = |h: usize| (corners[h], corners[h / 3 * 3 + (h + 1) % 3]);
        let pairs: Vec<u32> =
            (0..18).map(|h| (0..18).find(|&g| ends(g) == (ends(h).1, ends(h).0)).unwrap() as u32).collect();
        let with = |pairs: Vec<u32>| {
            let flat = FlatTriangles {
                coordinates: coordinates.clone(),
                corners: corners.clone(),
                tags: vec![0; 6],
                pairs,
                tolerance: 0.0,
            };
            Solid::from_flat_until(flat, 8, &Stop::new()).unwrap()
        };
        let (sorted, paired) = (with(Vec::new()), with(pairs));
        assert_eq!(sorted.triangles().triangles.len(), 4, "the opposed pair removed");
        assert_eq!(paired.triangles(), sorted.triangles());
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
    fn a_boolean_that_takes_its_operands_gives_the_borrowing_booleans_result() {
        let a = Mesh::icosphere(1.0, 3);
        let near = a.translate(Vec3::new(0.5, 0.2, 0.1));
        let apart = a.translate(Vec3::new(3.0, 0.0, 0.0));
        let stop = Stop::new();
        for b in [&near, &apart] {
            let (sa, sb) = (solid(&a), solid(b));
            for op in [CsgOp::Union, CsgOp::Difference, CsgOp::Intersection] {
                let borrowed = sa.boolean_until(&sb, op, &stop).unwrap();
                let owned = sa.clone().into_boolean_until(sb.clone(), op, &stop).unwrap();
                assert_eq!(owned.triangles(), borrowed.triangles(), "{op:?}");
                // For export: the same triangles, in the order the engine made them.
                let export = sa.clone().into_boolean_for_export_until(sb.clone(), op, &stop).unwrap();
                let sorted_triangles = |s: &Solid| {
                    let t = s.triangles();
                    let mut corners: Vec<[[u64; 3]; 3]> = t
                        .triangles
                        .iter()
                        .map(|c| {
                            let mut c = c.map(|v| t.positions[v as usize].to_array().map(f64::to_bits));
                            let first = (0..3).min_by_key(|&i| c[i]).unwrap();
                            c.rotate_left(first);
                            c
                        })
                        .collect();
                    corners.sort_unstable();
                    corners
                };
                assert_eq!(sorted_triangles(&export), sorted_triangles(&borrowed), "{op:?}, for export");
            }
        }
        let set = Stop::new();
        set.stop();
        let (sa, sb) = (solid(&a), solid(&near));
        assert_eq!(sa.into_boolean_until(sb, CsgOp::Difference, &set).err(), Some(EngineError::Stopped));
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
