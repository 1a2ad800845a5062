//! The marching-cubes case table, generated rather than typed in, with one rule that makes every
//! output closed and manifold.
//!
//! Cube corners `c = x + 2y + 4z`; a corner is inside when its sample is above the iso level.
//! Edge ids 0–11: axis-major (`axis · 4 + rank`), each from its lower corner to the corner one
//! step along the axis.
//!
//! Construction, per case: on each of the 6 faces, walk the 4 corners counter-clockwise seen from
//! outside the cube; each edge whose ends differ is a crossing, an *entry* (outside → inside) or
//! an *exit*. Each entry is joined to the next crossing (an exit) by a segment, entry → exit.
//! On a face with two diagonal inside corners (the ambiguous face) this cuts each inside corner off
//! on its own, so the inside corners are always separated — and since the rule depends only on the
//! face's four signs, the two cubes sharing a face draw the same segments (in opposite directions):
//! no cracks. Every crossing edge lies on two faces and is an entry on one and an exit on the
//! other, so the segments chain into closed loops; each loop becomes a fan of triangles from an
//! apex chosen so that no diagonal of the fan joins two points on one face (such a diagonal could
//! be repeated by the neighbouring cube). The result, over a grid, is a closed 2-manifold whose
//! triangles face outward (from inside corners to outside ones). This is the classic table with a
//! fixed ambiguity rule (Lorensen & Cline 1987 with the "separate the inside corners" face
//! decision), not Marching Cubes 33; the tunnels it cannot represent only change topology inside a
//! cell, never closedness.

use std::sync::OnceLock;

/// The 12 cube edges as (lower corner, upper corner), axis-major.
pub(super) const EDGES: [(u8, u8); 12] = {
    let mut e = [(0u8, 0u8); 12];
    let mut k = 0;
    let mut axis = 0;
    while axis < 3 {
        let mut c = 0u8;
        while c < 8 {
            if c & (1 << axis) == 0 {
                e[k] = (c, c | (1 << axis));
                k += 1;
            }
            c += 1;
        }
        axis += 1;
    }
    e
};

/// The triangles of every case as triples of edge ids, in one list with per-case ranges.
pub(super) struct CaseTable {
    ranges: [(u16, u8); 256],
    triangles: Vec<[u8; 3]>,
}

impl CaseTable {
    /// The triangles of case `case` (bit c set when corner c is inside).
    #[inline]
    pub(super) fn triangles(&self, case: u8) -> &[[u8; 3]] {
        let (start, count) = self.ranges[case as usize];
        &self.triangles[start as usize..start as usize + count as usize]
    }
}

/// The table, built once.
pub(super) fn table() -> &'static CaseTable {
    static TABLE: OnceLock<CaseTable> = OnceLock::new();
    TABLE.get_or_init(build)
}

fn edge_id(a: u8, b: u8) -> u8 {
    let (a, b) = (a.min(b), a.max(b));
    EDGES.iter().position(|&e| e == (a, b)).expect("corners one step apart form an edge") as u8
}

/// The 6 faces as 4 corners counter-clockwise seen from outside.
fn faces() -> [[u8; 4]; 6] {
    let mut out = [[0u8; 4]; 6];
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in 0..2u8 {
            let corner = |cu: u8, cv: u8| (side << axis) | (cu << u) | (cv << v);
            // (u, v, axis) is right-handed, so (0,0) (1,0) (1,1) (0,1) turns counter-clockwise
            // about +axis; the face at side 0 looks along −axis and takes the reverse order.
            out[axis * 2 + side as usize] = if side == 1 {
                [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
            } else {
                [corner(0, 0), corner(0, 1), corner(1, 1), corner(1, 0)]
            };
        }
    }
    out
}

/// Whether edges `e1` and `e2` lie on a common cube face.
fn share_face(e1: u8, e2: u8) -> bool {
    let (a, b) = EDGES[e1 as usize];
    let (c, d) = EDGES[e2 as usize];
    (0..3).any(|axis| {
        let bit = 1 << axis;
        [0, bit].iter().any(|&side| [a, b, c, d].iter().all(|&p| p & bit == side))
    })
}

/// The loops (as edge ids, in order) of one case.
pub(super) fn loops(case: u8) -> Vec<Vec<u8>> {
    let inside = |c: u8| case & (1 << c) != 0;
    let mut next = [u8::MAX; 12];
    for face in faces() {
        let mut crossings = Vec::new();
        for k in 0..4 {
            let (a, b) = (face[k], face[(k + 1) % 4]);
            if inside(a) != inside(b) {
                crossings.push((edge_id(a, b), inside(b)));
            }
        }
        for (k, &(e, entry)) in crossings.iter().enumerate() {
            if entry {
                let (exit, is_entry) = crossings[(k + 1) % crossings.len()];
                debug_assert!(!is_entry, "crossings alternate around a face");
                next[e as usize] = exit;
            }
        }
    }
    let mut seen = [false; 12];
    let mut out = Vec::new();
    for start in 0..12u8 {
        if next[start as usize] == u8::MAX || seen[start as usize] {
            continue;
        }
        let mut lp = Vec::new();
        let mut e = start;
        while !seen[e as usize] {
            seen[e as usize] = true;
            lp.push(e);
            e = next[e as usize];
        }
        out.push(lp);
    }
    out
}

/// The fan apex of a loop: the first vertex none of whose diagonals joins two points on a face.
pub(super) fn apex(lp: &[u8]) -> Option<usize> {
    let k = lp.len();
    (0..k).find(|&a| (2..k - 1).all(|d| !share_face(lp[a], lp[(a + d) % k])))
}

fn build() -> CaseTable {
    let mut ranges = [(0u16, 0u8); 256];
    let mut triangles = Vec::new();
    for case in 0..=255u8 {
        let start = triangles.len();
        for lp in loops(case) {
            let a = apex(&lp).expect("every marching-cubes loop has a safe fan apex (checked by a test)");
            let k = lp.len();
            for i in 1..k - 1 {
                triangles.push([lp[a], lp[(a + i) % k], lp[(a + i + 1) % k]]);
            }
        }
        ranges[case as usize] = (start as u16, (triangles.len() - start) as u8);
    }
    CaseTable { ranges, triangles }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_loop_of_every_case_has_a_safe_apex() {
        for case in 0..=255u8 {
            for lp in loops(case) {
                assert!(lp.len() >= 3, "case {case}: loop {lp:?}");
                assert!(apex(&lp).is_some(), "case {case}: loop {lp:?} has no safe apex");
            }
        }
    }

    #[test]
    fn crossing_edges_each_belong_to_exactly_one_loop() {
        for case in 0..=255u8 {
            let mut count = [0; 12];
            for lp in loops(case) {
                for e in lp {
                    count[e as usize] += 1;
                }
            }
            for (e, &(a, b)) in EDGES.iter().enumerate() {
                let crosses = ((case >> a) & 1) != ((case >> b) & 1);
                assert_eq!(count[e], usize::from(crosses), "case {case}, edge {e}");
            }
        }
    }

    #[test]
    fn single_corners_give_one_triangle_and_ambiguous_faces_separate_inside_corners() {
        // One inside corner: a single triangle; the empty and full cases: none.
        assert_eq!(table().triangles(0).len(), 0);
        assert_eq!(table().triangles(255).len(), 0);
        for c in 0..8 {
            assert_eq!(table().triangles(1 << c).len(), 1);
            assert_eq!(table().triangles(!(1u8 << c)).len(), 1);
        }
        // Two diagonal corners of a face are separated: two triangles, not a quad strip.
        assert_eq!(loops(0b0000_1001).len(), 2);
        // Their complement (six inside) separates the inside corners 1 and 2 on that face, so the
        // two outside corners are joined across it: one loop around the joined outside region.
        assert_eq!(loops(!0b0000_1001u8).len(), 1);
    }
}
