//! Tests of the flat-shell removal ([`without_flat_shells`]) on triangles as the engine gives
//! them: a closed shell of no volume goes, the rest stays, whatever the number of threads.

use super::*;

/// A closed triangle mesh's triangles with the engine's pairing, each tagged `tag`.
fn paired(mesh: &Mesh, tag: u32) -> PairedTriangles {
    PairedTriangles {
        positions: mesh.positions().to_vec(),
        corners: (0..mesh.face_count() as u32).flat_map(|f| mesh.face_vertices(f)).collect(),
        pairs: corner_pairs(mesh),
        tags: vec![tag; mesh.face_count()],
    }
}

/// A flat shell: one triangle and its reverse, at `at`, tagged `tag`.
fn sheet(at: Vec3, tag: u32) -> PairedTriangles {
    PairedTriangles {
        positions: vec![at, at + Vec3::X, at + Vec3::Y],
        corners: vec![0, 1, 2, 0, 2, 1],
        // 0→1 runs back as the reverse's 1→0 (its third edge), 1→2 as 2→1, 2→0 as 0→2.
        pairs: vec![5, 4, 3, 2, 1, 0],
        tags: vec![tag; 2],
    }
}

/// The triangles of `parts`, one after another.
fn joined(parts: &[PairedTriangles]) -> PairedTriangles {
    let mut out = PairedTriangles::default();
    for p in parts {
        let (v, h) = (out.positions.len() as u32, out.corners.len() as u32);
        out.positions.extend_from_slice(&p.positions);
        out.corners.extend(p.corners.iter().map(|&c| c + v));
        out.pairs.extend(p.pairs.iter().map(|&q| q + h));
        out.tags.extend_from_slice(&p.tags);
    }
    out
}

#[test]
fn flat_shells_go_and_the_rest_stays_whatever_the_threads() {
    // More triangles than one run of the sums, so the shells' sums meet across runs.
    let ball = Mesh::icosphere(1.0, 5).triangulate().unwrap();
    assert!(ball.face_count() > SHELL_SUM_RUN);
    let input = joined(&[sheet(Vec3::new(5.0, 0.0, 0.0), 7), paired(&ball, 1), sheet(Vec3::new(-5.0, 0.0, 0.0), 8)]);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| without_flat_shells(input.clone()))
    };
    let out = on(1);
    assert_eq!(out, on(3), "the same triangles on one thread and on three");
    assert_eq!(out.corners.len(), 3 * ball.face_count(), "both sheets go, the ball stays");
    assert_eq!(out.positions.len(), ball.vertex_count());
    assert!(out.tags.iter().all(|&t| t == 1));
    for (h, &q) in out.pairs.iter().enumerate() {
        assert_eq!(out.pairs[q as usize] as usize, h, "half-edge {h} pairs both ways");
    }
    // Without a flat shell nothing changes.
    let ball_only = paired(&ball, 1);
    assert_eq!(without_flat_shells(ball_only.clone()), ball_only);
}
