#!/usr/bin/env python3
"""How soon `--timeout` stops long kernel work: for each operation, a recipe whose setup runs
first and whose one long call the deadline lands in; prints the operation's whole time and how
long after the deadline the stop's message came and the process ended (the stop latency the
README's Limits section promises).

    cargo build --release --bin blocksmith
    python3 tests/data/limits/stop_latency.py [path/to/blocksmith]
    ONLY=save python3 tests/data/limits/stop_latency.py    # the operations whose name has "save"

Each recipe is first run without a deadline (setup alone, then setup and the call, each cut at
30 s) to time it; the deadline is then set 40 % into the call (1 s into a call cut at 30 s). Start-up is measured once with an empty recipe
and taken off. Times are wall-clock seconds, best of two runs untimed and three with the deadline.
A deadline that falls in the setup (a busy machine) is moved later, one that falls after the
call earlier. A row "finished first" means the deadline still fell after the call; run again.
"""

import math
import os
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
BIN = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "target", "release", "blocksmith")

# (name, setup, call): the call is the one long kernel operation under test.
CASES = [
    ("icosphere(1, 9)", "", "let m = icosphere(1, 9);"),
    ("uv_sphere(1, 3000, 3000)", "", "let m = uv_sphere(1, 3000, 3000);"),
    ("torus(2, 1, 3000, 3000)", "", "let m = torus(2, 1, 3000, 3000);"),
    ("polar_sphere(1, 3000, 3000)", "", "let p = polar_sphere(1, 3000, 3000);"),
    ("catmull_clark, 6.3M faces", "let c = cube(1);", "let m = c.catmull_clark(10);"),
    ("loop_subdivide, 5.2M faces", "let c = icosphere(1, 4);", "let m = c.loop_subdivide(5);"),
    ("catmull_clark_limit", "let c = cube(1).catmull_clark(9);", "let m = c.catmull_clark_limit();"),
    ("loop_limit", "let c = icosphere(1, 8);", "let m = c.loop_limit();"),
    ("triangulate, 1.6M quads", "let c = cube(1).catmull_clark(9);", "let m = c.triangulate();"),
    ("normals, 1.6M quads", "let c = cube(1).catmull_clark(9);", "let n = c.normals();"),
    ("volume, 5.2M triangles", "let c = icosphere(1, 9);", "let v = c.volume();"),
    ("boolean, 2 x 1.3M triangles",
     "let a = icosphere(1, 8); let b = a.translate([0.3, 0.2, 0.1]);", "let m = a - b;"),
    ("block meshing (tolerance 1e-12)",
     "let b = blocks(); b.add(block([-1, -1, -1], [1, 1, 1]));",
     "let m = b.mesh(#{ tolerance: 1e-12, max_depth: 14 });"),
    ("marching cubes, 512^3",
     "let v = voxels(512); v.fill_sphere([256, 256, 256], 250.0);", "let m = v.to_mesh();"),
    ("voxel fill_sphere, 512^3", "let v = voxels(512);", "v.fill_sphere([256, 256, 256], 250.0);"),
    ("polar to_mesh, 3000 x 3000", "let p = polar_sphere(1, 3000, 3000);", "let m = p.to_mesh();"),
    ("polar skeleton, 3000 x 3000", "let p = polar_sphere(1, 3000, 3000);", "let s = p.skeleton();"),
    ("save .glb, 5.2M triangles", "let c = icosphere(1, 9);", "c.save(\"{dir}/big.glb\");"),
    ("save .stl, 5.2M triangles", "let c = icosphere(1, 9);", "c.save(\"{dir}/big.stl\");"),
    ("save .3mf, 1.3M triangles", "let c = icosphere(1, 8);", "c.save(\"{dir}/big.3mf\");"),
    ("save .gltf, 5.2M triangles", "let c = icosphere(1, 9);", "c.save(\"{dir}/big.gltf\");"),
    ("polar check, 3000 x 3000", "let p = polar_sphere(1, 3000, 3000);", "p.check();"),
    ("voxelize, 512^3", "let m = icosphere(1, 7);", "let v = voxelize(m, 512);"),
    ("load .stl, 5.2M triangles", "", "let m = load(\"{dir}/big.stl\");"),
    # Small files at their worst (issue 33), written by `write_worst_files`.
    ("load .stl, 300k corners in one cell", "", "let m = load(\"{dir}/crowded.stl\");"),
    ("load .3mf, DAG 10 wide 6 deep", "", "let m = load(\"{dir}/dag.3mf\");"),
    ("load .glb, 400,000 instances", "", "let m = load(\"{dir}/instances.glb\");"),
    ("save .stl, two 20,000-gons", "let m = load(\"{dir}/disk.obj\");", "m.save(\"{dir}/disk.stl\");"),
]


def write_worst_files(dir):
    """The worst inputs of the readers and the weld (issue 33): an STL of 100,000 triangles
    whose 300,000 corners lie within 180 weld tolerances of the origin, none within one
    tolerance of another, beside one far triangle (all in one cell of the old weld grid); a
    1 KB 3MF whose components form a DAG 10 wide and 6 deep (10^6 tetrahedra); a GLB of one
    triangle instanced by 400,000 nodes; an OBJ of two 20,000-corner faces (a star and its
    reverse, whose triangulation takes the fallback)."""
    tol = 1e-8 * math.sqrt(3.0)
    s = 1.25 * tol
    tris = []
    n = 47
    for i in range(100_000):
        b = (3 * s * (i % n), 3 * s * (i // n % n), 3 * s * (i // (n * n)))
        tris.append((b, (b[0] + s, b[1], b[2]), (b[0], b[1] + s, b[2])))
    tris.append(((1.0, 1.0, 1.0), (1.0, 0.9, 1.0), (0.9, 1.0, 1.0)))
    with open(os.path.join(dir, "crowded.stl"), "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<12fH", 0, 0, 1, *t[0], *t[1], *t[2], 0))

    core = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
    objs = ['<object id="0" type="model"><mesh><vertices><vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/>'
            '<vertex x="0" y="1" z="0"/><vertex x="0" y="0" z="1"/></vertices><triangles>'
            '<triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/><triangle v1="0" v2="3" v3="2"/>'
            '<triangle v1="1" v2="2" v3="3"/></triangles></mesh></object>']
    for k in range(1, 7):
        comps = "".join(f'<component objectid="{k - 1}" transform="1 0 0 0 1 0 0 0 1 {2 * j} 0 {k}"/>'
                        for j in range(10))
        objs.append(f'<object id="{k}" type="model"><components>{comps}</components></object>')
    model = (f'<?xml version="1.0"?><model unit="millimeter" xmlns="{core}"><resources>{"".join(objs)}'
             '</resources><build><item objectid="6"/></build></model>')
    with zipfile.ZipFile(os.path.join(dir, "dag.3mf"), "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("3D/3dmodel.model", model)

    nodes = ",".join(f'{{"mesh":0,"translation":[{2 * i},0,0]}}' for i in range(400_000))
    gltf = ('{"asset":{"version":"2.0"},"buffers":[{"byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],'
            '"accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3,"min":[0,0,0],"max":[1,1,0]}],'
            '"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],'
            f'"nodes":[{nodes}],"scenes":[{{"nodes":[{",".join(str(i) for i in range(400_000))}]}}],"scene":0}}')
    j = gltf.encode()
    j += b" " * (-len(j) % 4)
    b = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    b += b"\0" * (-len(b) % 4)
    with open(os.path.join(dir, "instances.glb"), "wb") as f:
        f.write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(j) + 8 + len(b)))
        f.write(struct.pack("<I", len(j)) + b"JSON" + j + struct.pack("<I", len(b)) + b"BIN\0" + b)

    k = 20_000
    with open(os.path.join(dir, "disk.obj"), "w") as f:
        for i in range(k):
            a, r = i * 2 * math.pi / k, (1.0 if i % 2 == 0 else 0.8)
            f.write(f"v {r * math.cos(a)} {r * math.sin(a)} 0\n")
        f.write("f " + " ".join(str(i) for i in range(1, k + 1)) + "\n")
        f.write("f 1 " + " ".join(str(i) for i in range(k, 1, -1)) + "\n")


CAP = 30.0  # seconds an untimed run may take (block meshing at 1e-12 would take minutes)


def run(recipe, dir, timeout=None):
    """Best wall time of the recipe (two runs untimed, three with the deadline), with the last
    run's outcome; with a deadline, also the best time to the first line of its message."""
    path = os.path.join(dir, "r.rhai")
    with open(path, "w") as f:
        f.write(recipe.replace("{dir}", dir))
    args = [BIN, "run", path]
    if timeout is not None:
        args += ["--timeout", f"{timeout:.3f}"]
    best = best_message = None
    out = None
    for _ in range(3 if timeout is not None else 2):
        start = time.perf_counter()
        p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        # A run still going at CAP is killed (its stderr then ends, so the reads return).
        watchdog = threading.Timer(CAP, p.kill)
        watchdog.start()
        first = p.stderr.readline()
        message = time.perf_counter() - start
        rest = p.stderr.read()
        code = p.wait()
        watchdog.cancel()
        t = time.perf_counter() - start
        if t >= CAP:
            return CAP, None, None
        out = (code, first + rest)
        best = t if best is None else min(best, t)
        if first:
            best_message = message if best_message is None else min(best_message, message)
    return best, best_message, out


def main():
    with tempfile.TemporaryDirectory() as dir:
        startup, _, _ = run("", dir)
        # The files the load cases read.
        run("icosphere(1, 9).save(\"{dir}/big.stl\");", dir)
        write_worst_files(dir)
        print(f"start-up {startup * 1000:.0f} ms; deadline 40 % into each call")
        print(f"{'operation':34} {'call s':>8} {'message ms':>11} {'exit ms':>8}  message")
        only = os.environ.get("ONLY", "")
        for name, setup, call in CASES:
            if only not in name:
                continue
            t_setup, _, _ = run(setup, dir)
            t_all, _, out = run(setup + "\n" + call, dir)
            if out is not None and out[0] != 0:
                print(f"{name:34} failed without a deadline: {out[1].strip()[:100]}")
                continue
            t_call = max(t_all - t_setup, 0.0) if t_all < CAP else 2.5
            deadline = max(t_setup - startup + 0.4 * t_call, 0.05)
            # The setup's time varies on a busy machine: a deadline that falls in the setup
            # (line 1; the call is line 2) is moved later, one that falls after the call (the
            # run finishes) earlier, up to three times.
            for _ in range(4):
                t_stopped, t_message, out = run(setup + "\n" + call, dir, deadline)
                if out is None:
                    break
                if out[0] == 0:
                    deadline = max(deadline - 0.15 * t_call - 0.05, 0.05)
                elif ":1:" in out[1].splitlines()[0]:
                    deadline += 0.1 * t_call + 0.05
                else:
                    break
            late = t_stopped - startup - deadline
            if out is None:
                msg, shown = "(not stopped)", "-"
            elif out[0] != 0:
                msg = out[1].strip().splitlines()[0].split("error: ")[-1][:60]
                shown = f"{(t_message - startup - deadline) * 1000:.0f}"
            else:
                msg, shown = "(finished first)", "-"
            call = f"{t_call:8.2f}" if t_all < CAP else f"{'>' + str(int(CAP)):>8}"
            print(f"{name:34} {call} {shown:>11} {late * 1000:8.0f}  {msg}")


if __name__ == "__main__":
    main()
