//! Subdivision at about 100k faces: Catmull–Clark and Loop three levels deep, split into the
//! topology refinement, the position refinement and the half-edge build of the result; and the
//! limit evaluator (build, then 1M (face, u, v) samples). Also two Catmull–Clark levels of a
//! cylinder with 100,000-gon caps (`cc2_cylinder100k`), whose centres reach valence 100,000.
//!
//! Inputs: `ico6`, the icosphere with 6 subdivisions (40,962 vertices, 81,920 triangles — the mesh
//! `../shared/peers/subdiv_peers.py` times libigl, pymeshlab and Blender's OpenSubdiv on, and
//! `tests/data/subdiv/osd_bench.cpp` OpenSubdiv's own CPU refiner); `torus100k`, a 320 × 320 quad
//! torus (102,400 quads, all regular); `torus100k_semi`, the same torus with 20 loops around the
//! tube (6,400 edges) of sharpness 2.5, so every level meets semi-sharp creases and the last
//! blends the rules (the cost of semi-sharp creases is `cc3_torus100k_semi_total` over
//! `cc3_torus100k_total`); they are made by `support/subdiv_inputs.rs`, which
//! `examples/subdiv_once.rs` shares. The inputs are written as OBJ files (crease tags included) to
//! `subdiv_inputs/` in Cargo's target tmp folder, where `tests/data/subdiv/bench_vs_osd.sh`
//! runs OpenSubdiv's Far on the same meshes and prints the ratios. Limit evaluation: the 320 × 320 torus (every face one
//! bicubic patch) and one Catmull–Clark step of `Mesh::icosphere(1, 3)` (3,840 quads, every one
//! with two extraordinary corners: the adaptive path), at 1M seeded uniform (u, v) samples.
//!
//! Run: `cargo bench --workspace --bench subdiv` (or `bash tests/data/subdiv/bench_vs_osd.sh`).

use std::hint::black_box;
use std::time::Duration;

use blocksmith_kernel::subdiv::{LimitEvaluator, Refiner, Scheme};
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};

#[path = "support/subdiv_inputs.rs"]
mod subdiv_inputs;

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
    let inputs = subdiv_inputs::inputs();
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("subdiv_inputs");
    subdiv_inputs::write_inputs(&dir, &inputs).unwrap();
    let [(_, ico6), (_, torus), (_, semi)] = &inputs[..] else { unreachable!("three inputs") };
    let mut g = c.benchmark_group("subdiv");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for (name, mesh, scheme) in [
        ("cc3_ico6", ico6, Scheme::CatmullClark),
        ("loop3_ico6", ico6, Scheme::Loop),
        ("cc3_torus100k", torus, Scheme::CatmullClark),
        ("cc3_torus100k_semi", semi, Scheme::CatmullClark),
    ] {
        g.throughput(Throughput::Elements(mesh.face_count() as u64));
        // The whole operation, as Mesh::catmull_clark / loop_subdivide do it. Freeing the
        // refiner and the mesh is left out of the time, as osd_bench.cpp leaves out deleting
        // Far's refiner and its position buffers.
        g.bench_function(format!("{name}_total"), |b| {
            b.iter_with_large_drop(|| {
                let r = Refiner::new(mesh, scheme, 3).unwrap();
                let p = r.refine_positions(mesh.positions());
                let m = r.to_mesh(p).unwrap();
                (r, m)
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
    // Two levels of a cylinder whose caps are 100,000-gons: each cap's face point has valence
    // 100,000 after the first step (the half-edge build was quadratic in valence).
    let cylinder = Mesh::cylinder(1.0, 1.0, 100_000);
    g.throughput(Throughput::Elements(cylinder.face_count() as u64));
    g.bench_function("cc2_cylinder100k_total", |b| b.iter(|| black_box(cylinder.catmull_clark(2).unwrap())));
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
