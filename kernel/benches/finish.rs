//! Surface finishing at about 100k and 1.3M triangles, and on a CSG part: isotropic remeshing (Botsch–Kobbelt,
//! O(n) per iteration), quadric decimation (Garland–Heckbert, O(n log n)), smooth refinement
//! (Manifold's Refine, O(n·k²) for k pieces an edge) and Taubin relaxation (O(n) per round).
//!
//! Inputs: `scan100k`, the icosphere of radius 10 with 6 subdivisions (81,920 triangles) with
//! every vertex moved along its radius by 5 % of three octaves of seeded Perlin noise (the
//! "scan-like" surface of the issue note's pymeshlab table, written by the recipe there);
//! `scan1m`, the same at 8 subdivisions (1,310,720 triangles); the plate of
//! `examples/shapeup_bent_plate.rhai` (a box minus two cylinders, as the engine's boolean leaves it).
//!
//! The peer side is `finish_peer.py` beside this file: pymeshlab's
//! `meshing_isotropic_explicit_remeshing` and `meshing_decimation_quadric_edge_collapse` on the
//! same surfaces, which this bench leaves in target/bench-data/ (`finish_scan100k.ply`,
//! `finish_scan1m.ply` and `finish_plate.ply`, written before timing, with our results at the
//! benched settings: `finish_ours_decimate10k.ply`, `finish_ours_remesh.ply`,
//! `finish_ours_plate_remesh.ply`), and the quality of both sides (Hausdorff distance to the
//! input, triangle angles, edge lengths) with the time ratios from criterion's estimates; and
//! pymeshlab's times on the 1.3M surface.
//!
//! Run: `cargo bench -p blocksmith-kernel --bench finish` (release; a few minutes), then
//! `python kernel/benches/finish_peer.py`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use blocksmith_kernel::csg::Csg;
use blocksmith_kernel::finish::{self, DecimateOptions, DecimateTarget, RelaxOptions, RemeshOptions};
use blocksmith_kernel::io::save;
use blocksmith_kernel::math::{Noise, NoiseOptions, Vec3};
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

/// The plate of `examples/shapeup_bent_plate.rhai` as CSG makes it: a 6 × 2 × 0.3 box minus
/// two cylinders of 48 segments (radii 0.45 and 0.3), with the long slivers a boolean leaves.
fn plate() -> Mesh {
    let slab = Mesh::cuboid(Vec3::new(-3.0, -1.0, -0.15), Vec3::new(3.0, 1.0, 0.15));
    let hole = |x: f64, r: f64| Csg::mesh(Mesh::cylinder(r, 1.0, 48).translate(Vec3::new(x, 0.0, 0.0)));
    Csg::mesh(slab).difference(hole(-1.5, 0.45)).difference(hole(1.5, 0.3)).evaluate().unwrap()
}

/// The plate's remesh: edges of 0.1, 6 iterations (the recipe's), edges sharper than 60° kept.
const PLATE_REMESH: RemeshOptions = RemeshOptions { edge_length: 0.1, iterations: 6, sharp_angle: 60.0 };

/// The inputs and our results at the benched settings, for `finish_peer.py`.
fn write_for_peer(s100k: &Mesh, s1m: &Mesh, decimate_to: usize, remesh: RemeshOptions) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/bench-data");
    std::fs::create_dir_all(&dir).unwrap();
    let (decimated, _) =
        finish::decimate(s100k, DecimateOptions { target: DecimateTarget::Triangles(decimate_to) }).unwrap();
    let (remeshed, _) = finish::remesh(s100k, remesh).unwrap();
    let plate = plate();
    let (plate_remeshed, _) = finish::remesh(&plate, PLATE_REMESH).unwrap();
    for (name, mesh) in [
        ("finish_scan100k", s100k),
        ("finish_ours_decimate10k", &decimated),
        ("finish_ours_remesh", &remeshed),
        ("finish_plate", &plate),
        ("finish_ours_plate_remesh", &plate_remeshed),
        ("finish_scan1m", s1m),
    ] {
        save(mesh, dir.join(format!("{name}.ply"))).unwrap();
    }
}

fn finishing(c: &mut Criterion) {
    let mut g = c.benchmark_group("finish");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    let s100k = scan(6);
    let s1m = scan(8);
    write_for_peer(&s100k, &s1m, 10_000, RemeshOptions { edge_length: 0.5, iterations: 5, sharp_angle: 60.0 });
    let plate = plate();
    g.bench_function("remesh_plate_L0.1_6it", |b| b.iter(|| finish::remesh(black_box(&plate), PLATE_REMESH).unwrap()));
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
