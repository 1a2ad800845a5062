//! Voxel sculpting against Heurtebise & Thon's Tables 1–2 and the peers (PyWavelets,
//! scikit-image, PyMCubes).
//!
//! - `voxel/haar_128`: build a 5-level hierarchy of a 128³ sphere and extract levels 0–3
//!   (Table 1); build 3 levels and reconstruct (PyWavelets `wavedecn`/`waverecn`, 3 levels, in
//!   /work/shared/peers/haar3d_peer.py). Serial and parallel builds.
//! - `voxel/rotate_{8,16,32,64}`: rotate a t³ tool (a sphere of radius 0.45 t) over its whole reach,
//!   brute force vs the stepping of Algorithm 1, without and with trilinear antialiasing
//!   (Table 2), one of 8 (axis, angle) pairs per iteration, so times average over angles. Serial
//!   like the paper; the 64³ stepping also in parallel.
//! - `voxel/marching_cubes_{128,256}`: the peer's sphere (radius 0.8 of the half-side) as
//!   densities, meshed from scratch (scikit-image and PyMCubes in marching_cubes_peer.py), raw
//!   and smoothed (`Surface::Smooth`, the default of `to_mesh`, which the serial fresh mesh uses).
//! - `voxel/sculpt_256`: strokes of a 32³ ball tool turned 30° on a 256³ ball whose hierarchy and
//!   level-0 surface cache exist: a stroke dragged by one voxel (cached rotation) vs one at a new
//!   sub-voxel offset (all rotated again), and the re-mesh after a stroke vs a full mesh.
//! - `voxel/voxelize_128`: a 96 × 48-quad torus into 128³.
//!
//! Before timing it prints the memory of a 256³ grid with its hierarchy and level-0 surface cache.
//!
//! Run: `cargo bench -p blocksmith-kernel --bench voxel`.

use std::hint::black_box;
use std::time::Duration;

use blocksmith_kernel::math::{Mat3, Quat};
use blocksmith_kernel::voxel::{
    marching_cubes, rotate_tool, HaarHierarchy, Placement, RotationMethod, SculptMode, SculptOptions, Surface, Voxels,
    DEFAULT_ISO,
};
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, criterion_main, Criterion};

fn sphere(n: usize, radius: f64, parallel: bool) -> Voxels {
    let mut v = Voxels::new(n).unwrap();
    v.set_parallel(parallel);
    v.fill_sphere(Vec3::splat(n as f64 / 2.0), radius).unwrap();
    v
}

/// 8 (axis, angle) pairs spread over the sphere of axes and over angles.
fn rotations() -> Vec<Mat3> {
    let pairs = [
        (Vec3::new(1.0, 0.0, 0.0), 15.0),
        (Vec3::new(0.0, 1.0, 0.0), 30.0),
        (Vec3::new(0.0, 0.0, 1.0), 45.0),
        (Vec3::new(1.0, 1.0, 0.0), 60.0),
        (Vec3::new(1.0, 1.0, 1.0), 75.0),
        (Vec3::new(-1.0, 2.0, 0.5), 33.0),
        (Vec3::new(0.3, -0.2, 1.0), 120.0),
        (Vec3::new(2.0, 0.1, -1.0), 170.0),
    ];
    pairs.iter().map(|&(a, d)| Mat3::from_quat(Quat::from_axis_angle(a.normalize(), f64::to_radians(d)))).collect()
}

fn memory_report() {
    let mut v = sphere(256, 100.0, true);
    let _ = v.hierarchy();
    let mesh = v.to_mesh(0, DEFAULT_ISO).unwrap();
    let mib = v.memory_bytes() as f64 / (1024.0 * 1024.0);
    eprintln!(
        "VOXEL_MEMORY n=256 grid+hierarchy+surface_cache={mib:.1} MiB (target < 64) level0_triangles={}",
        mesh.face_count()
    );
}

fn haar(c: &mut Criterion) {
    let mut g = c.benchmark_group("voxel/haar_128");
    g.sample_size(20).measurement_time(Duration::from_secs(4));
    let v = sphere(128, 45.0, true);
    let mut serial = v.clone();
    serial.set_parallel(false);
    g.bench_function("build_5_levels", |b| b.iter(|| black_box(HaarHierarchy::build(&v, 5).unwrap())));
    g.bench_function("build_5_levels_serial", |b| b.iter(|| black_box(HaarHierarchy::build(&serial, 5).unwrap())));
    let h = HaarHierarchy::build(&v, 5).unwrap();
    for level in 0..=3 {
        g.bench_function(format!("extract_level_{level}"), |b| b.iter(|| black_box(h.extract(level, true).unwrap())));
    }
    g.bench_function("build_3_levels", |b| b.iter(|| black_box(HaarHierarchy::build(&v, 3).unwrap())));
    let h3 = HaarHierarchy::build(&v, 3).unwrap();
    g.bench_function("reconstruct_from_3_levels", |b| b.iter(|| black_box(h3.extract(0, true).unwrap())));
    g.finish();
}

fn rotate(c: &mut Criterion) {
    let rots = rotations();
    for t in [8usize, 16, 32, 64] {
        let tool = sphere(t, 0.45 * t as f64, false);
        let mut g = c.benchmark_group(format!("voxel/rotate_{t}"));
        g.sample_size(20).measurement_time(Duration::from_secs(3));
        let cases = [
            ("brute_force", RotationMethod::BruteForce, false, false),
            ("optimised", RotationMethod::Incremental, false, false),
            ("brute_force_aa", RotationMethod::BruteForce, true, false),
            ("optimised_aa", RotationMethod::Incremental, true, false),
        ];
        for (name, method, aa, parallel) in cases {
            let mut k = 0;
            g.bench_function(name, |b| {
                b.iter(|| {
                    k = (k + 1) % rots.len();
                    let p = Placement::from_parts(rots[k], 1.0, Vec3::splat(100.25));
                    black_box(rotate_tool(&tool, &p, method, aa, parallel).unwrap())
                })
            });
        }
        if t == 64 {
            for (name, aa) in [("optimised_parallel", false), ("optimised_aa_parallel", true)] {
                let mut k = 0;
                g.bench_function(name, |b| {
                    b.iter(|| {
                        k = (k + 1) % rots.len();
                        let p = Placement::from_parts(rots[k], 1.0, Vec3::splat(100.25));
                        black_box(rotate_tool(&tool, &p, RotationMethod::Incremental, aa, true).unwrap())
                    })
                });
            }
        }
        g.finish();
    }
}

fn mc(c: &mut Criterion) {
    for n in [128usize, 256] {
        // The peer samples 0.8 − |x| at x = −1 + 2i/(n − 1): a sphere of radius 0.4 (n − 1) samples.
        let v = sphere(n, 0.4 * (n - 1) as f64, true);
        let mut g = c.benchmark_group(format!("voxel/marching_cubes_{n}"));
        g.sample_size(10).measurement_time(Duration::from_secs(5));
        for (name, surface) in [("marching_cubes", Surface::Raw), ("marching_cubes_smooth", Surface::Smooth)] {
            g.bench_function(name, |b| {
                b.iter(|| black_box(marching_cubes(v.data(), n, DEFAULT_ISO, surface).unwrap()))
            });
        }
        let mut serial = v.clone();
        serial.set_parallel(false);
        g.bench_function("to_mesh_fresh_serial", |b| {
            b.iter(|| {
                serial.clear_caches();
                black_box(serial.to_mesh(0, DEFAULT_ISO).unwrap())
            })
        });
        g.finish();
    }
}

fn sculpt(c: &mut Criterion) {
    let mut g = c.benchmark_group("voxel/sculpt_256");
    g.sample_size(20).measurement_time(Duration::from_secs(5));
    let mut tool = Voxels::new(32).unwrap();
    tool.fill_sphere(Vec3::splat(16.0), 14.0).unwrap();
    let mut obj = sphere(256, 100.0, true);
    let _ = obj.hierarchy();
    obj.to_mesh(0, DEFAULT_ISO).unwrap();
    let stroke = |i: u64, offset: f64| {
        let x = 28.0 + (i % 40) as f64 + offset;
        SculptOptions::at(Vec3::new(x, 128.0, 128.0))
            .with_rotation(Vec3::new(1.0, 1.0, 0.0), 30.0)
            .with_mode(SculptMode::Subtract)
    };
    let mut i = 0u64;
    g.bench_function("stroke_drag_cached", |b| {
        b.iter(|| {
            i += 1;
            black_box(obj.sculpt(&tool, &stroke(i, 0.25)).unwrap())
        })
    });
    let mut i = 0u64;
    g.bench_function("stroke_new_offset", |b| {
        b.iter(|| {
            i += 1;
            black_box(obj.sculpt(&tool, &stroke(i, if i.is_multiple_of(2) { 0.25 } else { 0.75 })).unwrap())
        })
    });
    let mut i = 0u64;
    g.bench_function("stroke_then_remesh_level0", |b| {
        b.iter(|| {
            i += 1;
            obj.sculpt(&tool, &stroke(i, 0.25)).unwrap();
            black_box(obj.to_mesh(0, DEFAULT_ISO).unwrap())
        })
    });
    g.bench_function("full_mesh_level0", |b| {
        b.iter(|| {
            let mut fresh = obj.clone();
            fresh.clear_caches();
            black_box(fresh.to_mesh(0, DEFAULT_ISO).unwrap())
        })
    });
    g.finish();
}

fn voxelize(c: &mut Criterion) {
    let mut g = c.benchmark_group("voxel/voxelize_128");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    let torus = Mesh::torus(2.0, 0.7, 96, 48);
    g.bench_function("torus", |b| b.iter(|| black_box(Voxels::from_mesh(&torus, 128).unwrap())));
    g.finish();
}

fn all(c: &mut Criterion) {
    memory_report();
    haar(c);
    rotate(c);
    mc(c);
    sculpt(c);
    voxelize(c);
}

criterion_group!(benches, all);
criterion_main!(benches);
