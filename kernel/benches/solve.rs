//! Shape-Up as ARAP, side by side with libigl's `arap_precomputation` / `arap_solve`
//! (`../shared/peers/arap_peer.py`, the same problem): an icosphere (subdivisions 5: 10,242
//! vertices; 7: 163,842) scaled to a (0.5, 0.5, 2) bar, the vertices below z = −1.85 fixed,
//! those above 1.85 turned 45° about y around (0, 0, 1.85) and moved by (0.6, 0, −0.4). Each
//! vertex's one-ring (the vertex and its neighbours) is a rigid constraint (weight 1), the
//! handles anchors (weight 1000).
//! - `factor`: building and factoring the normal matrix (libigl: precomputation);
//! - `iterations_10`: ten local/global iterations (libigl: `arap_solve` with max_iter 10).
//!
//! - `shape_up_circles_*`: the circle constraint with its size (issue 35, `CircleSize::KeepSize`,
//!   the least-squares circle fitted in every local step) on every latitude ring of a uv sphere
//!   squashed to (1, 0.6, 1) (64 × 32: 1,986 vertices in 31 rings; 256 × 128: 32,514 in 127),
//!   closeness 1: `factor` and `iterations_10`.
//!
//! Run (release, as criterion builds it): `cargo bench -p blocksmith-kernel --bench solve`.

use std::hint::black_box;

use blocksmith_kernel::math::Quat;
use blocksmith_kernel::solve::{CircleSize, ShapeUp};
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, criterion_main, Criterion};

fn problem(sub: u32) -> (Mesh, ShapeUp, Vec<Vec3>) {
    let m = Mesh::icosphere(1.0, sub).scale(Vec3::new(0.5, 0.5, 2.0));
    let mut up = ShapeUp::new(&m).unwrap();
    for v in 0..m.vertex_count() as u32 {
        let mut ring: Vec<u32> = m.vertex_neighbors(v).collect();
        ring.push(v);
        up.rigid(&ring, None, 1.0).unwrap();
    }
    let q = Quat::from_axis_angle(Vec3::Y, 45f64.to_radians());
    let pivot = Vec3::new(0.0, 0.0, 1.85);
    let mut start = m.positions().to_vec();
    let (mut verts, mut targets) = (Vec::new(), Vec::new());
    for (v, p) in m.positions().iter().enumerate() {
        let target = if p.z < -1.85 {
            *p
        } else if p.z > 1.85 {
            q * (*p - pivot) + pivot + Vec3::new(0.6, 0.0, -0.4)
        } else {
            continue;
        };
        verts.push(v as u32);
        targets.push(target);
        start[v] = target;
    }
    up.anchor(&verts, &targets, 1000.0).unwrap();
    (m, up, start)
}

fn arap(c: &mut Criterion) {
    for sub in [5, 7] {
        let (m, up, start) = problem(sub);
        let mut g = c.benchmark_group(format!("shape_up_arap_{}v", m.vertex_count()));
        g.sample_size(10);
        g.bench_function("factor", |b| b.iter(|| black_box(up.factor().unwrap())));
        let f = up.factor().unwrap();
        g.bench_function("iterations_10", |b| b.iter(|| black_box(f.solve(black_box(&start), 10).unwrap())));
        g.finish();
    }
}

fn circles(c: &mut Criterion) {
    for (segments, rings) in [(64u32, 32u32), (256, 128)] {
        let m = Mesh::uv_sphere(1.0, segments, rings).scale(Vec3::new(1.0, 0.6, 1.0));
        let mut up = ShapeUp::new(&m).unwrap();
        // Vertex 0 is a pole, then the latitude rings of `segments` vertices each.
        for k in 0..rings - 1 {
            let ring: Vec<u32> = (1 + segments * k..1 + segments * (k + 1)).collect();
            up.circle_sized(&ring, 10.0, CircleSize::KeepSize).unwrap();
        }
        up.closeness(1.0).unwrap();
        let mut g = c.benchmark_group(format!("shape_up_circles_{}v_{}rings", m.vertex_count(), rings - 1));
        g.sample_size(10);
        g.bench_function("factor", |b| b.iter(|| black_box(up.factor().unwrap())));
        let f = up.factor().unwrap();
        g.bench_function("iterations_10", |b| b.iter(|| black_box(f.solve(black_box(m.positions()), 10).unwrap())));
        g.finish();
    }
}

criterion_group!(benches, arap, circles);
criterion_main!(benches);
