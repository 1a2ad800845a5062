// apart_runs_tests.rs — blocksmith patch (PATCHES.md, 26): a composition's parts are found and
// checked, and a boolean on them part by part is the boolean in one run.

use super::*;
use crate::linalg::Vec3;
use crate::manifold::{ApartPart, Manifold};
use crate::types::OpType;

/// `n` spheres of radius 1 on a circle of radius 4, `n` 4 or less (the same largest coordinate,
/// so each part's epsilon is the composition's), composed of parts apart.
fn spheres(n: usize) -> (Vec<Manifold>, Manifold) {
    let at = |i: usize| {
        let angle = std::f64::consts::TAU * i as f64 / n as f64;
        Vec3::new(4.0 * angle.cos(), 4.0 * angle.sin(), 0.0)
    };
    let parts: Vec<Manifold> = (0..n).map(|i| Manifold::sphere(1.0, 48).translate(at(i))).collect();
    let placed: Vec<ApartPart<'_>> =
        parts.iter().map(|part| ApartPart { part, moved_to: None, face_id_shift: 0 }).collect();
    let composed = Manifold::compose_apart(&placed).expect("apart");
    (parts, composed)
}

#[test]
fn a_composition_gives_its_parts_and_a_changed_one_none() {
    let (parts, composed) = spheres(4);
    let runs = parts_apart(composed.as_impl()).expect("the parts");
    assert_eq!(runs.len(), 4);
    let (mut face, mut vert) = (0, 0);
    for (run, part) in runs.iter().zip(&parts) {
        assert_eq!(run.faces, face..face + part.num_tri());
        assert_eq!(run.verts, vert..vert + part.num_vert());
        face += part.num_tri();
        vert += part.num_vert();
    }
    assert_eq!(face, composed.num_tri());
    // One mesh is no parts; neither is a composition whose half-edge pairs or vertices cross
    // from one part into another.
    assert_eq!(parts_apart(parts[0].as_impl()), None);
    let second = 3 * runs[1].faces.start;
    let mut paired_across = composed.as_impl().clone();
    paired_across.halfedge[1].paired_halfedge = second as i32;
    assert_eq!(parts_apart(&paired_across), None);
    let mut vertex_across = composed.as_impl().clone();
    vertex_across.halfedge[1].end_vert = runs[2].verts.start as i32;
    assert_eq!(parts_apart(&vertex_across), None);
    // Too small to gain: a part of two.
    let (_, small) = {
        let parts: Vec<Manifold> =
            [-3.5, 2.5].map(|x| Manifold::cube(Vec3::splat(1.0), false).translate(Vec3::new(x, 0.0, 0.0))).into();
        let placed: Vec<ApartPart<'_>> =
            parts.iter().map(|part| ApartPart { part, moved_to: None, face_id_shift: 0 }).collect();
        let composed = Manifold::compose_apart(&placed).expect("apart");
        (parts, composed)
    };
    assert_eq!(parts_apart(small.as_impl()), None);
}

/// Everything an export reads: positions (bits), triangles, face IDs.
fn exported(m: &Manifold) -> (Vec<u64>, Vec<u64>, Vec<u64>) {
    let g = m.get_mesh_gl64(-1);
    (g.vert_properties.iter().map(|p| p.to_bits()).collect(), g.tri_verts.clone(), g.face_id.clone())
}

/// A slab through the spheres' middles, every operation both ways round, with the composition
/// as either operand: the same result part by part as in one run (the windings of the parts'
/// vertices and their whole edges are what the parts change).
#[test]
fn a_boolean_on_parts_apart_is_the_boolean_in_one_run() {
    let (_, composed) = spheres(4);
    assert!(parts_apart(composed.as_impl()).is_some());
    let slab = Manifold::cube(Vec3::new(12.0, 12.0, 1.2), false).translate(Vec3::new(-6.0, -6.0, -0.3));
    for op in [OpType::Add, OpType::Subtract, OpType::Intersect] {
        for (a, b) in [(&slab, &composed), (&composed, &slab)] {
            let parted = a.boolean(b, op);
            set_one_run_only(true);
            let one_run = a.boolean(b, op);
            set_one_run_only(false);
            assert!(parted.num_tri() > 0, "{op:?}");
            assert_eq!(exported(&parted), exported(&one_run), "{op:?}");
            let export = a.boolean_for_export_with_token(b, op, None);
            set_one_run_only(true);
            let one_run_export = a.boolean_for_export_with_token(b, op, None);
            set_one_run_only(false);
            assert_eq!(exported(&export), exported(&one_run_export), "{op:?}, for export");
        }
    }
}

/// The whole edges of a composition appended part by part fill every slot, pointer and
/// reference as the one pass does, slot for slot: inclusions of -1 (reversed), 0 (left out),
/// 1 and 2 (doubled) dealt over the vertices.
#[test]
fn whole_edges_part_by_part_are_the_one_pass_slot_for_slot() {
    use crate::boolean_result::{append_whole_edges, append_whole_edges_in_parts};
    use crate::types::{Halfedge, TriRef};
    let (_, composed) = spheres(4);
    let m = composed.as_impl();
    let mut x = 0x2545_f491u32;
    let i03: Vec<i32> = (0..m.vert_pos.len())
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            [-1, 0, 1, 1, 2][x as usize % 5]
        })
        .collect();
    let vp2r: Vec<i32> = i03.iter().scan(0, |next, &i| Some(std::mem::replace(next, *next + i.abs()))).collect();
    // Each face's slots: the inclusion of each of its edges' forward half-edge's start.
    let sides: Vec<i32> = (0..m.num_tri())
        .map(|f| {
            (3 * f..3 * f + 3)
                .map(|e| {
                    let h = m.halfedge[e];
                    i03[if h.is_forward() { h.start_vert } else { h.end_vert } as usize].abs()
                })
                .sum()
        })
        .collect();
    let mut face_p2r = Vec::with_capacity(sides.len());
    let mut face_edge = vec![0];
    for &s in &sides {
        face_p2r.push(face_edge.len() as i32 - 1);
        if s > 0 {
            face_edge.push(face_edge.last().unwrap() + s);
        }
    }
    let slots = *face_edge.last().unwrap() as usize;
    let whole = vec![true; m.halfedge.len()];
    let unset = Halfedge { start_vert: -1, end_vert: -1, paired_halfedge: -1, prop_vert: -1 };
    let run = |parts: bool| {
        let mut out = ManifoldImpl::new();
        out.halfedge = vec![unset; slots];
        let mut face_ptr = face_edge[..face_edge.len() - 1].to_vec();
        let mut refs = vec![TriRef::default(); slots];
        if parts {
            let end = face_edge.len() - 1;
            let parts = parts_apart(m);
            assert!(parts.is_some());
            append_whole_edges_in_parts(&mut out, &mut face_ptr, &mut refs, m, &whole, &i03, &vp2r, &face_p2r, false, parts.as_deref(), &face_edge, end);
        } else {
            append_whole_edges(&mut out, &mut face_ptr, &mut refs, m, &whole, &i03, &vp2r, &face_p2r, false);
        }
        (out.halfedge, face_ptr, refs)
    };
    let one_pass = run(false);
    assert!(one_pass.0.iter().all(|h| h.start_vert >= 0), "every slot filled");
    assert_eq!(run(true), one_pass);
}
