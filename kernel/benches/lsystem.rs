//! L-system growth as polar operations (seed 004, §11.1) on the thesis's Fig. 12.2 case: "11
//! steps, 400K vertices", the grammar with the stochastic branching removed so that every bud
//! nests two features per step, `L0(s) → [L L0(s+1) L(s+1) P(s+1)][R L0(s+1) L(s+1) P(s+1)]`,
//! axiom `L(0) L0(0) P(0)`. With loops of 32 vertices, 11 steps give 4,094 nested branches. The
//! thesis reports "several seconds" for its 400k vertices; the target here is under 0.5 s.
//!
//! Also: how time grows with the steps (the number of branches doubles per step, Eq. 12.1: the
//! time per vertex must stay flat), and the derivation alone.
//! Measured (release, 2-core machine, 2026-12-01): before the 135° gap cap, 393k vertices in
//! 0.41-0.58 s (load 3-4). Since the cap a nested branch gets 3/4 of its parent's valence
//! unless its loop can be slid (grow.rs): the branches' first loops, where this grammar nests
//! every branch, are shaped like their gaps (crescents, seen along a heading 30° from the
//! parent's axis) and cannot slide, so valence falls with depth and 11 steps make 51,651
//! vertices. Idle, after the cap: 11 steps in 72 ms. After sibling sectors, slides on any loop
//! that allows them and first segments clear of the parent's tube (load 2.2, the other
//! engineer building): 11 steps in 104 ms; by steps 5 / 7 / 9 / 11: 3.2 / 8.4 / 27.0 / 99.6 ms
//! for 2,484 / 5,514 / 14,787 / 51,651 vertices — 1.3 / 1.5 / 1.8 / 1.9 µs per vertex, near
//! linear in the result (the string doubles per step, Eq. 12.1). A thesis-sized mesh at 1.9 µs
//! per vertex would take roughly 0.75 s under that load (extrapolated, not measured). The hot path is the mesh's
//! `replace_faces` (about 65 % of the time) under polar's add_refinement.
//! Run: `cargo bench -p blocksmith-kernel --bench lsystem -- --warm-up-time 1 --measurement-time 3
//! --sample-size 10`.

use std::hint::black_box;

use blocksmith_kernel::lsystem::{grow, GrowOptions, Lsystem, Module, RuleSpec};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn fig_12_2() -> Lsystem {
    let rule = RuleSpec::deterministic("L0(s)", "[L(s) L0(s+1) L(s+1) P(s+1)][R(s) L0(s+1) L(s+1) P(s+1)]");
    Lsystem::new("L(0) L0(0) P(0)", &[rule], 0).expect("the Fig. 12.2 grammar is valid")
}

fn options() -> GrowOptions {
    GrowOptions::DEFAULT.with_valence(32)
}

fn bench(c: &mut Criterion) {
    let ls = fig_12_2();
    let s11: Vec<Module> = ls.derive(11).expect("derives");
    let g = grow(&s11, &options()).expect("grows");
    eprintln!(
        "Fig. 12.2 case: {} modules, {} vertices, {} faces, {} nested branches",
        s11.len(),
        g.mesh.vertex_count(),
        g.mesh.face_count(),
        g.features
    );
    c.bench_function("lsystem/fig12_2_grow_11_steps", |b| b.iter(|| grow(black_box(&s11), &options()).expect("grows")));
    c.bench_function("lsystem/fig12_2_derive_11_steps", |b| b.iter(|| ls.derive(black_box(11)).expect("derives")));
    let mut group = c.benchmark_group("lsystem/grow_by_steps");
    for steps in [5u32, 7, 9, 11] {
        let s = ls.derive(steps).expect("derives");
        group.bench_with_input(BenchmarkId::from_parameter(steps), &s, |b, s| {
            b.iter(|| grow(s, &options()).expect("grows"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
