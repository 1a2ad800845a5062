//! Modeling with blocks (seed 000 §3) on procedural buildings ([`building`]): connect, control
//! mesh and tessellation together, at about 1,000, 1,700 and 10,000 blocks. The paper's office
//! building of Fig. 18 has 1,694 blocks and 105,264 triangles; the target is a building of that
//! size in under a second. Each size prints its counts and triangles per second (from a timed
//! run outside criterion), and the criterion groups show how time grows with the blocks
//! (connections are found through a BVH, meshing is per patch: near-linear is expected).
//! Run: `cargo bench -p blocksmith-kernel --bench blocks -- --warm-up-time 1 --measurement-time 3 --sample-size 10`.
//!
//! Measured (2 shared cores, load ~3.4, kd-trees on rayon): 1,047 blocks (40,504 patches,
//! 81,008 triangles) 0.51 s; 1,633 blocks (63,936 patches, 127,872 triangles) 0.46 s; 9,729
//! blocks (390,680 patches, 781,360 triangles) 4.8 s — about 0.5 ms per block, linear. At 1,633
//! blocks: connections 35 ms, control mesh 96 ms, tessellation 567 ms (limit evaluation is most
//! of it).

use std::hint::black_box;
use std::time::Instant;

use blocksmith_kernel::blocks::building::{building, BuildingPlan};
use blocksmith_kernel::blocks::{BlockModel, MeshOptions};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};

/// ≈ 1,000, ≈ 1,700 (the paper's Fig. 18 size) and ≈ 10,000 blocks.
const PLANS: [BuildingPlan; 3] = [
    BuildingPlan { storeys: 4, rooms_x: 5, rooms_y: 6 },
    BuildingPlan { storeys: 4, rooms_x: 7, rooms_y: 7 },
    BuildingPlan { storeys: 4, rooms_x: 18, rooms_y: 18 },
];

fn mesh(m: &BlockModel) -> usize {
    m.tessellate(&MeshOptions::DEFAULT, None).expect("buildings mesh").stats.triangles
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("blocks/building_connect_control_tessellate");
    group.sample_size(10);
    for plan in PLANS {
        let m = building(&plan);
        let start = Instant::now();
        let t = m.tessellate(&MeshOptions::DEFAULT, None).expect("buildings mesh");
        let secs = start.elapsed().as_secs_f64();
        eprintln!(
            "building {}x{}x{}: {} blocks, {} patches, {} sub-patches, {} triangles; one run {:.3} s, {:.0} triangles/s",
            plan.storeys,
            plan.rooms_x,
            plan.rooms_y,
            t.stats.blocks,
            t.stats.patches,
            t.stats.sub_patches,
            t.stats.triangles,
            secs,
            t.stats.triangles as f64 / secs
        );
        group.throughput(Throughput::Elements(t.stats.blocks as u64));
        group.bench_with_input(BenchmarkId::from_parameter(t.stats.blocks), &m, |b, m| b.iter(|| mesh(black_box(m))));
    }
    group.finish();
    let mut group = c.benchmark_group("blocks/building_stages");
    group.sample_size(10);
    let m = building(&PLANS[1]);
    let cm = m.control_mesh().expect("buildings build");
    group.bench_function("connections", |b| b.iter(|| black_box(&m).connections().expect("connects").len()));
    group
        .bench_function("control_mesh", |b| b.iter(|| black_box(&m).control_mesh().expect("builds").mesh.face_count()));
    group.bench_function("tessellate_control", |b| {
        b.iter(|| {
            blocksmith_kernel::blocks::tessellate_control(black_box(&cm), &MeshOptions::DEFAULT, None)
                .expect("meshes")
                .sub_patches
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
