//! Diagnosis at a million triangles (issue 34): `defects()` (components with genus, boundaries,
//! touching places, degenerate faces, self-intersections, handle loops), and its parts alone.
//!
//! Inputs (triangles, each quad of a torus grid split along its diagonal):
//! - `torus_1m`: one torus (major radius 2, minor 0.5), 1000 × 500 quads: 1M triangles, genus 1,
//!   nothing crossing (the BVH search finds only neighbours' boxes overlapping).
//! - `two_tori_1m`: two tori of 708 × 354 quads (1.0M triangles) overlapping side by side
//!   (centres 3 apart): two crossing curves, 2 handles.
//!
//! Complexity: components, boundaries, touching places and degenerate faces are linear; the
//! self-intersection search is a median-split BVH (O(n log n) to build, O(n log n + k) to
//! report k overlapping pairs, the exact pair tests in parallel); handle loops O(n log n + g·n)
//! for g handles.
//!
//! kernel/benches/diagnose_peers.py does the same diagnosis with trimesh and pymeshlab on the
//! same files, which this bench leaves in target/bench-data/ (written before timing), and
//! prints the times side by side with the ratios to this bench's (criterion's estimates).
//!
//! Run (release, as every bench): `cargo bench -p blocksmith-kernel --bench diagnose`.

use std::f64::consts::TAU;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use blocksmith_kernel::diagnose::{components, crossings, defects, handle_loops};
use blocksmith_kernel::io::save;
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

/// A triangulated `n × m` torus grid of radii 2 and 0.5 centred at `centre`.
fn torus(n: u32, m: u32, centre: Vec3) -> Mesh {
    let mut positions = Vec::with_capacity((n * m) as usize);
    for i in 0..n {
        let u = TAU * f64::from(i) / f64::from(n);
        for j in 0..m {
            let v = TAU * f64::from(j) / f64::from(m);
            let r = 2.0 + 0.5 * v.cos();
            positions.push(centre + Vec3::new(r * u.cos(), r * u.sin(), 0.5 * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + j % m;
    let mut indices = Vec::with_capacity((n * m * 6) as usize);
    for i in 0..n {
        for j in 0..m {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            indices.extend_from_slice(&[q[0], q[1], q[2], q[0], q[2], q[3]]);
        }
    }
    let arities = vec![3; indices.len() / 3];
    Mesh::from_indexed(positions, &indices, &arities).unwrap()
}

fn bench_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/bench-data");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn diagnose(c: &mut Criterion) {
    let one = torus(1000, 500, Vec3::ZERO);
    let (a, b) = (torus(708, 354, Vec3::ZERO), torus(708, 354, Vec3::new(3.0, 0.0, 0.0)));
    let two = Mesh::combine(&[&a, &b]).unwrap();
    for (name, mesh, handles) in [("torus_1m", &one, 1), ("two_tori_1m", &two, 2)] {
        // The answers first (each case is what it says), then the files for the peers.
        let found = defects(mesh).unwrap();
        let count = |k| found.iter().filter(|d| d.kind == k).count();
        use blocksmith_kernel::diagnose::DefectKind as K;
        assert_eq!(count(K::Handle), handles, "{name}");
        assert_eq!((count(K::Boundary), count(K::NonManifoldVertex), count(K::DegenerateFace)), (0, 0, 0));
        let crossing = count(K::SelfIntersection);
        assert_eq!(crossing == 0, name == "torus_1m", "{name}: {crossing} crossing pairs");
        let path = bench_dir().join(format!("diagnose_{name}.ply"));
        save(mesh, &path).unwrap();
        eprintln!("{name}: {} triangles, {crossing} crossing pairs; written to {}", mesh.face_count(), path.display());

        let mut g = c.benchmark_group(format!("diagnose/{name}"));
        g.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(8));
        g.throughput(Throughput::Elements(mesh.face_count() as u64));
        g.bench_function("defects", |b| b.iter(|| defects(black_box(mesh)).unwrap()));
        g.bench_function("self_intersections", |b| b.iter(|| crossings(black_box(mesh)).unwrap()));
        g.bench_function("components", |b| b.iter(|| components(black_box(mesh)).unwrap()));
        g.bench_function("handle_loops", |b| b.iter(|| handle_loops(black_box(mesh)).unwrap()));
        g.finish();
    }
}

criterion_group!(benches, diagnose);
criterion_main!(benches);
