//! 2D profiles and the solids made from them, on the inputs `profile_peer.py` (below) gives
//! manifold3d: a 64-gon of radius 1 extruded 2 with a 90° twist over 32 layers; a 64-gon of
//! radius 0.5 at x = 2 revolved in 128 steps; the hulls of 100,000 and 1,000,000 points on a
//! sphere of radius 1 (a fixed pseudo-random sequence); the Minkowski sum of an L prism and Manifold's 32-segment
//! sphere of radius 0.2 (non-convex ⊕ convex); a 10×10 square offset by 1 with 32-segment round
//! joins. Without a peer here: 10,000 characters of text (100 lines) in the bundled font.
//!
//! Ours includes building the result's half-edge `Mesh`; manifold3d's stops at its lazy result's
//! `num_tri()`. Run: `cargo bench -p blocksmith-kernel --bench profile`; the peer:
//! `~/.cache/blocksmith-peers/venv/bin/python kernel/benches/profile_peer.py bench`.
//!
//! Measured (release, this 2-core machine, 2026-12-06, `--quick` interleaved with the peer in
//! one sitting: ours criterion's middle estimate, manifold3d's median of 10–300; the machine's
//! speed drifts by up to 1.8× over minutes, so only ratios of neighbouring runs are quoted):
//! | case | ours / manifold3d median |
//! |---|---|
//! | extrude, 64-gon, 90° twist, 32 layers (0.21 ms) | 0.13–0.14× |
//! | revolve, 64-gon in 128 steps (1.0 ms) | 0.18–0.19× |
//! | hull of 100,000 sphere points (342–369 ms) | 0.88–0.99× |
//! | Minkowski, L prism ⊕ sphere (116–135 ms) | 0.95–1.0× |
//! | offset, round joins (4.3–4.6 µs; the peer's timer shows 4 µs) | about 1.1× |
//! | hull of 1,000,000 sphere points (5.4–6.0 s; every point is on the hull: 2M triangles) | 0.92–1.01× |
//!
//! The hulls were 0.92× and 1.3× on 2026-12-04; engine patches 11 and 12
//! (`vendor/manifold-rust/PATCHES.md`) took the quickhull's cache misses and its exact
//! orientation tests of faces clearly decided by their float planes off (1M: 7.4–7.8 s before
//! them, in the same sitting). Extrude and revolve were 1.2–1.4× the peer (1.8–2.0 ms and
//! 7.2–8.2 ms) while they made the engine's solid and exported its triangles: 85 % of that time
//! was the solid's sort, normals, coplanar groups and collider, which nothing reads before a
//! boolean (and a boolean imports the mesh again). Engine patch 13 hands out the constructors'
//! triangles, and the mesh is built from them directly; manifold3d's figure still includes
//! building its manifold.
//! Text has no peer here: 10,000 characters take about 7 ms (each glyph cleaned once, only
//! glyphs whose ink meets unioned; a union of the whole text took 3.7 s).

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::hint::black_box;

use blocksmith_kernel::csg::engine::{Solid, Stop};
use blocksmith_kernel::profile::{
    extrude, hull_points, minkowski, revolve, text, ExtrudeOptions, Font, OffsetOptions, Profile, RevolveOptions,
    TextOptions, Vec2,
};
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, criterion_main, Criterion};

/// `n` points on the unit sphere from a fixed linear congruential sequence.
fn sphere_points(n: usize) -> Vec<Vec3> {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let z = 2.0 * next() - 1.0;
            let a = 2.0 * std::f64::consts::PI * next();
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let circle = Profile::circle(1.0, 64).unwrap();
    let twist = ExtrudeOptions::DEFAULT.with_twist(90.0).with_slices(32);
    c.bench_function("profile/extrude_twist_64gon", |b| b.iter(|| black_box(extrude(&circle, 2.0, &twist).unwrap())));
    let disc = Profile::circle(0.5, 64).unwrap().translate(Vec2::new(2.0, 0.0)).unwrap();
    let around = RevolveOptions::DEFAULT.with_segments(128);
    c.bench_function("profile/revolve_torus_64x128", |b| b.iter(|| black_box(revolve(&disc, &around).unwrap())));
    let points = sphere_points(100_000);
    c.bench_function("profile/hull_100k_sphere_points", |b| b.iter(|| black_box(hull_points(&points).unwrap())));
    let million = sphere_points(1_000_000);
    let mut slow = c.benchmark_group("profile_slow");
    slow.sample_size(10);
    slow.bench_function("hull_1m_sphere_points", |b| b.iter(|| black_box(hull_points(&million).unwrap())));
    slow.finish();
    let ell = Profile::rect(Vec2::ZERO, Vec2::new(2.0, 1.0))
        .unwrap()
        .union(&Profile::rect(Vec2::ZERO, Vec2::new(1.0, 2.0)).unwrap());
    let prism = extrude(&ell, 1.0, &ExtrudeOptions::DEFAULT).unwrap();
    // Manifold's own sphere (32 segments), the very mesh manifold3d sums with.
    let t = Solid::manifold_sphere(0.2, 32).triangles();
    let ball = Mesh::from_indexed(t.positions, t.triangles.as_flattened(), &vec![3; t.triangles.len()]).unwrap();
    c.bench_function("profile/minkowski_l_prism_sphere", |b| b.iter(|| black_box(minkowski(&prism, &ball).unwrap())));
    // The engine alone on the same operands, already imported (what manifold3d's figure times).
    let import = |m: &Mesh| {
        let tris: Vec<[u32; 3]> = m.to_polygons().iter().map(|f| [f[0], f[1], f[2]]).collect();
        let tags: Vec<u32> = (0..tris.len() as u32).collect();
        Solid::new(m.positions(), &tris, &tags).unwrap()
    };
    let (sa, sb) = (import(&prism), import(&ball));
    c.bench_function("profile/minkowski_engine_only", |b| {
        b.iter(|| black_box(sa.minkowski_until(&sb, &Stop::new()).unwrap().triangle_count()))
    });
    // 10,000 characters of running text in 100 lines, in the bundled font.
    let words = "The quick brown fox jumps over the lazy dog; 0123456789 ";
    let long: String = (0..100).map(|_| words.repeat(2)[..99].to_string() + "\n").collect();
    let font = Font::bundled();
    c.bench_function("profile/text_10k_chars", |b| {
        b.iter(|| black_box(text(&long, &font, &TextOptions::DEFAULT).unwrap().point_count()))
    });
    let square = Profile::rect(Vec2::ZERO, Vec2::new(10.0, 10.0)).unwrap();
    let round = OffsetOptions::DEFAULT.with_segments(32);
    c.bench_function("profile/offset_round_square", |b| b.iter(|| black_box(square.offset(1.0, &round).unwrap())));
}

criterion_group!(benches, bench);
criterion_main!(benches);
