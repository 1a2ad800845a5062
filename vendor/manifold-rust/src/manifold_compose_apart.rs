//! blocksmith patch (PATCHES.md, 16): the union of parts that are apart, by concatenation, and
//! translated copies of a part placed without importing them again.
//!
//! `compose_meshes` (`Manifold::compose`) rebuilds its result from triangles: it pairs every
//! half-edge again, cleans up, recomputes the normals and coplanar groups and sorts — as much
//! work as importing the parts afresh. C++ Manifold's `CsgLeafNode::Compose` instead copies its
//! parts' half-edges with their indices shifted and sorts them, and its lazily transformed
//! leaves share their topology with the manifold they were made from. This is that path for
//! parts already valid: an instanced pattern (a sphere translated to 21 places) is imported
//! once and copied 20 times.

use std::collections::HashMap;
use std::sync::Arc;

use super::Manifold;
use crate::impl_mesh::ManifoldImpl;
use crate::linalg::Vec3;
use crate::types::{Error, Halfedge, TriRef};

/// One part of [`Manifold::compose_apart`].
pub struct ApartPart<'a> {
    /// The part.
    pub part: &'a Manifold,
    /// Where its vertices go, in its own vertex order, for a translated copy: every vertex
    /// moved by one vector, within the part's epsilon (checked). `None` leaves the part where
    /// it is.
    pub moved_to: Option<Vec<Vec3>>,
    /// Added to the face ID of each of its triangles that has one.
    pub face_id_shift: i32,
}

impl Manifold {
    /// The union of `parts` whose bounding boxes are pairwise apart (no two touch), each
    /// optionally translated (see [`ApartPart`]), without importing them again: their
    /// half-edges, normals and coplanar groups are copied with their indices shifted, each
    /// part keeps its own mesh IDs (renumbered as `compose` renumbers them), and nothing is
    /// sorted: the parts go in the Morton order of their boxes' centres, each keeping its own
    /// order (spatially coherent: every manifold is sorted when made), and the collider joins
    /// the parts' own (`Collider::compose`). Linear in the parts' size.
    ///
    /// The parts' clean-up (short edges, degenerate triangles) is not run again, so each part
    /// must already have been cleaned at an epsilon no smaller than the result's; the result
    /// keeps the parts' largest epsilon and tolerance.
    ///
    /// `None` (and nothing composed) when a condition does not hold: no parts; a part empty,
    /// invalid, a soup, or carrying properties or tangents; positions of the wrong count, not
    /// finite or not one translation; two boxes not apart; a part's epsilon smaller than the
    /// result's automatic one. The caller then composes another way (`Manifold::compose`, or a
    /// fresh import of all the parts).
    pub fn compose_apart(parts: &[ApartPart<'_>]) -> Option<Manifold> {
        Self::compose_apart_from(parts, PAR_HALFEDGES)
    }

    /// [`Manifold::compose_apart`], the parts checked and placed in parallel (one part a
    /// task) from `par_halfedges` half-edges in all.
    fn compose_apart_from(parts: &[ApartPart<'_>], par_halfedges: usize) -> Option<Manifold> {
        if parts.is_empty() {
            return None;
        }
        let fits = parts.iter().all(|p| {
            let m = &p.part.imp;
            m.status == Error::NoError
                && !m.is_soup
                && !m.halfedge.is_empty()
                && m.num_prop == 0
                && m.halfedge_tangent.is_empty()
                && m.vert_normal.len() == m.vert_pos.len()
                && m.face_normal.len() == m.num_tri()
                && m.mesh_relation.tri_ref.len() == m.num_tri()
        });
        if !fits {
            return None;
        }
        // One part a task when they are large in all.
        let num_halfedge: usize = parts.iter().map(|p| p.part.imp.halfedge.len()).sum();
        let threshold = if num_halfedge >= par_halfedges { 2 } else { usize::MAX };
        // The parts' boxes (a copy's checked vertex by vertex).
        let boxes: Vec<Option<(Vec3, Vec3)>> =
            crate::par::maybe_par_map(parts.len(), threshold, |i| {
                let (p, m) = (&parts[i], &parts[i].part.imp);
                match &p.moved_to {
                    None => Some((m.bbox.min, m.bbox.max)),
                    Some(to) => translation_bounds(&m.vert_pos, to, m.epsilon),
                }
            });
        let boxes: Vec<(Vec3, Vec3)> = boxes.into_iter().collect::<Option<_>>()?;
        if !pairwise_apart(&boxes) {
            return None;
        }

        let mut out = ManifoldImpl::new();
        // Each part's mesh IDs become local IDs 1, 2, 3, … in part order, as `compose_meshes`
        // numbers them, so `increment_mesh_ids` hands out fresh ones in a deterministic order
        // and two copies of one part stay two instances.
        let mut next_local = 1i32;
        let order = spatial_order(&boxes);
        let mut locals = Vec::with_capacity(order.len());
        for &i in &order {
            let mut local = std::collections::HashMap::new();
            for (id, relation) in &parts[i].part.imp.mesh_relation.mesh_id_transform {
                local.insert(*id, next_local);
                out.mesh_relation
                    .mesh_id_transform
                    .insert(next_local, relation.clone());
                next_local += 1;
            }
            locals.push(local);
        }
        // The parts laid end to end in `order`: each one's first vertex and first half-edge.
        let starts = |size: fn(&ManifoldImpl) -> usize| -> Vec<usize> {
            let mut acc = 0;
            let mut starts: Vec<usize> = order
                .iter()
                .map(|&i| {
                    let start = acc;
                    acc += size(&parts[i].part.imp);
                    start
                })
                .collect();
            starts.push(acc);
            starts
        };
        let vert_starts = starts(|m| m.vert_pos.len());
        let edge_starts = starts(|m| m.halfedge.len());
        let tri_starts: Vec<usize> = edge_starts.iter().map(|&e| e / 3).collect();
        let imp = |k: usize| &parts[order[k]].part.imp;
        out.vert_pos = crate::par::concatenated(&vert_starts, threshold, |k| {
            let p = &parts[order[k]];
            p.moved_to.as_deref().unwrap_or(&p.part.imp.vert_pos).iter().copied()
        });
        out.vert_normal = crate::par::concatenated(&vert_starts, threshold, |k| imp(k).vert_normal.iter().copied());
        out.face_normal = crate::par::concatenated(&tri_starts, threshold, |k| imp(k).face_normal.iter().copied());
        out.halfedge = crate::par::concatenated(&edge_starts, threshold, |k| {
            let (vert_offset, edge_offset) = (vert_starts[k] as i32, edge_starts[k] as i32);
            imp(k).halfedge.iter().map(move |h| Halfedge {
                start_vert: h.start_vert + vert_offset,
                end_vert: h.end_vert + vert_offset,
                paired_halfedge: if h.paired_halfedge < 0 {
                    h.paired_halfedge
                } else {
                    h.paired_halfedge + edge_offset
                },
                prop_vert: h.prop_vert + vert_offset,
            })
        });
        out.mesh_relation.tri_ref = crate::par::concatenated(&tri_starts, threshold, |k| {
            let (local, shift, tri_offset) = (&locals[k], parts[order[k]].face_id_shift, tri_starts[k] as i32);
            imp(k).mesh_relation.tri_ref.iter().map(move |r| TriRef {
                mesh_id: local.get(&r.mesh_id).copied().unwrap_or(r.mesh_id),
                original_id: r.original_id,
                face_id: if r.face_id >= 0 { r.face_id + shift } else { r.face_id },
                coplanar_id: r.coplanar_id + tri_offset,
            })
        });
        out.mesh_relation.original_id = -1;
        out.calculate_bbox();
        out.set_epsilon(-1.0, false);
        if parts.iter().any(|p| p.part.imp.epsilon < out.epsilon) {
            return None;
        }
        out.epsilon = parts
            .iter()
            .map(|p| p.part.imp.epsilon)
            .fold(out.epsilon, f64::max);
        out.tolerance = parts
            .iter()
            .map(|p| p.part.imp.tolerance)
            .fold(out.tolerance, f64::max);
        // No sort: the parts come in the order of their boxes' Morton codes, each already in
        // its own Morton order (every part was sorted when it was made), so the face order is
        // spatially coherent as it stands. The parts' own trees are kept (a copy's moved, and
        // widened by twice its epsilon, within which it is a translate), joined by a tree over
        // the parts; a part without a tree has one built over the whole, with the faces'
        // positions as their codes.
        // Each part's tree is shared, not copied (patch 20): one for all the copies of a part.
        let mut shared: HashMap<*const crate::collider::Collider, Arc<crate::collider::Collider>> = HashMap::new();
        let trees: Vec<(Arc<crate::collider::Collider>, Vec3, f64)> = order
            .iter()
            .map(|&i| {
                let m = &parts[i].part.imp;
                let key: *const crate::collider::Collider = &m.collider;
                let tree = Arc::clone(shared.entry(key).or_insert_with(|| Arc::new(m.collider.clone())));
                match &parts[i].moved_to {
                    Some(to) => (tree, to[0] - m.vert_pos[0], 2.0 * m.epsilon),
                    None => (tree, Vec3::splat(0.0), 0.0),
                }
            })
            .collect();
        out.collider = match crate::collider::Collider::compose(&trees) {
            Some(c) if c.num_leaves() == out.num_tri() => c,
            _ => {
                let (face_box, _) = crate::sort::get_face_box_morton(&out);
                let codes = (0..face_box.len() as u32).collect();
                crate::collider::Collider::new(face_box, codes)
            }
        };
        out.increment_mesh_ids();
        Some(Manifold::from_impl(out))
    }
}

/// Half-edges in all from which the parts are checked and placed in parallel (as `sort.rs`'s
/// `PAR_THRESHOLD`). blocksmith patch (PATCHES.md, 19).
const PAR_HALFEDGES: usize = 100_000;

/// The order of the boxes `(min, max)` by the Morton codes of their centres in the box around
/// them all (ties in index order).
fn spatial_order(boxes: &[(Vec3, Vec3)]) -> Vec<usize> {
    let mut all = crate::types::Box::default();
    for &(lo, hi) in boxes {
        all.union_point(lo);
        all.union_point(hi);
    }
    let mut order: Vec<(u32, usize)> = boxes
        .iter()
        .enumerate()
        .map(|(i, &(lo, hi))| (crate::sort::morton_code((lo + hi) / 2.0, &all), i))
        .collect();
    order.sort_unstable();
    order.into_iter().map(|(_, i)| i).collect()
}

/// The bounds of `to` when it is `from` moved by one vector within `epsilon` (the vector
/// taken from the first vertex), else `None`.
fn translation_bounds(from: &[Vec3], to: &[Vec3], epsilon: f64) -> Option<(Vec3, Vec3)> {
    if from.len() != to.len() || from.is_empty() {
        return None;
    }
    let d = to[0] - from[0];
    let mut lo = to[0];
    let mut hi = to[0];
    for (&a, &b) in from.iter().zip(to) {
        let off = b - a - d;
        let finite = b.x.is_finite() && b.y.is_finite() && b.z.is_finite();
        if !finite || off.x.abs() > epsilon || off.y.abs() > epsilon || off.z.abs() > epsilon {
            return None;
        }
        lo = Vec3::new(lo.x.min(b.x), lo.y.min(b.y), lo.z.min(b.z));
        hi = Vec3::new(hi.x.max(b.x), hi.y.max(b.y), hi.z.max(b.z));
    }
    Some((lo, hi))
}

/// Whether no two of the boxes `(min, max)` touch: a sweep along x, each box compared with the
/// earlier ones whose x-range reaches it.
fn pairwise_apart(boxes: &[(Vec3, Vec3)]) -> bool {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x).then(a.cmp(&b)));
    let mut active: Vec<usize> = Vec::new();
    for &i in &order {
        let (lo, hi) = boxes[i];
        active.retain(|&j| boxes[j].1.x >= lo.x);
        for &j in &active {
            let (jl, jh) = boxes[j];
            let apart = jh.x < lo.x
                || hi.x < jl.x
                || jh.y < lo.y
                || hi.y < jl.y
                || jh.z < lo.z
                || hi.z < jl.z;
            if !apart {
                return false;
            }
        }
        active.push(i);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere_at(x: f64, y: f64) -> Manifold {
        Manifold::sphere(1.0, 32).translate(Vec3::new(x, y, 0.0))
    }

    #[test]
    fn composing_apart_gives_what_compose_gives() {
        // Equally far from the origin, so each part's epsilon is the result's.
        let parts = [
            sphere_at(0.0, 3.0),
            sphere_at(3.0, 0.0),
            sphere_at(-3.0, 0.0),
        ];
        let placed: Vec<ApartPart<'_>> = parts
            .iter()
            .map(|part| ApartPart {
                part,
                moved_to: None,
                face_id_shift: 0,
            })
            .collect();
        let apart = Manifold::compose_apart(&placed).expect("apart");
        let composed = Manifold::compose(&parts);
        assert_eq!(apart.num_tri(), composed.num_tri());
        assert_eq!(apart.num_vert(), composed.num_vert());
        assert!((apart.volume() - composed.volume()).abs() < 1e-12 * composed.volume());
        assert!(apart.as_impl().is_manifold());
        // The collider built over the unsorted order finds every face.
        assert_eq!(crate::sort::collider_self_misses(apart.as_impl()), 0);
        // Usable in a boolean: a box through all three spheres.
        let bar = Manifold::cube(Vec3::new(8.0, 0.5, 0.5), true);
        let a = apart.difference(&bar);
        let b = composed.difference(&bar);
        assert_eq!(a.status(), Error::NoError);
        assert!((a.volume() - b.volume()).abs() < 1e-9 * b.volume());
        assert_eq!(a.num_tri(), b.num_tri());
    }

    #[test]
    fn parts_placed_in_parallel_are_placed_as_one_at_a_time() {
        // The copies no farther from the origin than the part, so its epsilon holds.
        let s = sphere_at(20.0, 0.0);
        let copies: Vec<ApartPart<'_>> = (0..6)
            .map(|k| {
                let d = Vec3::new(-3.0 * k as f64, 1.5 * k as f64, 0.25);
                ApartPart {
                    part: &s,
                    moved_to: (k > 0).then(|| s.as_impl().vert_pos.iter().map(|&p| p + d).collect()),
                    face_id_shift: 100 * k,
                }
            })
            .collect();
        let one_at_a_time = Manifold::compose_apart_from(&copies, usize::MAX).expect("apart");
        let in_parallel = Manifold::compose_apart_from(&copies, 0).expect("apart");
        let (a, b) = (one_at_a_time.as_impl(), in_parallel.as_impl());
        assert_eq!(a.num_tri(), 6 * s.num_tri());
        let bits = |v: &[Vec3]| v.iter().map(|p| [p.x, p.y, p.z].map(f64::to_bits)).collect::<Vec<_>>();
        assert!(bits(&a.vert_pos) == bits(&b.vert_pos), "positions");
        assert!(bits(&a.vert_normal) == bits(&b.vert_normal), "vertex normals");
        assert!(bits(&a.face_normal) == bits(&b.face_normal), "face normals");
        assert!(a.halfedge == b.halfedge, "half-edges");
        // Each composition hands out fresh mesh IDs: the same ones, from another start.
        let relative = |m: &ManifoldImpl| {
            let first = m.mesh_relation.tri_ref.iter().map(|r| r.mesh_id).min().unwrap_or(0);
            m.mesh_relation
                .tri_ref
                .iter()
                .map(|r| TriRef { mesh_id: r.mesh_id - first, ..*r })
                .collect::<Vec<_>>()
        };
        let (ra, rb) = (relative(a), relative(b));
        assert!(ra == rb, "triangle references");
        let instances: std::collections::BTreeSet<i32> = ra.iter().map(|r| r.mesh_id).collect();
        assert_eq!(instances.len(), 6, "six instances");
        assert!(b.is_manifold());
        // A copy that is not one translation is refused on both paths.
        let mut bent = copies;
        if let Some(to) = bent[3].moved_to.as_mut() {
            to[5].x += 0.5;
        }
        assert!(Manifold::compose_apart_from(&bent, 0).is_none());
        assert!(Manifold::compose_apart_from(&bent, usize::MAX).is_none());
    }

    #[test]
    fn a_translated_copy_is_the_translated_part() {
        // The copy no farther from the origin than the part, so the part's epsilon holds.
        let s = sphere_at(10.0, 0.0);
        let d = Vec3::new(-20.0, 1.0, -2.0);
        let moved: Vec<Vec3> = s.as_impl().vert_pos.iter().map(|&p| p + d).collect();
        let copies = [
            ApartPart {
                part: &s,
                moved_to: None,
                face_id_shift: 0,
            },
            ApartPart {
                part: &s,
                moved_to: Some(moved),
                face_id_shift: 7,
            },
        ];
        let both = Manifold::compose_apart(&copies).expect("apart");
        assert_eq!(both.num_tri(), 2 * s.num_tri());
        assert!((both.volume() - 2.0 * s.volume()).abs() < 1e-12 * s.volume());
        let b = both.bounding_box();
        assert!((b.min.x - (-11.0)).abs() < 1e-12 && (b.max.x - 11.0).abs() < 1e-12);
        assert!(both.as_impl().is_manifold());
        assert_eq!(crate::sort::collider_self_misses(both.as_impl()), 0);
        // Cut by a slab through the part's bottom and the copy's top: as the composed pair is.
        let composed = Manifold::compose(&[s.clone(), s.translate(d)]);
        let slab =
            Manifold::cube(Vec3::new(30.0, 30.0, 0.2), true).translate(Vec3::new(0.0, 0.0, -1.0));
        let (cut, expected) = (both.difference(&slab), composed.difference(&slab));
        assert_eq!(cut.status(), Error::NoError);
        assert!(cut.volume() < both.volume() - 1e-3, "the slab cuts");
        assert!((cut.volume() - expected.volume()).abs() < 1e-9 * expected.volume());
        assert_eq!(cut.num_tri(), expected.num_tri());
        // The copy's face IDs are shifted; the original's are not.
        let ids: std::collections::BTreeSet<i32> = both
            .as_impl()
            .mesh_relation
            .tri_ref
            .iter()
            .map(|r| r.face_id)
            .collect();
        let own: std::collections::BTreeSet<i32> = s
            .as_impl()
            .mesh_relation
            .tri_ref
            .iter()
            .map(|r| r.face_id)
            .collect();
        let shifted: std::collections::BTreeSet<i32> = own
            .iter()
            .map(|&f| if f >= 0 { f + 7 } else { f })
            .collect();
        assert_eq!(ids, own.union(&shifted).copied().collect());
    }

    #[test]
    fn what_does_not_hold_is_refused() {
        let s = sphere_at(0.0, 0.0);
        let t = sphere_at(1.5, 0.0);
        let part = |m| ApartPart {
            part: m,
            moved_to: None,
            face_id_shift: 0,
        };
        // Overlapping boxes.
        assert!(Manifold::compose_apart(&[part(&s), part(&t)]).is_none());
        assert!(Manifold::compose_apart(&[]).is_none());
        // Not one translation.
        let mut bent: Vec<Vec3> = s
            .as_impl()
            .vert_pos
            .iter()
            .map(|&p| p + Vec3::new(4.0, 0.0, 0.0))
            .collect();
        bent[3].y += 0.1;
        assert!(Manifold::compose_apart(&[
            part(&s),
            ApartPart {
                part: &s,
                moved_to: Some(bent),
                face_id_shift: 0
            }
        ])
        .is_none());
        // The wrong count, or not finite.
        let short = vec![Vec3::new(9.0, 0.0, 0.0)];
        assert!(Manifold::compose_apart(&[ApartPart {
            part: &s,
            moved_to: Some(short),
            face_id_shift: 0
        }])
        .is_none());
        let mut nan: Vec<Vec3> = s.as_impl().vert_pos.clone();
        nan[0].x = f64::NAN;
        assert!(Manifold::compose_apart(&[ApartPart {
            part: &s,
            moved_to: Some(nan),
            face_id_shift: 0
        }])
        .is_none());
        // A part cleaned at a finer epsilon than the result's: a copy farther from the origin.
        let far: Vec<Vec3> = s
            .as_impl()
            .vert_pos
            .iter()
            .map(|&p| p + Vec3::new(1e3, 0.0, 0.0))
            .collect();
        assert!(Manifold::compose_apart(&[
            part(&s),
            ApartPart {
                part: &s,
                moved_to: Some(far),
                face_id_shift: 0
            }
        ])
        .is_none());
    }
}
