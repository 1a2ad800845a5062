#!/usr/bin/env python3
"""Loading public mesh files, blocksmith against trimesh (issue 34): no refusal of a file
trimesh loads; after repair, positions identical to the file's, and triangles, components,
boundary edges and the Euler characteristic (V - E + F) compared with trimesh's.

For each mesh file (.stl .obj .glb .gltf .ply .3mf) under DIR, ours is
`blocksmith run load.rhai --set path=FILE -o OUT.obj --stats json` (the loaded mesh, written
with exact positions and read back, and its facts and diagnosis; the load's repair warnings come
on standard error), theirs is `trimesh.load(FILE, force="mesh")` then `merge_vertices(merge_tex=True,
merge_norm=True)` (vertices at equal positions joined across UV and normal seams, as our weld
joins them). Positions: every position of ours is one of the file's (trimesh's
unprocessed vertices; glTF's Y-up turned to our Z-up: (x, y, z) -> (x, -z, y)), else the largest
distance to the nearest, relative to the model's size (the weld joins corners within 1e-8 of the
bounding-box diagonal, keeping one of their positions). Differences are expected where our
repair splits a non-manifold vertex or edge (trimesh keeps it: its Euler characteristic and
components differ by what was split) and are listed with the repair.

  ~/.cache/blocksmith-peers/venv/bin/python tests/data/compare_loads_trimesh.py \\
      --bin target/debug/blocksmith DIR [FILE ...]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import trimesh

RECIPE = 'load(param("path", "", #{ doc: "the mesh file" }))\n'
EXTS = (".stl", ".obj", ".glb", ".gltf", ".ply", ".3mf")


def ours(binary, path, tmp):
    recipe = os.path.join(tmp, "load.rhai")
    with open(recipe, "w") as f:
        f.write(RECIPE)
    out = os.path.join(tmp, "out.obj")
    r = subprocess.run([binary, "run", recipe, "--set", f"path={os.path.abspath(path)}", "-o", out,
                        "--allow-read", os.path.dirname(os.path.abspath(path)),
                        "--stats", "json"], capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        return None, [l for l in r.stderr.splitlines() if "error" in l][:1] or ["failed"]
    stats = json.loads(r.stdout)
    v = []
    with open(out) as f:
        for line in f:
            if line.startswith("v "):
                v.append(tuple(float(x) for x in line.split()[1:4]))
    warnings = [l for l in r.stderr.splitlines() if "warning:" in l]
    return (stats, set(v)), warnings


def theirs(path):
    """trimesh's counts twice: as loaded (vertices merged at equal positions, UV and normal seams
    kept apart) and with the seams joined too; ours agree when they equal either."""
    m = trimesh.load(path, force="mesh")
    if m.is_empty:
        return None
    as_loaded = counts(m, path)
    # The file's own positions: unprocessed, every vertex.
    raw = trimesh.load(path, force="mesh", process=False)
    vs = np.asarray(raw.vertices, dtype=float)
    if path.lower().endswith((".glb", ".gltf")):
        vs = np.column_stack([vs[:, 0], -vs[:, 2], vs[:, 1]])
    as_loaded["positions"] = set(map(tuple, vs.tolist()))
    m.merge_vertices(merge_tex=True, merge_norm=True)
    return [as_loaded, counts(m, path)]


def counts(m, path):
    edges = m.edges_sorted
    _, counts = np.unique(edges, axis=0, return_counts=True)
    parts = trimesh.graph.connected_components(m.face_adjacency, nodes=np.arange(len(m.faces)), min_len=1)
    vs = m.vertices[np.unique(m.faces)]
    if path.lower().endswith((".glb", ".gltf")):
        vs = np.column_stack([vs[:, 0], -vs[:, 2], vs[:, 1]])
    return {
        "triangles": len(m.faces), "components": len(parts), "boundary_edges": int((counts == 1).sum()),
        "euler": int(m.euler_number), "positions": set(map(tuple, vs.astype(float).tolist())),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="target/debug/blocksmith")
    ap.add_argument("paths", nargs="+")
    a = ap.parse_args()
    files = []
    for p in a.paths:
        if os.path.isdir(p):
            files += sorted(os.path.join(p, f) for f in os.listdir(p) if f.lower().endswith(EXTS))
        else:
            files.append(p)
    tally = {"files": 0, "trimesh_loads": 0, "we_refuse": 0, "same_positions": 0, "all_counts_agree": 0, "repaired": 0}
    print(f"{'file':<36} {'tri ours/tm':>15} {'comp':>7} {'bnd edges':>11} {'euler':>11} pos  repair")
    for path in files:
        tally["files"] += 1
        try:
            t = theirs(path)
        except Exception as e:  # noqa: BLE001 - a file trimesh cannot read is not compared
            t = None
        if t is None:
            continue
        tally["trimesh_loads"] += 1
        with tempfile.TemporaryDirectory() as tmp:
            o, warnings = ours(a.bin, path, tmp)
        name = os.path.basename(path)
        if o is None:
            tally["we_refuse"] += 1
            print(f"{name:<36} REFUSED: {warnings[0] if warnings else ''}")
            continue
        stats, pos = o
        d = stats["diagnosis"]
        mine = {"triangles": stats["triangles"], "components": d["component_count"],
                "boundary_edges": d["boundary_edges"], "euler": stats["vertices"] - stats["edges"] + stats["faces"]}
        same = pos <= t[0]["positions"]
        tally["same_positions"] += same
        if not same:
            theirs_pos = np.array(sorted(t[0]["positions"]))
            ours_pos = np.array(sorted(pos))
            tree = trimesh.proximity.cKDTree(theirs_pos) if hasattr(trimesh.proximity, "cKDTree") else None
            if tree is None:
                from scipy.spatial import cKDTree
                tree = cKDTree(theirs_pos)
            dist, _ = tree.query(ours_pos)
            scale = float(np.abs(theirs_pos).max()) or 1.0
            same = f"max {dist.max() / scale:.1e}"
            tally["max_relative_position_difference"] = max(tally.get("max_relative_position_difference", 0), dist.max() / scale)
        agreeing = [x for x in t if all(mine[k] == x[k] for k in mine)]
        agree = bool(agreeing)
        t = agreeing[0] if agreeing else t[0]
        tally["all_counts_agree"] += agree
        tally["repaired"] += bool(warnings)
        cell = lambda k: f"{mine[k]}/{t[k]}" + ("" if mine[k] == t[k] else "*")
        rep = "; ".join(w.split("warning: ", 1)[1][:90] for w in warnings)
        print(f"{name:<36} {cell('triangles'):>15} {cell('components'):>7} {cell('boundary_edges'):>11} "
              f"{cell('euler'):>11} {'=' if same is True else same}  {rep}")
    print(json.dumps(tally))


if __name__ == "__main__":
    sys.exit(main())
