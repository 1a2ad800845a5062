//! Surface finishing at about 100k and 1.3M triangles: isotropic remeshing (Botsch–Kobbelt,
//! O(n) per iteration), quadric decimation (Garland–Heckbert, O(n log n)), smooth refinement
//! (Manifold's Refine, O(n·k²) for k pieces an edge) and Taubin relaxation (O(n) per round).
//!
//! Inputs: `scan100k`, the icosphere of radius 10 with 6 subdivisions (81,920 triangles) with
//! every vertex moved along its radius by 5 % of three octaves of seeded Perlin noise (the
//! "scan-like" surface of the issue note's pymeshlab table, written by the recipe there);
//! `scan1m`, the same at 8 subdivisions (1,310,720 triangles).
//!
//! The peer side (pymeshlab's `meshing_isotropic_explicit_remeshing` and
//! `meshing_decimation_quadric_edge_collapse` on the same surface) is in the issue 31 note
//! (/tmp/notes/31-finish.md): its script writes the input with `blocksmith run` and times both.
//!
//! Run: `cargo bench -p blocksmith-kernel --bench finish` (release; a few minutes).

use std::hint::black_box;
use std::time::Duration;

use blocksmith_kernel::finish::{self, DecimateOptions, DecimateTarget, RelaxOptions, RemeshOptions};
use blocksmith_kernel::math::{Noise, NoiseOptions};
use blocksmith_kernel::Mesh;
use criterion::{criterion_group, criterion_main, Criterion};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn scan(subdivisions: u32) -> Mesh {
    let noise = Noise::new(NoiseOptions { seed: 3, octaves: 3, ..NoiseOptions::default() }).unwrap();
    let ball = Mesh::icosphere(10.0, subdivisions);
    let moved = ball.positions().iter().map(|&p| p * (1.0 + 0.05 * noise.sample(p * 0.3).unwrap())).collect();
    let mut m = ball.clone();
    m.set_positions(moved).unwrap();
    m
}

fn finishing(c: &mut Criterion) {
    let mut g = c.benchmark_group("finish");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    let s100k = scan(6);
    g.bench_function("remesh_scan100k_L0.5_5it", |b| {
        b.iter(|| {
            finish::remesh(black_box(&s100k), RemeshOptions { edge_length: 0.5, iterations: 5, sharp_angle: 60.0 })
                .unwrap()
        })
    });
    g.bench_function("decimate_scan100k_to10k", |b| {
        b.iter(|| {
            finish::decimate(black_box(&s100k), DecimateOptions { target: DecimateTarget::Triangles(10_000) }).unwrap()
        })
    });
    g.bench_function("refine2_scan100k", |b| b.iter(|| finish::refine(black_box(&s100k), 2).unwrap()));
    let s1m = scan(8);
    g.bench_function("remesh_scan1m_L0.15_3it", |b| {
        b.iter(|| {
            finish::remesh(black_box(&s1m), RemeshOptions { edge_length: 0.15, iterations: 3, sharp_angle: 60.0 })
                .unwrap()
        })
    });
    g.bench_function("decimate_scan1m_to100k", |b| {
        b.iter(|| {
            finish::decimate(black_box(&s1m), DecimateOptions { target: DecimateTarget::Triangles(100_000) }).unwrap()
        })
    });
    g.bench_function("relax_taubin_scan1m_10", |b| {
        b.iter(|| finish::relax(black_box(&s1m), RelaxOptions::default()).unwrap())
    });
    g.finish();
}

criterion_group!(benches, finishing);
criterion_main!(benches);
