#!/usr/bin/env python3
"""Booleans side by side with manifold3d (issue 38): the die (a cube of side 2 minus 21 spheres of
radius 0.15, Manifold's sphere at 32, 64, 128 and 256 segments) and the stress case (10^3 unit
cubes united, minus 1,000 spheres of radius 0.55, 56 segments, ~1M triangles) and, with
`--plates 10,20,40`, the perforated plate (a 100 x 100 x 2 plate minus n x n cylinders of 32
segments: two faces of n^2 holes each, where the triangulation of a face with holes dominates), on
the same inputs, interleaved (the order of the two sides alternates from round to round).

Ours: the csg bench binary in its CSG_RUN mode (kernel/benches/csg.rs): `cube(2) - combine(spheres)`
as the CSG tree a recipe builds, evaluated into our Mesh with a source per face. Theirs:
manifold3d's batch_boolean of the same solids (../shared/peers/die_manifold.py's inputs), forced
by num_tri(); the stress case's union and difference both (the tree's total, as ours).

Each side runs in its own process, `--reps` booleans a process; it prints, per boolean, the median
wall time, user and system CPU seconds (/proc/self/stat), and the largest peak resident memory
above the memory before a boolean (the peak is reset with /proc/self/clear_refs before each
boolean; the largest, because later booleans of one process reuse memory the allocator kept from
the first, mimalloc more than glibc's, so their own peaks understate it). Around every
process, `perf stat` counts user and kernel instructions (load-independent; the whole process,
setup included) when perf works. Printed: one line per process, a table of medians over the
rounds with the ratios ours / manifold3d, then the die's growth from one size to the next, each side
(per round, then the median), the time per triangle and the cost of the triangles each step adds
(free of any fixed cost per boolean; `cost_per_triangle`), and the growth over the whole range.

`--instructions` counts instead of timing: the die's boolean in instructions with valgrind's
callgrind, each side on one thread, and their growth from size to size — the same on a busy or a
quiet machine, where the wall time's growth carries the machine's drift and the peer's latency at
small sizes.

  cargo bench -p blocksmith-kernel --bench csg --no-run    # prints the binary's path
  ~/.cache/blocksmith-peers/venv/bin/python kernel/benches/csg_side_by_side.py \\
      --bin target/release/deps/csg-HASH [--sizes 32,64,128,256] [--stress] [--plates 10,20,40]
      [--rounds 3] [--reps 3]
      [--instructions]
"""
import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
PEERS = os.environ.get("BLOCKSMITH_PEERS", os.path.join(HERE, "..", "..", "..", "shared", "peers"))


def status_bytes(field):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field):
                return int(line.split()[1]) * 1024
    return 0


def peer(case, segments, reps):
    """manifold3d's side, in this process: one CSG_RUN-like line."""
    sys.path.insert(0, PEERS)
    import manifold3d as mf
    import die_manifold as dm

    if case == "die":
        cube = mf.Manifold.cube((2.0, 2.0, 2.0), True)
        sph = mf.Manifold.sphere(0.15, segments)
        spheres = [sph.translate(p) for p in dm.die_pips()]
        for s in [cube] + spheres:
            s.num_tri()

        def boolean():
            r = mf.Manifold.batch_boolean([cube] + spheres, mf.OpType.Subtract)
            return r.num_tri()
    elif case == "plate":
        n = max(1, segments)
        pitch = 100.0 / n
        plate = mf.Manifold.cube((100.0, 100.0, 2.0))
        cylinder = mf.Manifold.cylinder(4.0, 0.3 * pitch, 0.3 * pitch, 32)
        holes = [cylinder.translate(((k % n + 0.5) * pitch, (k // n + 0.5) * pitch, -1.0)) for k in range(n * n)]
        for s in [plate] + holes:
            s.num_tri()

        def boolean():
            r = mf.Manifold.batch_boolean([plate] + holes, mf.OpType.Subtract)
            return r.num_tri()
    else:
        centres = [(i * 0.9, j * 0.9, k * 0.9) for i in range(10) for j in range(10) for k in range(10)]
        cube = mf.Manifold.cube((1.0, 1.0, 1.0), True)
        sph = mf.Manifold.sphere(0.55, segments)
        cubes = [cube.translate(c) for c in centres]
        spheres = [sph.translate(c) for c in centres]
        for s in cubes + spheres:
            s.num_tri()

        def boolean():
            u = mf.Manifold.batch_boolean(cubes, mf.OpType.Add)
            r = mf.Manifold.batch_boolean([u] + spheres, mf.OpType.Subtract)
            return r.num_tri()

    if reps == 0:
        return  # the inputs alone: the baseline of the instruction count (--instructions)
    times, peaks = [], []
    tris = 0
    t0 = os.times()
    for _ in range(reps):
        try:
            with open("/proc/self/clear_refs", "w") as f:
                f.write("5")
        except OSError:
            pass
        before = status_bytes("VmRSS:")
        t = time.perf_counter()
        tris = boolean()
        times.append(time.perf_counter() - t)
        peaks.append(max(0, status_bytes("VmHWM:") - before))
    t1 = os.times()
    print(
        f"PEER_RUN case={case} segments={segments} tris={tris} reps={reps} "
        f"bool_med_s={statistics.median(times):.6f} bool_min_s={min(times):.6f} "
        f"user_s={(t1.user - t0.user) / reps:.3f} sys_s={(t1.system - t0.system) / reps:.3f} "
        f"peak_delta_mib={max(peaks) / 1048576:.1f} peak_mib={status_bytes('VmHWM:') / 1048576:.1f}",
        flush=True,
    )


def perf_works():
    try:
        r = subprocess.run(["perf", "stat", "-x,", "-e", "instructions:u", "true"], capture_output=True, text=True)
        return r.returncode == 0 and "not supported" not in r.stderr
    except OSError:
        return False


def measured(cmd, env, use_perf):
    """Runs `cmd`; its key=value line, with perf's instruction counts (billions) when asked."""
    full = (["perf", "stat", "-x,", "-e", "instructions:u,instructions:k"] if use_perf else []) + cmd
    r = subprocess.run(full, capture_output=True, text=True, env=env)
    line = next((l for l in r.stdout.splitlines() if "_RUN " in l), None)
    if line is None:
        sys.exit(f"no result from {' '.join(cmd)}:\n{r.stdout}\n{r.stderr}")
    out = dict(kv.split("=", 1) for kv in line.split()[1:])
    for l in r.stderr.splitlines():
        parts = l.split(",")
        if len(parts) > 2 and parts[2].startswith("instructions"):
            key = "ginstr_user" if parts[2].endswith(":u") else "ginstr_kernel"
            try:
                out[key] = f"{int(parts[0]) / 1e9:.3f}"
            except ValueError:
                pass
    print(line.split()[0], " ".join(f"{k}={v}" for k, v in out.items()), flush=True)
    return out


def callgrind_count(cmd, env, toggle=None):
    """The instructions valgrind's callgrind counts in `cmd` (only inside `toggle` when given)."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "callgrind.out")
        full = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}"]
        full += [f"--toggle-collect={toggle}"] if toggle else []
        r = subprocess.run(full + cmd, capture_output=True, text=True, env=env)
        if r.returncode != 0 or not os.path.exists(out):
            sys.exit(f"callgrind failed on {' '.join(cmd)}:\n{r.stderr[-2000:]}")
        with open(out) as f:
            for line in f:
                if line.startswith("summary:") or line.startswith("totals:"):
                    return int(line.split()[1])
    sys.exit(f"no instruction count for {' '.join(cmd)}")


def instructions(binary, sizes):
    """The die's boolean in instructions (load-independent), each side, and their growth per size.
    Ours: the instructions inside Csg::evaluate_here (the whole of `Csg::evaluate`'s work) on one
    thread. manifold3d's: a process that runs batch_boolean and num_tri less one that only builds the
    inputs (OpenBLAS, which numpy loads, on one thread, so its idle workers do not spin into either)."""
    print("| die segments | ours Ginstr | manifold3d Ginstr | ratio | ours growth | manifold3d growth |")
    print("|---|---|---|---|---|---|")
    last = None
    for seg in sizes:
        env = dict(os.environ, CSG_RUN="die", CSG_SEGMENTS=str(seg), CSG_REPS="1", RAYON_NUM_THREADS="1",
                   OPENBLAS_NUM_THREADS="1")
        ours = callgrind_count([binary], env, toggle="*Csg::evaluate_here")
        peer_cmd = lambda reps: [sys.executable, __file__, "--peer", "die", str(seg), str(reps)]
        theirs = callgrind_count(peer_cmd(1), env) - callgrind_count(peer_cmd(0), env)
        growth = f"| {ours / last[0]:.2f} | {theirs / last[1]:.2f} |" if last else "| | |"
        print(f"| {seg} | {ours / 1e9:.3f} | {theirs / 1e9:.3f} | {ours / theirs:.2f} {growth}", flush=True)
        last = (ours, theirs)


def load_average():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--peer":
        peer(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True, help="the csg bench binary (target/release/deps/csg-*)")
    ap.add_argument("--sizes", default="32,64,128,256")
    ap.add_argument("--stress", action="store_true", help="also the ~1M-triangle stress case")
    ap.add_argument("--plates", default="", help="also the perforated plate, n x n holes for each n given (10,20,40)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--no-perf", action="store_true")
    ap.add_argument("--instructions", action="store_true",
                    help="count the die's instructions with valgrind's callgrind instead of timing it")
    a = ap.parse_args()
    if a.instructions:
        instructions(a.bin, [int(s) for s in a.sizes.split(",") if s])
        return
    use_perf = not a.no_perf and perf_works()
    cases = [("die", int(s)) for s in a.sizes.split(",") if s]
    if a.stress:
        cases.append(("stress", 56))
    cases += [("plate", int(n)) for n in a.plates.split(",") if n]
    results = {c: ([], []) for c in cases}
    print(f"load average before: {load_average()}", flush=True)
    for rnd in range(a.rounds):
        for case in cases:
            kind, seg = case
            env = dict(os.environ, CSG_RUN=kind, CSG_SEGMENTS=str(seg), CSG_REPS=str(a.reps))
            ours = lambda: measured([a.bin], env, use_perf)
            theirs = lambda: measured([sys.executable, __file__, "--peer", kind, str(seg), str(a.reps)], env, use_perf)
            if rnd % 2 == 0:
                o, t = ours(), theirs()
            else:
                t, o = theirs(), ours()
            results[case][0].append(o)
            results[case][1].append(t)
    print(f"load average after: {load_average()}", flush=True)

    def med(rows, key):
        vals = [float(r[key]) for r in rows if key in r]
        return statistics.median(vals) if vals else float("nan")

    keys = [("bool_med_s", "time"), ("user_s", "user"), ("sys_s", "sys"), ("peak_delta_mib", "peak"),
            ("ginstr_user", "instr u"), ("ginstr_kernel", "instr k")]
    print()
    print("| case | segments | triangles (ours / theirs) | ours time s | manifold3d s | time ratio | user ratio "
          "| sys ratio | ours peak MiB | manifold3d MiB | memory ratio | instr ratio (user, whole process) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for case in cases:
        o, t = results[case]
        ratio = {k: med(o, k) / med(t, k) if med(t, k) else float("nan") for k, _ in keys}
        print(f"| {case[0]} | {case[1]} | {o[-1]['tris']} / {t[-1]['tris']} | {med(o, 'bool_med_s'):.4f} | "
              f"{med(t, 'bool_med_s'):.4f} | {ratio['bool_med_s']:.2f} | {ratio['user_s']:.2f} | {ratio['sys_s']:.2f} | "
              f"{med(o, 'peak_delta_mib'):.1f} | {med(t, 'peak_delta_mib'):.1f} | {ratio['peak_delta_mib']:.2f} | "
              f"{ratio['ginstr_user']:.2f} |")

    # Growth from one size to the next: the time of the larger over the smaller, each side, per round (the
    # sizes of one round run minutes apart at most, so a round's pair shares the machine's speed), then
    # the median over the rounds; ours grows no faster than theirs where `ours / theirs` is <= 1.
    for kind in ("die", "plate"):
        growth(kind, [c for c in cases if c[0] == kind], results)


def growth(kind, sized, results):
    """The growth tables of one kind of case (the die's sizes, or the plate's)."""
    if len(sized) > 1:
        print()
        print(f"| {kind} size | result triangles | ours growth | manifold3d growth | ours / theirs "
              "| rounds where ours grows no faster |")
        print("|---|---|---|---|---|---|")
        for small, large in zip(sized, sized[1:]):
            grow = [
                [float(b["bool_med_s"]) / float(l["bool_med_s"]) for l, b in zip(results[small][side], results[large][side])]
                for side in (0, 1)
            ]
            ours_g, theirs_g = statistics.median(grow[0]), statistics.median(grow[1])
            no_faster = sum(1 for o, t in zip(grow[0], grow[1]) if o <= t)
            print(f"| {small[1]} -> {large[1]} | {results[small][0][-1]['tris']} -> {results[large][0][-1]['tris']} "
                  f"| {ours_g:.2f} | {theirs_g:.2f} | {ours_g / theirs_g:.2f} | {no_faster} of {len(grow[0])} |")
        cost_per_triangle(sized, results)


def fit_line(xs, ys):
    """The least-squares line y = a x + c through the points: (a, c)."""
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    a = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    return a, my - a * mx


def cost_per_triangle(sized, results):
    """The die's time per result triangle, and the cost of the triangles each step adds, each side.

    A growth ratio mixes a cost per triangle with any fixed cost per boolean: a side with a fixed
    cost per boolean (calls, thread start, conversions) grows less than its triangles at small
    sizes even when each triangle costs it the same. So, per size, the time per triangle; per step, the cost of the triangles added (the time
    the larger size adds over the smaller, per added triangle; per round, then the median); and over
    the whole range, the growth and its exponent, each side."""
    tris = {c: int(results[c][0][-1]["tris"]) for c in sized}
    med_time = {c: [statistics.median(float(r["bool_med_s"]) for r in results[c][side]) for side in (0, 1)]
                for c in sized}
    print()
    print(f"| {sized[0][0]} size | result triangles | ours us / triangle | manifold3d us / triangle | ratio |")
    print("|---|---|---|---|---|")
    for c in sized:
        o, t = (1e6 * med_time[c][side] / tris[c] for side in (0, 1))
        print(f"| {c[1]} | {tris[c]} | {o:.3f} | {t:.3f} | {o / t:.2f} |")
    print()
    print(f"| {sized[0][0]} size | triangles added | ours us / added triangle | manifold3d us / added triangle | ratio "
          "| rounds where ours is no dearer |")
    print("|---|---|---|---|---|---|")
    for small, large in zip(sized, sized[1:]):
        added = tris[large] - tris[small]
        marginal = [
            [1e6 * (float(l["bool_med_s"]) - float(s["bool_med_s"])) / added
             for s, l in zip(results[small][side], results[large][side])]
            for side in (0, 1)
        ]
        o, t = statistics.median(marginal[0]), statistics.median(marginal[1])
        no_dearer = sum(1 for a, b in zip(*marginal) if a <= b)
        print(f"| {small[1]} -> {large[1]} | {added} | {o:.3f} | {t:.3f} | {o / t:.2f} "
              f"| {no_dearer} of {len(marginal[0])} |")
    if len(sized) > 2:
        # Over the whole range: the exponent k of time ~ triangles^k, a least-squares line through
        # the sizes in log-log, per round (one round's sizes share the machine's speed), then the
        # median; k = 1 is linear.
        xs = [math.log(tris[c]) for c in sized]
        rounds = range(len(results[sized[0]][0]))
        time = lambda c, side, r: float(results[c][side][r]["bool_med_s"])
        k = [[fit_line(xs, [math.log(time(c, side, r)) for c in sized])[0] for r in rounds] for side in (0, 1)]
        whole = [statistics.median(time(sized[-1], side, r) / time(sized[0], side, r) for r in rounds) for side in (0, 1)]
        no_faster = sum(1 for a, b in zip(*k) if a <= b)
        print()
        print(f"| {sized[0][0]}, {sized[0][1]} -> {sized[-1][1]} | growth | exponent k (time ~ triangles^k) "
              f"| rounds where ours grows no faster |")
        print("|---|---|---|---|")
        print(f"| ours | {whole[0]:.1f} | {statistics.median(k[0]):.3f} | {no_faster} of {len(k[0])} |")
        print(f"| manifold3d | {whole[1]:.1f} | {statistics.median(k[1]):.3f} | |")
        print(f"| triangles | {tris[sized[-1]] / tris[sized[0]]:.1f} | 1 | |")


if __name__ == "__main__":
    main()
