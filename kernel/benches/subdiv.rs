//! Subdivision at about 100k faces: Catmull–Clark and Loop three levels deep, split into the
//! topology refinement, the position refinement and the half-edge build of the result; and the
//! limit evaluator (build, then 1M (face, u, v) samples).
//!
//! Inputs: `ico6`, the icosphere with 6 subdivisions (40,962 vertices, 81,920 triangles — the mesh
//! `../shared/peers/subdiv_peers.py` times libigl, pymeshlab and Blender's OpenSubdiv on, and
//! `tests/data/subdiv/osd_bench.cpp` OpenSubdiv's own CPU refiner); `torus100k`, a 320 × 320 quad
//! torus (102,400 quads, all regular). Limit evaluation: the 320 × 320 torus (every face one
//! bicubic patch) and one Catmull–Clark step of `Mesh::icosphere(1, 3)` (3,840 quads, every one
//! with two extraordinary corners: the adaptive path), at 1M seeded uniform (u, v) samples.
//!
//! Run: `cargo bench -p blocksmith-kernel --bench subdiv`.

use std::hint::black_box;
use std::time::Duration;

use blocksmith_kernel::subdiv::{LimitEvaluator, Refiner, Scheme};
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};

/// 1M (face, u, v) samples from a fixed-seed xorshift generator.
fn samples(faces: u32, count: usize) -> Vec<(u32, f64, f64)> {
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    (0..count)
        .map(|_| {
            let f = (next() % u64::from(faces)) as u32;
            let u = (next() >> 11) as f64 / (1u64 << 53) as f64;
            let v = (next() >> 11) as f64 / (1u64 << 53) as f64;
            (f, u, v)
        })
        .collect()
}

fn refinement(c: &mut Criterion) {
    let ico6 = Mesh::icosphere(1.0, 6);
    let torus = Mesh::torus(2.0, 0.5, 320, 320);
    let mut g = c.benchmark_group("subdiv");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for (name, mesh, scheme) in [
        ("cc3_ico6", &ico6, Scheme::CatmullClark),
        ("loop3_ico6", &ico6, Scheme::Loop),
        ("cc3_torus100k", &torus, Scheme::CatmullClark),
    ] {
        g.throughput(Throughput::Elements(mesh.face_count() as u64));
        // The whole operation, as Mesh::catmull_clark / loop_subdivide do it.
        g.bench_function(format!("{name}_total"), |b| {
            b.iter(|| {
                let r = Refiner::new(mesh, scheme, 3).unwrap();
                let p = r.refine_positions(mesh.positions());
                black_box(r.to_mesh(p).unwrap())
            })
        });
        // Its three phases.
        g.bench_function(format!("{name}_topology"), |b| b.iter(|| black_box(Refiner::new(mesh, scheme, 3).unwrap())));
        let r = Refiner::new(mesh, scheme, 3).unwrap();
        g.bench_function(format!("{name}_positions"), |b| b.iter(|| black_box(r.refine_positions(mesh.positions()))));
        let p = r.refine_positions(mesh.positions());
        g.bench_function(format!("{name}_halfedge_build"), |b| {
            b.iter_batched(|| p.clone(), |p| black_box(r.to_mesh(p).unwrap()), BatchSize::LargeInput)
        });
    }
    g.finish();
}

fn limit_evaluation(c: &mut Criterion) {
    let torus = Mesh::torus(2.0, 0.5, 320, 320);
    let ico = Mesh::icosphere(1.0, 3).catmull_clark(1).unwrap();
    let mut g = c.benchmark_group("subdiv_limit");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.throughput(Throughput::Elements(torus.face_count() as u64));
    g.bench_function("evaluator_build_torus100k", |b| b.iter(|| black_box(LimitEvaluator::new(&torus).unwrap())));
    for (name, mesh) in [("torus100k_regular", &torus), ("ico3_cc1_irregular", &ico)] {
        let ev = LimitEvaluator::new(mesh).unwrap();
        let s = samples(mesh.face_count() as u32, 1_000_000);
        g.throughput(Throughput::Elements(s.len() as u64));
        g.bench_function(format!("eval_1m_{name}"), |b| {
            b.iter(|| {
                let mut acc = Vec3::ZERO;
                for &(f, u, v) in &s {
                    acc += ev.eval(f, u, v).unwrap().position;
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, refinement, limit_evaluation);
criterion_main!(benches);
