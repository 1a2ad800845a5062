//! Mesh core at a million faces: building from indexed polygons, every measure, and writing and
//! reading `.glb` and `.obj` files.
//!
//! Inputs: a torus grid (major radius 2, minor 0.5) of 1000 × 1000 quads (1M quads, 1M
//! vertices), and one of 1000 × 500 quads each split in two (1M triangles, 500k vertices).
//! tests/data/bench_trimesh.py does the same work in trimesh on the same files, which this bench
//! leaves in target/bench-data/ (written before timing, so trimesh reads exactly these).
//!
//! Run: `cargo bench -p blocksmith-kernel --bench mesh_core`.

use std::f64::consts::TAU;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use blocksmith_kernel::io::{load, save};
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};

/// Positions, flat indices and arities of an `n × m` torus grid: quads, or each quad split
/// into two triangles along its diagonal.
fn torus_grid(n: u32, m: u32, triangles: bool) -> (Vec<Vec3>, Vec<u32>, Vec<u32>) {
    let mut positions = Vec::with_capacity((n * m) as usize);
    for i in 0..n {
        let u = TAU * f64::from(i) / f64::from(n);
        for j in 0..m {
            let v = TAU * f64::from(j) / f64::from(m);
            let r = 2.0 + 0.5 * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), 0.5 * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + j % m;
    let mut indices = Vec::with_capacity((n * m * if triangles { 6 } else { 4 }) as usize);
    let mut arities = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if triangles {
                indices.extend_from_slice(&[q[0], q[1], q[2], q[0], q[2], q[3]]);
                arities.extend_from_slice(&[3, 3]);
            } else {
                indices.extend_from_slice(&q);
                arities.push(4);
            }
        }
    }
    (positions, indices, arities)
}

fn bench_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/bench-data");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn mesh_core(c: &mut Criterion) {
    let inputs = [("quads_1m", torus_grid(1000, 1000, false)), ("tris_1m", torus_grid(1000, 500, true))];
    for (name, (positions, indices, arities)) in &inputs {
        let faces = arities.len() as u64;
        let mut g = c.benchmark_group(format!("mesh_core/{name}"));
        g.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
        g.throughput(Throughput::Elements(faces));

        g.bench_function("from_indexed", |b| {
            b.iter_batched(
                || positions.clone(),
                |p| Mesh::from_indexed(p, black_box(indices), black_box(arities)).unwrap(),
                BatchSize::LargeInput,
            );
        });
        let mesh = Mesh::from_indexed(positions.clone(), indices, arities).unwrap();
        g.bench_function("measures_all", |b| b.iter(|| black_box(&mesh).measures()));
        g.bench_function("volume_area_closed_euler", |b| {
            b.iter(|| {
                let m = black_box(&mesh);
                (m.volume(), m.area(), m.is_closed(), m.euler())
            });
        });

        let dir = bench_dir();
        for ext in ["glb", "obj"] {
            let path = dir.join(format!("{name}.{ext}"));
            save(&mesh, &path).unwrap();
            g.bench_function(format!("write_{ext}"), |b| b.iter(|| save(black_box(&mesh), &path).unwrap()));
            g.bench_function(format!("read_{ext}"), |b| b.iter(|| load(black_box(&path)).unwrap()));
            let back = load(&path).unwrap();
            assert_eq!(back.face_count(), mesh.face_count(), "{name}.{ext} reads back with its faces");
        }
        g.finish();
    }
}

criterion_group!(benches, mesh_core);
criterion_main!(benches);
