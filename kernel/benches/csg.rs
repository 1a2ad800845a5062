//! CSG beside manifold3d (../shared/peers/die_manifold.py) on the same inputs: the die (a cube
//! of side 2 minus 21 spheres of radius 0.15 sunk 0.05, Manifold's 32-segment sphere) and the
//! stress case (a 10³ lattice of unit cubes at spacing 0.9, unioned, minus 1,000 spheres of
//! radius 0.55 with 56 segments at the same centres; ~1M output triangles). Our times include
//! building the result `Mesh` with a source per face; manifold3d's stop at its lazy result's
//! `num_tri()`.
//!
//! The building (Figs. 18–20, 10 storeys, 1,091 blocks) is timed on the inputs its recipe saves
//! (tests/data/csg_building/building_peer.py says how, and times manifold3d on them).
//!
//! `csg/die_engine_only` times what manifold3d's figure times: the inputs already imported into
//! the engine, then the batch subtraction (compose the spheres, subtract) and the export.
//!
//! Run: `cargo bench -p blocksmith-kernel --bench csg` (the die, the building); the stress case runs once,
//! timed, with `CSG_STRESS=1 cargo bench -p blocksmith-kernel --bench csg`; its peak memory with
//! `/usr/bin/time -v target/release/deps/csg-* --bench` under `CSG_STRESS=1`.
//! `CSG_PROFILE=die` (or `building`, or `die_engine` for the engine-only die) evaluates outside
//! criterion (best, median, mean), for a profiler and for steadier side-by-side figures.
//! `CSG_RUN=die|stress|plate` (with `CSG_SEGMENTS`, `CSG_REPS`) is the side-by-side mode that
//! `kernel/benches/csg_side_by_side.py` drives against manifold3d (time, user and system CPU,
//! peak memory per boolean; the die at 32/64/128/256 segments, issue 38).
//! Peer: `PEERS_OUT=target/peers ~/.cache/blocksmith-peers/venv/bin/python
//! ../shared/peers/die_manifold.py die|stress`.
//!
//! Measured (release, this 2-core machine, 2026-12-02, ours and manifold3d's interleaved in one
//! sitting; `cargo bench -p blocksmith-kernel --bench csg`, its `CSG_PROFILE=die|die_engine|building`
//! mode (best and median of 200, of 30 for the building) and `CSG_STRESS=1` mode (one run, peak
//! by `/usr/bin/time -v`); manifold3d 3.5.4 by `../shared/peers/die_manifold.py die --reps 200`
//! and `stress`, and `tests/data/csg_building/building_peer.py` (15 runs))
//! | case | blocksmith | manifold3d | ratio |
//! |---|---|---|---|
//! | the die (9.5k triangles), best | 9.4–10.8 ms | 8.2–9.5 ms | 1.1–1.2× |
//! | the die, median | 9.9–14.1 ms | 9.0–11.3 ms | 1.1–1.3× |
//! | the die, one core (`taskset -c 0`, `RAYON_NUM_THREADS=1`), best / median | 13.8–14.5 / 14.7–16.2 ms | 11.8–12.8 / 12.5–14.0 ms | 1.15× / 1.2× |
//! | the die, engine only (inputs already imported, as manifold3d's figure), best / median | 8.5–9.1 / 9.3–11.5 ms | as above | 1.0× / 0.9–1.2× |
//! | the building, 10 storeys, 1,091 blocks (24.4k triangles; manifold3d's 22.3k), best / median | 68–74 / 71–87 ms | 83–95 / 88–117 ms | 0.8× / 0.75–0.9× |
//! | stress: 10³ cubes ∪, − 1,000 spheres (0.99M triangles), four runs | 5.3–5.8 s, 1.11–1.15 GB peak | 4.11 s (median of 3), 1.71 GB | 1.3–1.4×, 0.67× memory |
//!
//! Ours includes importing every input into the engine (about 2.5 ms of the die: the 21 pips,
//! 10.7k triangles, go in as one solid), provenance and building the result's half-edge
//! `Mesh` (0.5 ms preparing the leaves, 0.9 ms after the engine); manifold3d's
//! starts from solids it already holds (its compose of the spheres costs about what our import
//! does) and stops at its own lazy result. The machine's speed drifts by a third from minute to
//! minute (other tenants), so only ratios from one sitting are quoted.
//!
//! What made the difference (each measured against the build before it, identical outputs):
//! `Csg::evaluate` runs on a worker of the thread pool — called from the script's thread, the
//! booleans ran there and handed every parallel step to the pool, sleeping until it was done
//! (the die: 236 context switches a run, now 30; median −20 %); the engine's patches 3–5
//! (`vendor/manifold-rust/PATCHES.md`: linear-time owner search and sorts, one triangulation
//! task per large face, the collider's radix tree in parallel; −15 %); and the imports'
//! vertex renumbering through a flat map. The binary and the benches allocate with mimalloc:
//! glibc's malloc hands the engine's many mid-sized arrays back to the system and faults them
//! in again (17 % of the die). Before all this (2026-12-01): the die 2.0× by best, the stress
//! case 1.5–1.65×.
//!
//! Issue 38 (2026-12-05; `kernel/benches/csg_side_by_side.py --sizes 32,64,128,256 --stress
//! --rounds 3 --reps 3`, medians, load average 2–4.3 on the 2 cores from other builds): ratios
//! ours / manifold3d before → after, die at 32 / 64 / 128 / 256 segments 1.86 / 1.33 / 1.48 /
//! 1.65 → 1.12 / 1.15 / 1.40 / 1.39, stress 1.30 → 1.19; system time 1.7–7.9× the peer's →
//! 0.4–2.5×. What changed: the result's `Mesh` from the engine's own half-edge pairing (no twin
//! search), imports written straight into the engine's arrays, engine patches 9–10 (no
//! allocation per vertex orbit, parallel maps collected in place) and mimalloc without
//! transparent huge pages. Instructions (callgrind, die at 128 segments, one thread):
//! `Csg::evaluate` 2.895 → 2.475 G. Ours still imports every input (a third of the die's
//! instructions), which manifold3d's figure starts without.
//!
//! Issue 38 (2026-12-07, same command, load about 1.5, the builds of before and after each run
//! whole, one after the other): the import takes our half-edge pairing (engine patch 15) and
//! the radix sort moves keys with their indices (patch 14). Die at 32 / 64 / 128 / 256 segments
//! 1.28 / 1.67 / 1.61 / 2.07 → 1.52 / 1.15 / 1.50 / 1.71, stress 1.22 → 1.44; this machine's
//! runs of one binary vary by a fifth, so the steadier figures are the interleaved ones: the die
//! at 256 segments (`CSG_RUN=die CSG_SEGMENTS=256`, eight rounds of three, medians) 1.12 →
//! 1.02 s, the stress case (four rounds) 5.08 → 5.02 s, same results (hashes). By the engine's
//! stage timer at 256 segments the import is now 0.47 s of the 1.0 s (its half-edges 0.17 →
//! 0.03 s; normals and coplanar groups 0.09–0.11, degenerate edges 0.10–0.13 and the spatial
//! sort 0.15 remain, the same stages as Manifold's own import), the boolean 0.3 s; manifold3d's
//! whole figure is 0.53 s. Parity needs inputs that are not imported at each boolean: engine
//! forms kept with the meshes (and carried through rigid transforms, as Manifold keeps its
//! objects), not attempted yet.
//!
//! Issue 38 (2026-12-07, second session; same command, peaks now the largest of a process's
//! runs): translated copies in an import group are imported once and placed by the engine
//! (patch 16, `compose_apart`, joining the parts' own colliders), copies of a mesh leaf take its
//! preparation, moved, the imports all run before the booleans and the prepared leaves are
//! dropped before them, and the root boolean skips the engine's final sort (patch 17). Die at
//! 32 / 64 / 128 / 256 segments 1.38 / 1.29 / 1.50 / 1.69 → 0.76 / 0.86 / 0.77 / 0.98, stress
//! 1.23 → 1.08 (and 1.00 in three fresh processes of one run each, whose first-run peaks are
//! the fair memory figure: the die at 256 segments 505 → 356 MiB against the peer's 364, the
//! stress case 952 → 837 MiB against 876). Instructions (callgrind, die at 128 segments, one
//! thread): `Csg::evaluate` 2.469 → 1.435 G (the whole process 2.663 → 1.629 G); the stress
//! case's booleans are now 91 % of its time (the engine's own intersection, assembly,
//! triangulation and simplification, as manifold3d's). Then mimalloc's purge delay (how long
//! freed memory stays with the process) from 1 s to 5 s, as the binary sets it
//! (script/cli/src/allocator.rs): the stress case's system time 0.7–1.1 → 0.3–0.4 s; the same
//! command gives 0.79 / 0.94 / 0.76 / 0.81, stress 0.93, and three fresh processes of one run
//! each 0.87 (32 segments) / 0.91 (256) / 0.95 (stress), peaks 10.0 / 358 / 926 MiB against
//! 6.7 / 364 / 919 (a longer delay keeps freed pages a thread could not yet reuse: the stress
//! case's peak 837 → 926 MiB).
//!
//! Issue 38 (2026-12-07, third session; same command): a boolean of the tree takes its operands
//! and the engine frees them once the result's edges are assembled (patch 18): the bytes in use
//! at the peak (a counting allocator), die at 32 / 64 / 128 / 256 segments 5.1 / 19.4 / 75.0 /
//! 295.6 → 4.1 / 15.6 / 60.8 / 240.5 MiB, stress 602 → 498 MiB. Then the allocator: blocks of
//! 4 KiB and more go to glibc's malloc with one arena, kept until the program is idle
//! (script/cli/src/allocator.rs; mimalloc had kept a freed block in its thread's region of the
//! arena, and resident memory was 1.3–2.4 times the bytes in use). Ratios ours / manifold3d,
//! time then peak memory, three runs of the command on a machine whose speed drifted by a third
//! between them: die 0.59–0.83 / 0.63–0.85 / 0.71–0.77 / 0.70–0.85, stress 0.87–0.95; peaks
//! 5.8–6.0 / 17.5 / 67 / 265 / 528–541 MiB against 6.4–6.6 / 23.5–25.4 / 85–97 / 364 /
//! 869–977 (memory 0.89–0.91 / 0.69–0.75 / 0.69–0.79 / 0.73 / 0.55–0.61).
//! With 360 segments (950k result triangles, the issue's ~1M row): time 0.71, memory 522 against
//! 688 MiB (0.76). Growth from size to size (`--instructions`: callgrind, one thread each, load-
//! independent): ours 0.120 / 0.397 / 1.429 / 5.403 / 10.47 G instructions at 32–360 segments,
//! manifold3d 0.124 / 0.429 / 1.582 / 6.139 / 11.97 — steps of 3.32 / 3.60 / 3.78 / 1.94 against
//! 3.45 / 3.69 / 3.88 / 1.95 (triangles 3.61 / 3.69 / 3.85 / 1.96). In wall time the steps move by
//! ±15 % from run to run (both sides' times at 128 segments are bimodal across processes), and
//! manifold3d's time per triangle is higher at the small end (1.3 µs at 9.5k triangles, 0.98 at
//! 34k, with the same instructions per triangle), so its 32 → 64 step is 2.7–2.9 against our
//! 3.0–3.1.
//!
//! Issue 38 (2026-12-07, fourth session; same command, 7 rounds of 3): the engine places the
//! copies of an instanced import in parallel, each array written once in place (patch 19); a
//! translated copy is seen apart in one walk along its original's x order (a lookup per vertex
//! only when the walk cannot tell) and shares its original's arrays instead of cloning them; the
//! import plan's bounds and the flat-shell sums run in parallel. Stage times at 256 segments
//! (temporary timers, two threads): the copies' preparation 25–34 → 11–12 ms, the engine's
//! placement 42–46 → 36–37, the flat-shell check 20 → 11, the join 4.6 → 3.2. Ratios, time then
//! memory: die 0.59 / 0.57 / 0.70 / 0.66 / 0.65 at 32–360 segments, stress 0.97; peaks 5.7 /
//! 16.5 / 61 / 239 / 470 MiB against 6.6 / 23.6 / 98 / 364 / 688 (0.86 / 0.70 / 0.62 / 0.66 /
//! 0.68), stress 518 against 879 (0.59). Instructions 0.117 / 0.385 / 1.385 / 5.231 G at 32–256
//! segments against 0.125 / 0.428 / 1.585 / 6.147 (0.94 → 0.85), steps 3.28 / 3.60 / 3.78 against
//! 3.44 / 3.70 / 3.88. Wall-time steps, medians of the rounds: 2.98 / 3.72 / 4.26 / 1.98 against
//! 2.76 / 3.51 / 3.99 / 2.13 (the fastest round's: 3.01 / 3.63 / 4.28 / 1.98 against 2.71 / 3.69 /
//! 4.22 / 2.07): ours grows with the triangles (0.61–0.75 µs each from 9.5k to 950k), the peer's
//! less than them from 9.5k to 126k, its time per triangle falling from 1.27 to 0.99 µs.
//!
//! Issue 38 (2026-12-07, fifth session; same code, same command, 7 rounds of 3): the script
//! splits the growth into a cost per triangle and the rest. Ratios, time then memory: die 0.76 /
//! 0.66 / 0.72 / 0.77 / 0.71 at 32–360 segments, stress 0.89; memory 0.94 / 0.71 / 0.72 / 0.66 /
//! 0.68, stress 0.60. Steps ours / manifold3d 2.82 / 2.83, 3.74 / 3.66, 3.68 / 3.59, 1.93 / 2.13
//! (the triangles 3.61 / 3.69 / 3.85 / 1.96); the cost of the triangles each step adds 0.59 /
//! 0.79 / 0.89 / 0.91 µs each against 0.98 / 1.07 / 1.14 / 1.34 (ours cheaper in 26 of 28 rounds);
//! from 32 to 360 segments ours grows 85× against 90× (the triangles 100×), the log-log slope
//! 0.974 against 0.968. The steps' verdict moves with the machine from run to run (a step's two
//! sides differ by 1–3 %, the run-to-run spread is ±10 %).
//!
//! Then engine patch 20 (the composed collider shares its parts' trees instead of copying
//! every box; its walk branches once per query, not per node) and the copies' walk polling
//! the cancel token. Peaks 4.4 / 11.6 / 43.0 / 168.3 / 330.6 MiB at 32–360 segments (were
//! 6.2 / 16.9 / 61.5 / 239 / 471), memory ratios 0.67 / 0.49 / 0.44 / 0.46 / 0.48, stress 0.59;
//! time 0.64 / 0.58 / 0.68 / 0.66 / 0.71, stress 0.97. Instructions 0.113 / 0.369 / 1.321 /
//! 4.973 G at 32–256 segments against 0.126 / 0.428 / 1.585 / 6.148 (0.90 → 0.81), steps 3.25
//! / 3.58 / 3.76 against 3.40 / 3.70 / 3.88. Wall-time steps 2.72 / 3.88 / 4.11 / 1.78 against
//! 2.89 / 3.58 / 4.07 / 1.89; the cost of the added triangles 0.70 / 0.84 / 0.87 / 0.76 µs
//! against 1.21 / 1.23 / 1.27 / 1.07 (ours cheaper in 28 of 28 rounds); 32 → 360 segments ours
//! ×77 against ×73, the log-log slope 0.940 against 0.957.
//!
//! Issue 38 (2026-12-07, sixth session; same command, 7 rounds of 3): engine patches 21 (the
//! winding fill flags the cut edges instead of a binary search per edge, one root search per
//! vertex) and 22 (the export with its pairing gathered in parallel, its order's sort skipped
//! for keys in order), and the result's `Mesh` build walking its fans in parallel. Instructions
//! 0.110 / 0.355 / 1.264 / 4.735 G at 32–256 segments (were 0.113 / 0.369 / 1.321 / 4.973)
//! against 0.124 / 0.426 / 1.582 / 6.148: ratio 0.89 → 0.77, steps 3.23 / 3.56 / 3.75 against
//! 3.44 / 3.71 / 3.89. Three side-by-side runs as the work went in (the first with patch 21's
//! flags only, the last with everything; load 0.8–1.8), time ratios at
//! 32–360 segments 0.58–0.56–0.53 / 0.60–0.54–0.55 / 0.59–0.55–0.69 / 0.63–0.64–0.63 /
//! 0.60–0.67–0.61, stress 0.91 / 0.87 / 0.95; memory 0.61–0.73 / 0.49–0.51 / 0.44–0.50 / 0.46 /
//! 0.48, stress 0.58–0.60. Wall-time steps ours / manifold3d, run by run: 32 → 64 2.89 / 2.89,
//! 2.72 / 2.72, 2.43 / 3.11; 64 → 128 3.47 / 3.70, 3.73 / 3.51, 3.95 / 3.25; 128 → 256 4.08 /
//! 3.82, 4.57 / 4.07, 3.96 / 4.29; 256 → 360 1.93 / 2.07, 2.02 / 1.97, 1.89 / 1.86: each step
//! won in some runs and lost in others, the cost of the added triangles ours cheaper in 27 or
//! 28 rounds of 28 in each.
//!
//! Issue 38 (2026-12-07, seventh session; same command, 7 rounds of 3): engine patches 23 (a
//! boolean for export without vertex normals), 24 (a cleanup with nothing to repair told in one
//! walk per vertex), 25 (an export-only result compacted in place) and 26 (an operand of parts
//! apart united and assembled part by part in parallel), and translated copies found at once.
//! Instructions 0.099 / 0.315 / 1.118 / 4.163 G at 32–256 segments against 0.124 / 0.429 /
//! 1.583 / 6.148: ratio 0.80 / 0.74 / 0.71 / 0.68, steps 3.20 / 3.55 / 3.72 against 3.46 /
//! 3.69 / 3.88. Two side-by-side runs (after patches 23–24, load 0.9–1.9; after everything,
//! load 1.8): time ratios at 32–360 segments 0.60–0.49 / 0.48–0.47 / 0.52–0.45 / 0.52–0.50 /
//! 0.48–0.48, stress 0.80 / 0.92; memory 0.70–0.71 / 0.50 / 0.46–0.48 / 0.46 / 0.48, stress
//! 0.58–0.61. Wall-time steps ours / manifold3d: 32 → 64 2.72 / 2.73, 2.68 / 2.79; 64 → 128
//! 3.46 / 3.54, 3.55 / 3.71; 128 → 256 4.26 / 4.16, 3.81 / 4.12; 256 → 360 1.94 / 1.90, 2.13 /
//! 1.91; the cost of the added triangles ours cheaper in 28 of 28 rounds in both.
//!
//! Issue 38 (2026-12-08, eighth session): the perforated plate (`CSG_RUN=plate`, a 100 × 100 × 2
//! plate minus n × n cylinders of 32 segments; `--plates 10,20,40` in the script), where both
//! sides grew faster than their triangles: the triangulation of the two faces of n² holes, its
//! keyholing O(holes × verts) (30 % of the CPU at 40 × 40) and its ear queries over clipped
//! verts. Engine patches 27 (the ear clipper's tree built again as verts are clipped) and 28 (the
//! keyhole searches answered from a grid index), both with the walks' exact triangles, and the
//! flat-shell check's union-find on all threads. The plate, ours alone: 40 × 40 1.03–1.33 →
//! 0.72–0.75 s, 80 × 80 (845k triangles) 9.0 → 3.6 s (manifold3d 10.0 s, one run each). Side by
//! side (5 rounds of 3, load 1.5–2.0): plate time ratios 0.92 / 0.91 / 0.63 at 10 / 20 / 40
//! holes a side (0.87–0.96 / 0.90–0.98 / 0.88–0.93 before), memory 1.07 / 0.75 / 0.75, growth
//! 10 → 40 ×16.6 against ×24.3 (exponent 1.014 against 1.152, ours no faster in 5 of 5
//! rounds; triangles ×16.0); the die 0.55 / 0.47 / 0.58 / 0.48 / 0.54 at 32–360 segments,
//! stress 0.91, memory 0.73 / 0.51 / 0.47 / 0.46 / 0.48, stress 0.62. Instructions (one
//! thread, callgrind): the plate at 20 × 20 2.972 → 2.538 G, the die at 128 segments 1.114 →
//! 1.078 G.

/// The allocator the `blocksmith` binary uses (script/cli/src/main.rs), so the figures are what
/// a recipe run gets.
#[global_allocator]
static ALLOCATOR: blocksmith_kernel::limits::CountingAllocator<allocator::SplitAllocator> =
    blocksmith_kernel::limits::CountingAllocator(allocator::SplitAllocator);

/// The binary's own allocator module; the bench sets it up as the binary does, without the
/// thread that releases memory when idle.
// Its tests are the binary's, not run here.
#[allow(dead_code, unused_imports)]
#[path = "../../script/cli/src/allocator.rs"]
mod allocator;

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

use blocksmith_kernel::csg::engine::Solid;
use blocksmith_kernel::csg::Csg;
use blocksmith_kernel::io::load;
use blocksmith_kernel::{Mesh, Vec3};
use criterion::{criterion_group, Criterion};

#[path = "../tests/csg_support/die.rs"]
mod die;

use die::die_pips;

fn sphere(radius: f64, segments: i32) -> Mesh {
    let t = Solid::manifold_sphere(radius, segments).triangles();
    Mesh::from_indexed(t.positions, t.triangles.as_flattened(), &vec![3; t.triangles.len()]).unwrap()
}

fn die(segments: i32) -> Csg {
    let s = sphere(0.15, segments);
    let cube = Csg::mesh(Mesh::cuboid(Vec3::splat(-1.0), Vec3::splat(1.0)));
    cube.difference(
        Csg::union_all(die_pips().into_iter().map(|c| Csg::mesh(s.translate(Vec3::from(c)))).collect()).unwrap(),
    )
}

/// The perforated plate: a 100 × 100 × 2 plate minus `n` × `n` cylinders (radius 30 % of the
/// pitch, 32 segments, through the plate), one boolean. Its two large faces each become one
/// polygon with `n`² holes: the case where the triangulation's keyholes and ears see the whole face.
fn plate(n: i32) -> Csg {
    let n = n.max(1);
    let pitch = 100.0 / f64::from(n);
    let cylinder = Mesh::cylinder(0.3 * pitch, 4.0, 32);
    let holes = (0..n * n)
        .map(|k| {
            let (i, j) = (f64::from(k % n), f64::from(k / n));
            Csg::mesh(cylinder.translate(Vec3::new((i + 0.5) * pitch, (j + 0.5) * pitch, 1.0)))
        })
        .collect();
    Csg::mesh(Mesh::cuboid(Vec3::ZERO, Vec3::new(100.0, 100.0, 2.0))).difference(Csg::union_all(holes).unwrap())
}

fn stress() -> Csg {
    stress_with(56)
}

fn stress_with(segments: i32) -> Csg {
    let centres: Vec<Vec3> =
        (0..1000).map(|i| Vec3::new((i / 100) as f64, (i / 10 % 10) as f64, (i % 10) as f64) * 0.9).collect();
    let s = sphere(0.55, segments);
    let cubes = centres.iter().map(|&c| Csg::mesh(Mesh::cuboid(c - 0.5, c + 0.5))).collect();
    let spheres = centres.iter().map(|&c| Csg::mesh(s.translate(c))).collect();
    Csg::union_all(cubes).unwrap().difference(Csg::union_all(spheres).unwrap())
}

/// The building of examples/csg_fig18_building.rhai from the inputs it saves with
/// `--set inputs=DIR` (see tests/data/csg_building/building_peer.py): per storey
/// (slab ∪ walls) − openings, then the union of the storeys and the roof. `None` when the inputs
/// were not written.
fn building() -> Option<Csg> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/peers/csg_building");
    let obj = |name: &str| load(dir.join(format!("{name}.obj"))).ok().map(Csg::mesh);
    let mut storeys = Vec::new();
    for k in 0.. {
        let Some(slab) = obj(&format!("slab_{k}")) else { break };
        let walls = obj(&format!("walls_{k}"))?;
        storeys.push(slab.union(walls).difference(obj(&format!("openings_{k}"))?));
    }
    storeys.push(obj("roof")?);
    Csg::union_all(storeys)
}

/// `m` imported into the engine as it is (one tag per triangle).
fn import(m: &Mesh) -> Solid {
    let (t, _) = m.triangulate_with_sources().unwrap();
    let tris: Vec<[u32; 3]> = (0..t.face_count() as u32)
        .map(|f| {
            let v: Vec<u32> = t.face_vertices(f).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let tags: Vec<u32> = (0..tris.len() as u32).collect();
    Solid::new(t.positions(), &tris, &tags).unwrap()
}

/// The die's inputs already in the engine, as manifold3d's timing starts: the cube and the 21
/// spheres imported one by one; timed, the batch subtraction (compose the spheres, subtract).
fn die_solids() -> (Solid, Vec<Solid>) {
    let s = sphere(0.15, 32);
    let cube = import(&Mesh::cuboid(Vec3::splat(-1.0), Vec3::splat(1.0)));
    (cube, die_pips().into_iter().map(|c| import(&s.translate(Vec3::from(c)))).collect())
}

/// The engine-only die: the spheres composed and subtracted, on a worker of the thread pool as
/// `Csg::evaluate` runs.
fn die_engine(cube: &Solid, spheres: &[Solid]) -> usize {
    rayon::scope(|_| {
        let pits = Solid::union_all(spheres.to_vec()).unwrap();
        cube.boolean(&pits, blocksmith_kernel::csg::CsgOp::Difference).unwrap().triangles().triangles.len()
    })
}

fn bench(c: &mut Criterion) {
    let (cube, spheres) = die_solids();
    c.bench_function("csg/die_engine_only", |b| {
        b.iter(|| black_box(die_engine(&cube, &spheres)));
    });
    let tree = die(32);
    let m = tree.evaluate().unwrap();
    println!("die: {} triangles, volume {:.9}, genus {}", m.face_count(), m.volume(), m.genus());
    let mut g = c.benchmark_group("csg");
    g.sample_size(30);
    g.bench_function("die", |b| b.iter(|| black_box(tree.evaluate().unwrap())));
    match building() {
        Some(tree) => {
            let m = tree.evaluate().unwrap();
            println!("building: {} triangles, volume {:.9}, genus {}", m.face_count(), m.volume(), m.genus());
            g.sample_size(10);
            g.bench_function("building", |b| b.iter(|| black_box(tree.evaluate().unwrap())));
        }
        None => println!("building: no inputs in target/peers/csg_building (see building_peer.py)"),
    }
    g.finish();
}

criterion_group!(benches, bench);

/// Runs `f` `n` times and prints the best, median and mean times of one run.
fn timed(case: &str, n: usize, mut f: impl FnMut()) {
    let mut times: Vec<f64> = (0..n)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let mean = times.iter().sum::<f64>() / n as f64;
    println!("CSG_PROFILE {case}: min {:.2} ms, median {:.2} ms, mean {mean:.2} ms of {n}", times[0], times[n / 2]);
}

/// This process's resident memory now and at its peak (`VmRSS`, `VmHWM`), in bytes.
fn rss() -> (u64, u64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find_map(|l| l.strip_prefix(name))
            .and_then(|v| v.split_whitespace().next()?.parse::<u64>().ok())
            .map_or(0, |kib| kib * 1024)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

/// This process's user and system CPU time so far, in seconds (`/proc/self/stat`, clock ticks
/// of 10 ms: summed over several runs).
fn cpu() -> (f64, f64) {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which is in parentheses and may hold spaces): utime and
    // stime are the 12th and 13th.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<f64> = rest.split_whitespace().skip(11).take(2).filter_map(|v| v.parse().ok()).collect();
    if f.len() == 2 {
        (f[0] / 100.0, f[1] / 100.0)
    } else {
        (0.0, 0.0)
    }
}

/// `CSG_RUN=die|stress|plate` (`CSG_SEGMENTS`, default 32 for the die, 56 for the stress case and
/// 10 holes a side for the plate;
/// `CSG_REPS`, default 5): the side-by-side script's measurement (kernel/benches/csg_side_by_side.py).
/// Each run starts with the peak resident memory reset to the current one (`/proc/self/clear_refs`),
/// so the peak it prints is the boolean's own on top of its inputs: the largest of the runs' (later
/// runs reuse memory the allocator kept from the first, so their own peaks understate it); one
/// line, key=value.
fn side_by_side(case: &str) {
    let default_segments = match case {
        "stress" => 56,
        "plate" => 10,
        _ => 32,
    };
    let var = |name: &str, default: i32| std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default);
    let (segments, reps) = (var("CSG_SEGMENTS", default_segments), var("CSG_REPS", 5).max(1) as usize);
    let tree = match case {
        "stress" => stress_with(segments),
        "plate" => plate(segments),
        _ => die(segments),
    };
    let mut times = Vec::new();
    let mut peaks = Vec::new();
    let mut tris = 0;
    let mut result = String::new();
    let (u0, s0) = cpu();
    for _ in 0..reps {
        let _ = std::fs::write("/proc/self/clear_refs", "5");
        let (before, _) = rss();
        let t = Instant::now();
        let m = tree.evaluate().unwrap();
        times.push(t.elapsed().as_secs_f64());
        let peak = rss().1.saturating_sub(before);
        tris = m.face_count();
        if result.is_empty() {
            result = fingerprint(&m);
        }
        drop(black_box(m));
        peaks.push(peak);
    }
    let (u1, s1) = cpu();
    times.sort_by(f64::total_cmp);
    peaks.sort_unstable();
    println!(
        "CSG_RUN case={case} segments={segments} tris={tris} reps={reps} bool_med_s={:.6} bool_min_s={:.6} \
         user_s={:.3} sys_s={:.3} peak_delta_mib={:.1} peak_mib={:.1} {result}",
        times[reps / 2],
        times[0],
        (u1 - u0) / reps as f64,
        (s1 - s0) / reps as f64,
        peaks[reps - 1] as f64 / 1048576.0,
        rss().1 as f64 / 1048576.0
    );
}

/// What identifies a result, for comparing builds: its volume, genus, whether it is closed and
/// manifold, and an FNV-1a hash of its positions' bits, its faces' corners and their sources.
fn fingerprint(m: &Mesh) -> String {
    use std::hash::{Hash, Hasher};
    struct Fnv(u64);
    impl Hasher for Fnv {
        fn write(&mut self, bytes: &[u8]) {
            for &b in bytes {
                self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
            }
        }
        fn finish(&self) -> u64 {
            self.0
        }
    }
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    m.positions().iter().for_each(|p| p.to_array().map(f64::to_bits).hash(&mut h));
    (0..m.face_count() as u32).for_each(|f| m.face_vertices(f).for_each(|v| v.hash(&mut h)));
    m.face_sources().hash(&mut h);
    format!(
        "volume={:.12} genus={} closed_manifold={} hash={:016x}",
        m.volume(),
        m.genus(),
        m.is_closed() && m.is_manifold(),
        h.finish()
    )
}

fn main() {
    // As the `blocksmith` binary does (script/cli/src/allocator.rs).
    allocator::configure();
    // `CSG_PROFILE=die|die_engine|building`: evaluate 200 times outside criterion (whose
    // analysis threads would otherwise fill a profile), printing best, median and mean — for
    // `perf record`, and for side-by-side figures steadier than criterion's on a busy machine.
    if let Ok(case) = std::env::var("CSG_RUN") {
        side_by_side(&case);
        return;
    }
    if let Ok(case) = std::env::var("CSG_PROFILE") {
        if case == "die_engine" {
            let (cube, spheres) = die_solids();
            timed(&case, 200, || {
                black_box(die_engine(&cube, &spheres));
            });
        } else {
            let tree =
                if case == "building" { building().expect("building inputs (see building_peer.py)") } else { die(32) };
            timed(&case, if case == "building" { 30 } else { 200 }, || {
                black_box(tree.evaluate().unwrap());
            });
        }
        return;
    }
    if std::env::var_os("CSG_STRESS").is_some() {
        let tree = stress();
        let t0 = Instant::now();
        let m = tree.evaluate().unwrap();
        let dt = t0.elapsed().as_secs_f64();
        println!(
            "CSG_STRESS tris={} volume={:.6} genus={} closed={} total_s={dt:.3}",
            m.face_count(),
            m.volume(),
            m.genus(),
            m.is_closed() && m.is_manifold()
        );
        // The same booleans from solids already in the engine (manifold3d's timing).
        let centres: Vec<Vec3> =
            (0..1000).map(|i| Vec3::new((i / 100) as f64, (i / 10 % 10) as f64, (i % 10) as f64) * 0.9).collect();
        let s = sphere(0.55, 56);
        let cubes: Vec<Solid> = centres.iter().map(|&c| import(&Mesh::cuboid(c - 0.5, c + 0.5))).collect();
        let spheres: Vec<Solid> = centres.iter().map(|&c| import(&s.translate(c))).collect();
        let t0 = Instant::now();
        let tris = rayon::scope(|_| {
            let u = Solid::union_all(cubes).unwrap();
            let r = u.boolean(&Solid::union_all(spheres).unwrap(), blocksmith_kernel::csg::CsgOp::Difference).unwrap();
            r.triangles().triangles.len()
        });
        println!("CSG_STRESS engine_only tris={tris} engine_s={:.3}", t0.elapsed().as_secs_f64());
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
