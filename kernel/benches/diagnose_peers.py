#!/usr/bin/env python3
"""Diagnosis side by side (issue 34): what `cargo bench -p blocksmith-kernel --bench diagnose`
times, done by trimesh and pymeshlab on the same files (target/bench-data/diagnose_*.ply, which
the bench writes), with the ratios ours / theirs from criterion's estimates
(target/criterion/diagnose_<case>/<function>/new/estimates.json, the median).

  trimesh   components+genus: load(process=False), split(only_watertight=False) and each
            part's euler_number, plus the boundary edges (edges used once) - what our
            `components` + the component/boundary part of `defects` report;
  pymeshlab topology: get_topological_measures (components, boundary edges, genus,
            non-manifold counts); self-intersections: compute_selection_by_self_intersections_per_face
            (faces selected) - what our `self_intersections` reports, and with the topology
            what `defects` reports (pymeshlab draws no handle loops).

Each peer time is the median of --reps runs in this process, the file already loaded. Also
printed: pymeshlab's count of self-intersecting faces, to compare with the faces in our pairs.

  ~/.cache/blocksmith-peers/venv/bin/python kernel/benches/diagnose_peers.py [--reps 5]

With --count FILE.stl ... (and --bin target/debug/blocksmith), it compares counts instead of
times: the distinct faces of our `load(FILE).self_intersections()` pairs against pymeshlab's
self-intersecting faces, on the same triangles (the issue's check on the L-system plants:
`blocksmith run examples/lsystem_tree.rhai -o tree.stl`, then `--count tree.stl`).
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np
import pymeshlab
import trimesh

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def median_time(f, reps):
    times, out = [], None
    for _ in range(reps):
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def ours(case, function):
    p = os.path.join(ROOT, "target", "criterion", f"diagnose_{case}", function, "new", "estimates.json")
    if not os.path.exists(p):
        return None
    with open(p) as f:
        return json.load(f)["median"]["point_estimate"] / 1e9


def trimesh_components(m):
    parts = m.split(only_watertight=False)
    edges = m.edges_sorted
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return [(len(p.faces), p.euler_number) for p in parts], int((counts == 1).sum())


COUNT = """let m = load(param("path", ""));
let faces = #{};
let pairs = m.self_intersections();
for p in pairs { faces[`${p[0]}`] = 1; faces[`${p[1]}`] = 1; }
print(`${m.face_count} ${pairs.len()} ${faces.len()}`);
"""


def counts(binary, paths):
    with tempfile.TemporaryDirectory() as tmp:
        recipe = os.path.join(tmp, "count.rhai")
        with open(recipe, "w") as f:
            f.write(COUNT)
        for path in paths:
            path = os.path.abspath(path)
            r = subprocess.run([binary, "run", recipe, "--set", f"path={path}", "--allow-read", os.path.dirname(path)],
                               capture_output=True, text=True, check=True)
            faces, pairs, crossing = r.stdout.split()
            ms = pymeshlab.MeshSet()
            ms.load_new_mesh(path)
            ms.compute_selection_by_self_intersections_per_face()
            m = ms.current_mesh()
            print(f"{os.path.basename(path)}: ours {crossing} faces in {pairs} pairs of {faces} triangles; "
                  f"pymeshlab {m.selected_face_number()} faces of {m.face_number()}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--bin", default=os.path.join(ROOT, "target", "debug", "blocksmith"))
    ap.add_argument("--count", nargs="+", metavar="FILE")
    args = ap.parse_args()
    if args.count:
        counts(args.bin, args.count)
        return
    rows = []
    for case in ["torus_1m", "two_tori_1m"]:
        path = os.path.join(ROOT, "target", "bench-data", f"diagnose_{case}.ply")
        m = trimesh.load(path, process=False)
        t_tm, (parts, boundary) = median_time(lambda: trimesh_components(m), args.reps)
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(path)
        t_topo, topo = median_time(lambda: ms.get_topological_measures(), args.reps)

        def selfint():
            ms.set_selection_none()
            ms.compute_selection_by_self_intersections_per_face()
            return ms.current_mesh().selected_face_number()

        t_si, si_faces = median_time(selfint, args.reps)
        print(f"{case}: {len(m.faces)} triangles; trimesh: {len(parts)} components "
              f"(faces, euler) {parts}, {boundary} boundary edges; pymeshlab: "
              f"{topo['connected_components_number']} components, genus {topo['genus']}, "
              f"{topo['boundary_edges']} boundary edges, {si_faces} self-intersecting faces")
        rows += [
            (case, "components", ours(case, "components"), "trimesh split+euler+boundary", t_tm),
            (case, "self_intersections", ours(case, "self_intersections"), "pymeshlab self-intersections", t_si),
            (case, "defects", ours(case, "defects"), "pymeshlab topology+self-intersections", t_topo + t_si),
        ]
    print(f"\n{'case':<12} {'ours':<20} {'s':>8}   {'theirs':<38} {'s':>8}  ours/theirs")
    for case, fn, t_ours, peer, t_peer in rows:
        o = f"{t_ours:8.3f}" if t_ours is not None else "     n/a"
        r = f"{t_ours / t_peer:6.2f}" if t_ours is not None else "   n/a"
        print(f"{case:<12} {fn:<20} {o}   {peer:<38} {t_peer:8.3f}  {r}")


if __name__ == "__main__":
    main()
