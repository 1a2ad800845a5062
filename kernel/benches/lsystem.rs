//! L-system growth as polar operations (seed 004, §11.1) on the thesis's Fig. 12.2 case: "11
//! steps, 400K vertices", the grammar with the stochastic branching removed so that every bud
//! nests two features per step, `L0(s) → [L L0(s+1) L(s+1) P(s+1)][R L0(s+1) L(s+1) P(s+1)]`,
//! axiom `L(0) L0(0) P(0)`. With loops of 32 vertices, 11 steps give 4,094 nested branches. The
//! thesis reports "several seconds" for its 400k vertices; the target here is under 0.5 s.
//!
//! Also: how time grows with the steps (the number of branches doubles per step, Eq. 12.1: the
//! time per vertex must stay flat), the default gap rule, and the derivation alone.
//!
//! Size. The thesis's branches keep their parent's valence (a run of valence/2 + 1 loop
//! vertices, §4.3.1): grown so (`GrowOptions::wide_gaps`), 11 steps make 393,090 vertices,
//! about 96 per branch. By default a run that cannot be slid spans at most 135° of its loop
//! (grow.rs), this grammar nests every branch on a branch's first loop, shaped like its gap
//! (a crescent seen along a heading 30° off the parent's axis), which cannot slide, so valence
//! falls by a quarter per level and 11 steps make 51,651 vertices. Wide gaps cross more at
//! branch bases (grow.rs has the counts); taller, lens-shaped gaps meant to round those first
//! loops folded faces and kept the size (measured, not kept).
//!
//! Measured (release, 2-core machine shared with another engineer's builds, load 2-3,
//! 2026-12-02), wide gaps, by steps 5 / 7 / 9 / 11: 6.4 / 25.9 / 108.8 / 389 ms for 6,018 /
//! 24,450 / 98,178 / 393,090 vertices — 1.07 / 1.06 / 1.11 / 0.99 µs per vertex, flat: time
//! linear in the result (the string doubles per step, Eq. 12.1). `fig12_2_grow_11_steps` (the
//! same case, run first): 426-502 ms, mean 465 ms; the default gaps (51,651 vertices): 79 ms;
//! the derivation alone 3.3 ms. Before the mesh's replace_faces was made cheaper on small
//! patches (same day, same load, alternating runs of the 11-step wide-gap case): 497-627 ms
//! against 399-614 ms after. About 20 % of the time is the kernel zeroing fresh pages for the
//! growing mesh arrays; replace_faces (validation, hashing, sorting the new corners) is most of
//! the rest, under add_refinement.
//! With mimalloc, the allocator of the `blocksmith` binary, which this bench now uses as well
//! (other work paused, 2026-12-02): `fig12_2_grow_11_steps` 326-345 ms, mean 335 ms (glibc's
//! malloc in the same sitting: 428-543 ms, mean 481 ms); by steps 5 / 7 / 9 / 11: 6.1 / 20.3 /
//! 83.3 / 384 ms (1.01 / 0.83 / 0.85 / 0.98 µs per vertex); default gaps 56 ms; derivation 1.4 ms.
//! Run: `cargo bench -p blocksmith-kernel --bench lsystem -- --warm-up-time 1 --measurement-time 3
//! --sample-size 10`.
//!
//! `to_solid` (issue 35) of the same case at 5 / 7 steps, wide gaps (7,040 / 28,544 faces):
//! 0.41 / 1.52 s for solids of 9,526 / 32,568 triangles (2026-12-06), near-linear. Tried and not
//! kept: regions whose faces cross standing in as thin convex slices (the hull of each face,
//! its neighbours and the apexes) instead of their convex hulls: the release sweep's worst case
//! (thesis plant 7, wide gaps) went from 5.4 % to 4.0 % above the union of the tubes, but
//! to_solid took 3.1 / 14.7 s and the solids had 2.7x the triangles; slices of 45 degrees round
//! the axis: 0.79 s, and 5.1 %. Slices only for regions whose hull exceeds them by over 0.2 %
//! of the plant's volume (2026-12-07): 5 steps 331 -> 565 ms, and plant 7 at 5.3 % instead of
//! 5.8 % (of the polar mesh's volume, along 160² lines): each slice holds the branch's axis,
//! which the folded loops of those regions do not surround. Not kept either.

/// The allocator the `blocksmith` binary uses (script/src/main.rs), so the figures are what a
/// recipe run gets.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::hint::black_box;

use blocksmith_kernel::lsystem::{grow, GrowOptions, Lsystem, Module, RuleSpec};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn fig_12_2() -> Lsystem {
    let rule = RuleSpec::deterministic("L0(s)", "[L(s) L0(s+1) L(s+1) P(s+1)][R(s) L0(s+1) L(s+1) P(s+1)]");
    Lsystem::new("L(0) L0(0) P(0)", &[rule], 0).expect("the Fig. 12.2 grammar is valid")
}

/// The thesis's branches: wide gaps, every branch at the trunk's valence.
fn options() -> GrowOptions {
    GrowOptions::DEFAULT.with_valence(32).with_wide_gaps(true)
}

/// The default gap rule (135° unless a loop can be slid).
fn narrow() -> GrowOptions {
    GrowOptions::DEFAULT.with_valence(32)
}

fn bench(c: &mut Criterion) {
    let ls = fig_12_2();
    let s11: Vec<Module> = ls.derive(11).expect("derives");
    for (what, o) in [("wide gaps", options()), ("default gaps", narrow())] {
        let g = grow(&s11, &o).expect("grows");
        eprintln!(
            "Fig. 12.2 case, {what}: {} modules, {} vertices, {} faces, {} nested branches",
            s11.len(),
            g.mesh.vertex_count(),
            g.mesh.face_count(),
            g.features
        );
    }
    c.bench_function("lsystem/fig12_2_grow_11_steps", |b| b.iter(|| grow(black_box(&s11), &options()).expect("grows")));
    c.bench_function("lsystem/fig12_2_grow_11_steps_default_gaps", |b| {
        b.iter(|| grow(black_box(&s11), &narrow()).expect("grows"))
    });
    c.bench_function("lsystem/fig12_2_derive_11_steps", |b| b.iter(|| ls.derive(black_box(11)).expect("derives")));
    let mut group = c.benchmark_group("lsystem/grow_by_steps");
    for steps in [5u32, 7, 9, 11] {
        let s = ls.derive(steps).expect("derives");
        eprintln!("{steps} steps: {} vertices", grow(&s, &options()).expect("grows").mesh.vertex_count());
        group.bench_with_input(BenchmarkId::from_parameter(steps), &s, |b, s| {
            b.iter(|| grow(s, &options()).expect("grows"))
        });
    }
    group.finish();
    // The plant as a valid solid (PolarMesh::to_solid: tubes, stand-ins for twisted regions, the
    // engine's union) at 5 and 7 steps of the same case, wide gaps.
    let mut group = c.benchmark_group("lsystem/to_solid_by_steps");
    group.sample_size(10);
    for steps in [5u32, 7] {
        let pm = grow(&ls.derive(steps).expect("derives"), &options()).expect("grows").mesh;
        let solid = pm.to_solid().expect("a solid");
        eprintln!("{steps} steps: {} faces, solid of {} triangles", pm.face_count(), solid.face_count());
        group.bench_with_input(BenchmarkId::from_parameter(steps), &pm, |b, pm| {
            b.iter(|| pm.to_solid().expect("a solid"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
