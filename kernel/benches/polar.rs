//! Polar-mesh operations (seed 004, ch. 4) on meshes of 10k, 100k and 1M faces, and skeleton
//! inference (§7.1) on a 400k-vertex mesh.
//!
//! Inputs: UV spheres as polar meshes with 64 segments and 157, 1563 or 15625 bands (10,048,
//! 100,032 and 1,000,000 faces), so a loop has 64 edges at every size: the operations acting on a
//! loop or a feature touch the same number of faces whatever the mesh size, and their time must
//! stay flat. A backbone runs from pole to pole through every band, so adding or removing one
//! touches 2·bands faces and its time grows with the bands (its affected region), not the faces.
//!
//! Every operation is timed alone inside a cycle that restores the mesh (add then remove, merge
//! then split), so nothing is cloned. Run: `cargo bench -p blocksmith-kernel --bench polar`.

use std::hint::black_box;
use std::time::{Duration, Instant};

use blocksmith_kernel::polar::PolarMesh;
use blocksmith_kernel::Mesh;
use criterion::{criterion_group, criterion_main, Criterion};

const SEGMENTS: u32 = 64;

/// Vertex `i` of band-boundary loop `j` (1-based) of the UV sphere.
fn ring(j: u32, i: u32) -> u32 {
    1 + (j - 1) * SEGMENTS + i % SEGMENTS
}

fn he(pm: &PolarMesh, a: u32, b: u32) -> i64 {
    i64::from(pm.mesh().find_halfedge(a, b).expect("edge"))
}

fn operations(c: &mut Criterion) {
    for (label, bands) in [("10k", 157u32), ("100k", 1563), ("1M", 15625)] {
        let mut pm = PolarMesh::uv_sphere(1.0, SEGMENTS, bands);
        let j = bands / 2;
        let mut g = c.benchmark_group(format!("polar/{label}_faces"));
        g.sample_size(20).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));

        // Add / remove a loop (64 edges) in the middle band.
        g.bench_function("add_refinement_loop", |b| {
            b.iter_custom(|n| {
                let mut total = Duration::ZERO;
                for _ in 0..n {
                    let t = Instant::now();
                    let r = pm.add_refinement(he(&pm, ring(j, 0), ring(j + 1, 0))).unwrap();
                    total += t.elapsed();
                    pm.remove_refinement(i64::from(r.halfedges[0])).unwrap();
                }
                total
            })
        });
        g.bench_function("remove_refinement_loop", |b| {
            b.iter_custom(|n| {
                let mut total = Duration::ZERO;
                for _ in 0..n {
                    let r = pm.add_refinement(he(&pm, ring(j, 0), ring(j + 1, 0))).unwrap();
                    let t = Instant::now();
                    pm.remove_refinement(i64::from(r.halfedges[0])).unwrap();
                    total += t.elapsed();
                }
                total
            })
        });
        // Add / remove a backbone: pole to pole, 2·bands faces.
        g.bench_function("add_refinement_backbone", |b| {
            b.iter_custom(|n| {
                let mut total = Duration::ZERO;
                for _ in 0..n {
                    let t = Instant::now();
                    let r = pm.add_refinement(he(&pm, ring(j, 0), ring(j, 1))).unwrap();
                    total += t.elapsed();
                    pm.remove_refinement(i64::from(r.halfedges[0])).unwrap();
                }
                total
            })
        });
        g.bench_function("remove_refinement_backbone", |b| {
            b.iter_custom(|n| {
                let mut total = Duration::ZERO;
                for _ in 0..n {
                    let r = pm.add_refinement(he(&pm, ring(j, 0), ring(j, 1))).unwrap();
                    let t = Instant::now();
                    pm.remove_refinement(i64::from(r.halfedges[0])).unwrap();
                    total += t.elapsed();
                }
                total
            })
        });
        // Add, select and remove a feature on three loop vertices.
        let run = [ring(j, 2), ring(j, 3), ring(j, 4)];
        let home = pm.position(run[1]);
        let feature_cycle = |pm: &mut PolarMesh, which: usize| {
            let t = Instant::now();
            let p = pm.add_feature(&run).unwrap();
            let d0 = t.elapsed();
            let f = pm.face_of(pm.fan(i64::from(p)).unwrap()[0]);
            let t = Instant::now();
            black_box(pm.select_feature(i64::from(f)).unwrap());
            let d1 = t.elapsed();
            let t = Instant::now();
            pm.remove_feature(i64::from(f)).unwrap();
            let d2 = t.elapsed();
            pm.set_position(run[1], home).unwrap();
            [d0, d1, d2][which]
        };
        for (which, name) in ["add_feature", "select_feature", "remove_feature"].iter().enumerate() {
            g.bench_function(*name, |b| {
                b.iter_custom(|n| (0..n).map(|_| feature_cycle(&mut pm, which)).sum::<Duration>());
            });
        }
        // Merge two features into a handle, then split it again.
        let p = pm.add_feature(&[ring(j, 10), ring(j, 11), ring(j, 12)]).unwrap();
        let q = pm.add_feature(&[ring(j + 6, 12), ring(j + 6, 11), ring(j + 6, 10)]).unwrap();
        let mut poles = [p, q];
        let merge_split = |pm: &mut PolarMesh, poles: &mut [u32; 2], which: usize| {
            let t = Instant::now();
            pm.merge_features(i64::from(poles[0]), i64::from(poles[1])).unwrap();
            let d0 = t.elapsed();
            let bridge =
                pm.mesh().outgoing(ring(j, 11)).find(|&x| !pm.is_loop(x) && pm.ends(x)[1] != ring(j - 1, 11)).unwrap();
            let r = pm.add_refinement(i64::from(bridge)).unwrap();
            let t = Instant::now();
            *poles = pm.split_feature(i64::from(r.halfedges[0])).unwrap();
            let d1 = t.elapsed();
            [d0, d1][which]
        };
        for (which, name) in ["merge_features", "split_feature"].iter().enumerate() {
            g.bench_function(*name, |b| {
                b.iter_custom(|n| (0..n).map(|_| merge_split(&mut pm, &mut poles, which)).sum::<Duration>());
            });
        }
        g.finish();
        pm.check().expect("the benchmark cycles keep the mesh polar");
    }
}

/// Backbones with a fixed affected region: on a torus whose loops run around the main circle
/// (8,000 edges: 157, 1563, 15625 of them) and whose backbones run around the tube (64 edges), a
/// new backbone splits one ring of 64 faces at every mesh size.
fn backbones_on_a_torus(c: &mut Criterion) {
    for (label, around) in [("10k", 157u32), ("100k", 1563), ("1M", 15625)] {
        let torus = Mesh::torus(2.0, 0.5, around, SEGMENTS);
        // Vertex (i, j) is i·64 + j: the edge (0, 0)–(1, 0) runs along the main circle.
        let mut pm = PolarMesh::from_mesh(torus, &[], &[[0, SEGMENTS]]).unwrap();
        let mid = (around / 2) * SEGMENTS;
        let mut g = c.benchmark_group(format!("polar/torus_{label}_faces"));
        g.sample_size(20).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));
        // Adds a backbone then removes it, timing both.
        let pair = |pm: &mut PolarMesh| {
            let t = Instant::now();
            let r = pm.add_refinement(he(pm, mid, mid + SEGMENTS)).unwrap();
            let add = t.elapsed();
            let t = Instant::now();
            pm.remove_refinement(i64::from(r.halfedges[0])).unwrap();
            [add, t.elapsed()]
        };
        for (which, name) in ["add_refinement_backbone", "remove_refinement_backbone"].iter().enumerate() {
            g.bench_function(*name, |b| b.iter_custom(|n| (0..n).map(|_| pair(&mut pm)[which]).sum::<Duration>()));
        }
        g.finish();
        pm.check().expect("the benchmark cycles keep the mesh polar");
    }
}

fn skeleton(c: &mut Criterion) {
    // 400 segments × 1000 bands: 2 + 999·400 = 399,602 vertices, 400,000 faces.
    let pm = PolarMesh::uv_sphere(1.0, 400, 1000);
    let mut g = c.benchmark_group("polar/skeleton_400k_vertices");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    g.bench_function("infer", |b| b.iter(|| black_box(pm.skeleton(None).unwrap())));
    g.bench_function("feature_ids", |b| b.iter(|| black_box(pm.feature_ids())));
    g.bench_function("check", |b| b.iter(|| black_box(pm.check()).unwrap()));
    g.finish();
}

criterion_group!(benches, operations, backbones_on_a_torus, skeleton);
criterion_main!(benches);
