"""The mesh_core bench's work done in trimesh, on the very files the bench leaves in
target/bench-data/ (run `cargo bench -p blocksmith-kernel --bench mesh_core` first).

    /tmp/venv/bin/python tests/data/bench_trimesh.py            # timings, medians of 5 runs
    /tmp/venv/bin/python tests/data/bench_trimesh.py --only STEP MESH   # one step, 5 runs
    /usr/bin/time -v /tmp/venv/bin/python tests/data/bench_trimesh.py --peak STEP MESH

STEP: build, measures, write-glb, write-obj, read-glb, read-obj (as kernel/examples/
mesh_core_peak.rs); MESH: quads (1M quads; trimesh splits each into 2 triangles) or tris (1M
triangles). Prints `TRIMESH_BENCH mesh=… step=… median_s=… min_s=… faces_per_s=…` lines, where
faces counts the input faces (1M) as in the Rust bench.

What each step does in trimesh:
  build      Trimesh(vertices, faces, process=False), then is_watertight so that the edge
             structure is built (the constructor alone is lazy; blocksmith's from_indexed builds
             the half-edges and checks manifoldness at once)
  measures   volume, area, is_watertight, euler_number, body_count (genus), bounds, with the
             cache cleared first
  write-*    mesh.export(path) to a temporary file
  read-*     trimesh.load(path, process=False, force="mesh")
"""
import os
import statistics
import sys
import tempfile
import time

import numpy as np
import trimesh

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "target", "bench-data")
FILES = {"quads": "quads_1m", "tris": "tris_1m"}
FACES = 1_000_000


def arrays(which):
    """Vertices and faces (quads or triangles) of the bench's torus grid, as blocksmith makes them."""
    n, m = (1000, 1000) if which == "quads" else (1000, 500)
    u = np.repeat(np.arange(n) * (2 * np.pi / n), m)
    v = np.tile(np.arange(m) * (2 * np.pi / m), n)
    r = 2.0 + 0.5 * np.cos(v)
    verts = np.column_stack([r * np.cos(u), r * np.sin(u), 0.5 * np.sin(v)])
    i, j = np.repeat(np.arange(n), m), np.tile(np.arange(m), n)
    vid = lambda a, b: (a % n) * m + b % m
    q = np.column_stack([vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)])
    if which == "quads":
        return verts, q
    return verts, np.column_stack([q[:, 0], q[:, 1], q[:, 2], q[:, 0], q[:, 2], q[:, 3]]).reshape(-1, 3)


def make_step(step, which):
    """A function doing the step once, and a function preparing its input (not timed)."""
    path = lambda ext: os.path.join(DATA, FILES[which] + "." + ext)
    if step == "build":
        verts, faces = arrays(which)

        def run(_):
            m = trimesh.Trimesh(vertices=verts, faces=faces, process=False)
            assert m.is_watertight
            return m

        return run, lambda: None
    if step == "measures":
        verts, faces = arrays(which)
        mesh = trimesh.Trimesh(vertices=verts, faces=faces, process=False)

        def prep():
            mesh._cache.clear()
            return mesh

        def run(m):
            out = (m.volume, m.area, m.is_watertight, m.euler_number, m.body_count, m.bounds)
            assert out[2] and out[3] == 0
            return out

        return run, prep
    if step.startswith("write-"):
        ext = step[6:]
        mesh = trimesh.load(path("glb"), process=False, force="mesh")
        out = os.path.join(tempfile.gettempdir(), "bench_trimesh." + ext)
        return (lambda _: mesh.export(out)), lambda: None
    if step.startswith("read-"):
        ext = step[5:]
        return (lambda _: trimesh.load(path(ext), process=False, force="mesh")), lambda: None
    raise SystemExit("unknown step %r" % step)


STEPS = ["build", "measures", "write-glb", "write-obj", "read-glb", "read-obj"]

if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--peak":
        run, prep = make_step(sys.argv[2], sys.argv[3])
        t = time.perf_counter()
        run(prep())
        print("TRIMESH_PEAK step=%s mesh=%s seconds=%.3f" % (sys.argv[2], sys.argv[3], time.perf_counter() - t))
        sys.exit(0)
    print("trimesh", trimesh.__version__, "numpy", np.__version__)
    only = sys.argv[2:4] if len(sys.argv) == 4 and sys.argv[1] == "--only" else None
    for which in ["quads", "tris"]:
        for step in STEPS:
            if only and [step, which] != only:
                continue
            run, prep = make_step(step, which)
            times = []
            for _ in range(5):
                x = prep()
                t = time.perf_counter()
                run(x)
                times.append(time.perf_counter() - t)
            med = statistics.median(times)
            print(
                "TRIMESH_BENCH mesh=%s step=%s median_s=%.4f min_s=%.4f faces_per_s=%.3g"
                % (which, step, med, min(times), FACES / med)
            )
            sys.stdout.flush()
