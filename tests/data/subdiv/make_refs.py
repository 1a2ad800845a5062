#!/usr/bin/env python3
"""Regenerates the subdivision reference files in this folder (see README.md).

Sources:
  - OpenSubdiv 3.5 (Debian's libosd-dev), through osd_ref.cpp, in double precision: Catmull-Clark
    and Loop levels 1-3 with infinitely sharp creases and corners, and limit positions/normals
    (Far::PrimvarRefiner::Limit);
  - Blender's subdivision modifier (bpy 5.0.1 = OpenSubdiv, float32 vertex storage): Catmull-Clark
    limit surface (use_limit_surface, quality 10) and levels 1-3 (checked against OpenSubdiv here);
  - pymeshlab and trimesh: Loop levels 1-3 with Loop's original weights (stored: pymeshlab, which
    matches OpenSubdiv to 1e-15; trimesh matches on closed meshes but not on boundaries).

Run with the peers' Python (bash ../shared/peers/install.sh first; libosd-dev and g++ installed):
  ~/.cache/blocksmith-peers/venv/bin/python tests/data/subdiv/make_refs.py
"""
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
PEERS = os.environ.get("PEERS_HOME", os.path.expanduser("~/.cache/blocksmith-peers"))
BPY_PY = os.path.join(PEERS, "venv-bpy", "bin", "python")


# ----------------------------------------------------------------------------- meshes
def cube():
    v = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
    f = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return dict(v=[tuple(map(float, p)) for p in v], f=f, creases=[], corners=[])


def cube_crease():
    m = cube()
    m["creases"] = [(4, 5), (5, 6), (6, 7), (7, 4)]  # the +z face's four edges: one crease loop
    return m


def torus(n=6, m=4, R=2.0, r=0.7):
    v = []
    for i in range(n):
        a = 2 * math.pi * i / n
        for j in range(m):
            b = 2 * math.pi * j / m
            v.append(((R + r * math.cos(b)) * math.cos(a), (R + r * math.cos(b)) * math.sin(a), r * math.sin(b)))
    idx = lambda i, j: (i % n) * m + j % m
    f = [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)) for i in range(n) for j in range(m)]
    return v, f


def torus_mixed():
    """6x4 torus; faces 0 and 4 (sharing an edge) merged into a hexagon (two valence-3 vertices),
    face 13 split into two triangles (two valence-5 vertices)."""
    v, f = torus()
    a, b = f[0], f[4]
    hexagon = (a[0], a[1], b[1], b[2], b[3], a[3])
    q = f[13]
    faces = []
    for i, face in enumerate(f):
        if i == 0:
            faces.append(hexagon)
        elif i == 4:
            continue
        elif i == 13:
            faces += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
        else:
            faces.append(face)
    return dict(v=v, f=faces, creases=[], corners=[])


def grid(n=3, tri=False):
    w = n + 1
    v = [(float(i % w), float(i // w), 0.1 * (i % w) * (i // w) - 0.05 * (i % w) ** 2) for i in range(w * w)]
    f = []
    for j in range(n):
        for i in range(n):
            a = i + w * j
            if tri:
                if (i + j) % 2 == 0:
                    f += [(a, a + 1, a + 1 + w), (a, a + 1 + w, a + w)]
                else:
                    f += [(a, a + 1, a + w), (a + 1, a + 1 + w, a + w)]
            else:
                f.append((a, a + 1, a + 1 + w, a + w))
    return dict(v=v, f=f, creases=[], corners=[])


def icosahedron():
    import trimesh
    t = trimesh.creation.icosphere(subdivisions=0)
    return dict(v=[tuple(map(float, p)) for p in t.vertices], f=[tuple(map(int, x)) for x in t.faces], creases=[], corners=[])


def torus_tri():
    v, f = torus()
    faces = []
    for k, q in enumerate(f):
        if k % 2 == 0:
            faces += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
        else:
            faces += [(q[0], q[1], q[3]), (q[1], q[2], q[3])]
    return dict(v=v, f=faces, creases=[], corners=[])


def octahedron_crease():
    v = [(1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    f = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4), (1, 0, 5), (2, 1, 5), (3, 2, 5), (0, 3, 5)]
    return dict(v=[tuple(map(float, p)) for p in v], f=f, creases=[(0, 1), (1, 2), (2, 3), (3, 0)], corners=[5])


# ----------------------------------------------------------------------------- OpenSubdiv
def osd_binary():
    exe = os.path.join(tempfile.gettempdir(), "blocksmith_osd_ref")
    subprocess.run(["g++", "-O2", "-o", exe, os.path.join(HERE, "osd_ref.cpp"), "-losdCPU"], check=True)
    return exe


def run_osd(exe, mesh, scheme, levels, limit_level):
    lines = [f"scheme {scheme}", f"levels {levels}", f"limit_level {limit_level}"]
    lines += ["v %.17g %.17g %.17g" % p for p in mesh["v"]]
    lines += ["f %d %s" % (len(f), " ".join(map(str, f))) for f in mesh["f"]]
    lines += ["crease %d %d" % c for c in mesh["creases"]]
    lines += ["corner %d" % c for c in mesh["corners"]]
    out = subprocess.run([exe], input="\n".join(lines + ["end"]) + "\n", capture_output=True, text=True, check=True).stdout
    res = {"levels": {}, "limit": None}
    cur = None
    for line in out.splitlines():
        p = line.split()
        if p[0] == "level":
            cur = res["levels"].setdefault(int(p[1]), {"V": int(p[2]), "F": int(p[3]), "p": []})["p"]
        elif p[0] == "limit":
            res["limit"] = {"level": int(p[1]), "p": [], "n": []}
            cur = None
        elif p[0] == "p":
            xyz = tuple(float(x) for x in p[1:4])
            if cur is not None:
                cur.append(xyz)
            else:
                res["limit"]["p"].append(xyz)
                res["limit"]["n"].append(tuple(float(x) for x in p[5:8]))
    return res


# ----------------------------------------------------------------------------- bpy
BPY_WORKER = r"""
import bpy, json, sys
import numpy as np
spec = json.loads(sys.stdin.read())
bpy.ops.wm.read_factory_settings(use_empty=True)
out = {}
for name, m in spec.items():
    me = bpy.data.meshes.new(name)
    me.from_pydata(m["v"], [], m["f"])
    me.update()
    if m["creases"]:
        att = me.attributes.new("crease_edge", "FLOAT", "EDGE")
        want = {tuple(sorted(c)) for c in m["creases"]}
        for e in me.edges:
            att.data[e.index].value = 1.0 if tuple(sorted(e.vertices)) in want else 0.0
    res = {}
    for level, limit in [(1, False), (2, False), (3, False), (2, True)]:
        ob = bpy.data.objects.new("o", me)
        bpy.context.scene.collection.objects.link(ob)
        mod = ob.modifiers.new("ss", "SUBSURF")
        mod.levels = level
        mod.render_levels = level
        mod.use_limit_surface = limit
        mod.quality = 10
        dg = bpy.context.evaluated_depsgraph_get()
        ev = ob.evaluated_get(dg)
        em = ev.to_mesh()
        co = np.empty(len(em.vertices) * 3)
        em.vertices.foreach_get("co", co)
        res[("limit" if limit else "level") + str(level)] = dict(V=len(em.vertices), F=len(em.polygons), p=co.reshape(-1, 3).tolist())
        ev.to_mesh_clear()
        bpy.data.objects.remove(ob)
    out[name] = res
print("BPYJSON " + json.dumps(out))
"""


def run_bpy(meshes):
    pr = subprocess.run([BPY_PY, "-c", BPY_WORKER], input=json.dumps(meshes), capture_output=True, text=True)
    for line in pr.stdout.splitlines():
        if line.startswith("BPYJSON "):
            return json.loads(line[len("BPYJSON "):])
    raise RuntimeError("bpy failed: " + pr.stderr[-2000:])


# ----------------------------------------------------------------------------- comparisons
def max_nn(a, b):
    from scipy.spatial import cKDTree
    import numpy as np
    a, b = np.asarray(a, float), np.asarray(b, float)
    if len(a) != len(b):
        return float("inf")
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))


# ----------------------------------------------------------------------------- output
def write(path, header, mesh, sections):
    with open(path, "w") as fh:
        for h in header:
            fh.write("# " + h + "\n")
        fh.write("input %d %d\n" % (len(mesh["v"]), len(mesh["f"])))
        for p in mesh["v"]:
            fh.write("v %.17g %.17g %.17g\n" % p)
        for f in mesh["f"]:
            fh.write("f " + " ".join(map(str, f)) + "\n")
        for c in mesh["creases"]:
            fh.write("crease %d %d\n" % c)
        for c in mesh["corners"]:
            fh.write("corner %d\n" % c)
        for name, level, F, pts, digits in sections:
            fh.write("%s %d %d %d\n" % (name, level, len(pts), F))
            fmt = "p %%.%dg %%.%dg %%.%dg\n" % (digits, digits, digits)
            for p in pts:
                fh.write(fmt % tuple(p))


def main():
    import numpy as np
    import trimesh
    import pymeshlab as ml

    exe = osd_binary()
    report = []
    cc = {"cube": cube(), "cube_crease": cube_crease(), "torus_mixed": torus_mixed(), "grid": grid(3)}
    bpy = run_bpy(cc)
    for name, mesh in cc.items():
        osd = run_osd(exe, mesh, "catmark", 3, 1)
        b = bpy[name]
        for L in (1, 2, 3):
            d = max_nn(osd["levels"][L]["p"], b["level%d" % L]["p"])
            report.append(f"cc {name} L{L}: V={osd['levels'][L]['V']} F={osd['levels'][L]['F']} bpy-vs-osd max {d:.2e}")
        kept = (1, 2, 3)
        sections = [("level", L, osd["levels"][L]["F"], osd["levels"][L]["p"], 13) for L in kept]
        lim = osd["limit"]
        normals = [tuple(np.asarray(n) / (np.linalg.norm(n) or 1.0)) for n in lim["n"]]
        sections.append(("limit", 1, 0, lim["p"], 13))
        sections.append(("limit_normal", 1, 0, normals, 13))
        sections.append(("bpy_limit", 2, b["limit2"]["F"], b["limit2"]["p"], 9))
        write(os.path.join(HERE, f"cc_{name}.txt"),
              [f"Catmull-Clark reference for '{name}' (made by make_refs.py; see README.md).",
               "level L: OpenSubdiv 3.5 uniform refinement, double precision, 13 significant digits.",
               "limit 1 / limit_normal 1: OpenSubdiv PrimvarRefiner::Limit of the level-1 vertices (unit t1 x t2).",
               "bpy_limit 2: Blender 5.0.1 subdivision modifier, use_limit_surface, quality 10, level 2 (float32)."],
              mesh, sections)

    loop = {"icosahedron": icosahedron(), "torus_tri": torus_tri(), "grid_tri": grid(3, tri=True),
            "octahedron_crease": octahedron_crease()}
    for name, mesh in loop.items():
        osd = run_osd(exe, mesh, "loop", 3, 1)
        V = np.asarray(mesh["v"], float)
        F = np.asarray(mesh["f"], np.int64)
        tm = {}
        pm = {}
        if not mesh["creases"]:
            t = trimesh.Trimesh(V, F, process=False)
            for L in (1, 2, 3):
                tm[L] = np.asarray(t.subdivide_loop(iterations=L).vertices)
                ms = ml.MeshSet()
                ms.add_mesh(ml.Mesh(V, F.astype(np.int32)))
                ms.meshing_surface_subdivision_loop(iterations=L, threshold=ml.PercentageValue(0), loopweight="Loop")
                pm[L] = ms.current_mesh().vertex_matrix().copy()
                report.append(f"loop {name} L{L}: V={osd['levels'][L]['V']} trimesh-vs-osd {max_nn(tm[L], osd['levels'][L]['p']):.2e} "
                              f"pymeshlab-vs-osd {max_nn(pm[L], osd['levels'][L]['p']):.2e}")
        # pymeshlab agrees with OpenSubdiv everywhere; trimesh differs on boundaries (see README.md).
        src = "pymeshlab 2025.7 Loop, loopweight=Loop, threshold 0 (double)" if pm else "OpenSubdiv 3.5 Loop (double; the peers have no creases)"
        kept = (1, 2, 3)
        sections = [("level", L, osd["levels"][L]["F"], (pm[L] if pm else osd["levels"][L]["p"]), 13) for L in kept]
        lim = osd["limit"]
        normals = [tuple(np.asarray(n) / (np.linalg.norm(n) or 1.0)) for n in lim["n"]]
        sections.append(("limit", 1, 0, lim["p"], 13))
        sections.append(("limit_normal", 1, 0, normals, 13))
        write(os.path.join(HERE, f"loop_{name}.txt"),
              [f"Loop reference for '{name}' (made by make_refs.py; see README.md).",
               f"level L: {src}, 13 significant digits.",
               "limit 1 / limit_normal 1: OpenSubdiv 3.5 PrimvarRefiner::Limit (Loop) of the level-1 vertices."],
              mesh, sections)
    for r in report:
        print("SUBDIV_REF " + r)


if __name__ == "__main__":
    main()
