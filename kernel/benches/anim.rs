//! Posing a 400k-vertex plant per frame (seed 004 part II): the modifier stack over the skeleton
//! and the skinning of every vertex, on one core.
//!
//! Input: a stem scanned by loops — `PolarMesh::uv_sphere(0.1, 200, 2000)` stretched to 20 long
//! (399,802 vertices, a chain of 2,001 skeleton nodes) — with smooth skinning.
//! - `growth_pose`: node states at a mid-growth time, then the skinned positions;
//! - `growth_gravity_frame`: a frame of growth followed by gravity (Verlet step and 10 relaxation
//!   sweeps), then the skinned positions (measured over 10 frames, reported per frame);
//! - `skin_only`: the skinning alone, from given node states.
//!
//! Run: `cargo bench -p blocksmith-kernel --bench anim`.

use std::hint::black_box;

use blocksmith_kernel::anim::{Animation, Gravity, Growth, Modifier, NodeState, Skinning};
use blocksmith_kernel::polar::PolarMesh;
use blocksmith_kernel::Vec3;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn plant() -> PolarMesh {
    let m = blocksmith_kernel::Mesh::uv_sphere(0.1, 200, 2000).scale(Vec3::new(1.0, 1.0, 100.0));
    let north = m.vertex_count() as u32 - 1;
    PolarMesh::from_mesh(m, &[0, north], &[]).unwrap()
}

fn identity(_: usize, _: u32, _: f64, s: NodeState) -> Result<NodeState, String> {
    Ok(s)
}

fn posing(c: &mut Criterion) {
    let pm = plant();
    let vertices = pm.mesh().vertex_count() as u64;
    let mut g = c.benchmark_group("anim_400k");
    g.sample_size(10).throughput(Throughput::Elements(vertices));

    let mut grow = Animation::new(&pm, Some(0), Skinning::Smooth).unwrap();
    grow.add(Modifier::Growth(Growth { delay: 0.001, ..Growth::default() })).unwrap();
    let t = grow.duration() / 2.0;
    g.bench_function("growth_pose", |b| {
        b.iter(|| {
            let states = grow.states_at(black_box(t), &mut identity).unwrap();
            black_box(grow.skinned_positions(&states))
        })
    });

    let states = grow.states_at(t, &mut identity).unwrap();
    g.bench_function("skin_only", |b| b.iter(|| black_box(grow.skinned_positions(black_box(&states)))));

    let mut fall = grow.clone();
    fall.add(Modifier::Gravity(Gravity::default())).unwrap();
    g.throughput(Throughput::Elements(vertices * 10));
    g.bench_function("growth_gravity_10_frames", |b| {
        b.iter(|| {
            let frames = fall.frame_states(10, 1.0 / 24.0, &mut identity).unwrap();
            for s in &frames {
                black_box(fall.skinned_positions(s));
            }
        })
    });
    g.finish();
}

criterion_group!(benches, posing);
criterion_main!(benches);
