#!/usr/bin/env python3
"""Surface finishing side by side (issue 31): what `cargo bench -p blocksmith-kernel --bench finish`
times on the 100k-triangle scan-like surface, done by pymeshlab on the same file, and the quality
of both results.

The bench leaves in target/bench-data/: `finish_scan100k.ply` (the input), and our results at the
benched settings, `finish_ours_decimate10k.ply` (decimated to 10,000 triangles) and
`finish_ours_remesh.ply` (target edge length 0.5, 5 iterations). This script runs pymeshlab on
the input:

  decimate  meshing_decimation_quadric_edge_collapse(targetfacenum=10000, preservenormal,
            optimalplacement), as MeshLab's users run it;
  remesh    meshing_isotropic_explicit_remeshing(targetlen=AbsoluteValue(0.5), iterations=5).

and prints, for each result, its triangle count, the two-sided Hausdorff distance to the input
(pymeshlab's get_hausdorff_distance, 200,000 samples each way: max and mean, in units of the
input's bounding-box diagonal too), the smallest triangle angle and the share of angles under 30°,
the edge-length spread (standard deviation / mean) and the volume change. The times are the median
of --reps runs here, and ours is criterion's median
(target/criterion/finish/<function>/new/estimates.json); the ratio printed is ours / theirs.

The CSG plate (`finish_plate.ply`) is remeshed by both to edges of 0.1 in 6 iterations, edges
sharper than 60 degrees kept. With --big, pymeshlab is timed on the 1.3M-triangle surface too
(remesh L 0.15 3 iterations, decimate to 100k, 10 rounds of Taubin smoothing) against the bench's
1M cases. With manifold3d installed, smooth refinement (refine 2 of the 100k surface) is timed
against Manifold's own smooth_out and refine.

  ~/.cache/blocksmith-peers/venv/bin/python kernel/benches/finish_peer.py [--reps 3] [--big]
"""
import argparse
import json
import os
import statistics
import time

import numpy as np
import pymeshlab

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DATA = os.path.join(ROOT, "target", "bench-data")
# pymeshlab 2022.2 renamed PureValue to AbsoluteValue.
ABSOLUTE = getattr(pymeshlab, "AbsoluteValue", None) or pymeshlab.PureValue


def ours_time(function):
    p = os.path.join(ROOT, "target", "criterion", "finish", function, "new", "estimates.json")
    if not os.path.exists(p):
        return None
    with open(p) as f:
        return json.load(f)["median"]["point_estimate"] / 1e9


def quality(ms, index, input_index, input_volume, diagonal):
    """The measures of mesh `index` of `ms` against mesh `input_index` (the input)."""
    m = ms.mesh(index)
    v, f = m.vertex_matrix(), m.face_matrix()
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]

    def angle(p, q, r):
        u, w = q - p, r - p
        cos = np.einsum("ij,ij->i", u, w) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))

    angles = np.concatenate([angle(a, b, c), angle(b, c, a), angle(c, a, b)])
    edges = np.concatenate([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1)])
    there = ms.get_hausdorff_distance(sampledmesh=index, targetmesh=input_index, samplenum=200_000)
    back = ms.get_hausdorff_distance(sampledmesh=input_index, targetmesh=index, samplenum=200_000)
    ms.set_current_mesh(index)
    volume = ms.get_geometric_measures()["mesh_volume"]
    return {
        "triangles": len(f),
        "hausdorff_max": max(there["max"], back["max"]),
        "hausdorff_mean": (there["mean"] + back["mean"]) / 2,
        "hausdorff_max_per_diagonal": max(there["max"], back["max"]) / diagonal,
        "min_angle_deg": float(angles.min()),
        "angles_under_30_pct": float(100 * (angles < 30).mean()),
        "edge_spread": float(edges.std() / edges.mean()),
        "volume_change_pct": float(100 * (volume - input_volume) / input_volume),
    }


def side_by_side(ms, input_file, cases, reps):
    """Each case on a fresh copy of `input_file` (loaded as the set's first mesh): pymeshlab's time
    and, when our result is on file, both results' quality."""
    ms.load_new_mesh(input_file)
    input_index = ms.current_mesh_id()
    input_volume = ms.get_geometric_measures()["mesh_volume"]
    diagonal = ms.current_mesh().bounding_box().diagonal()
    for name, function, ours_file, run in cases:
        times = []
        for _ in range(reps):
            ms.set_current_mesh(input_index)
            ms.add_mesh(ms.mesh(input_index))  # a fresh copy of the input becomes the current mesh
            t = time.perf_counter()
            run()
            times.append(time.perf_counter() - t)
        theirs_index = ms.current_mesh_id()
        peer_time, our_time = statistics.median(times), ours_time(function)
        ratio = f"{our_time / peer_time:.2f}" if our_time else "n/a (run the bench)"
        print(f"{name}: pymeshlab {peer_time:.3f} s, ours {our_time if our_time else float('nan'):.3f} s, ratio {ratio}")
        if ours_file is None:
            continue
        ms.load_new_mesh(os.path.join(DATA, ours_file))
        ours_index = ms.current_mesh_id()
        theirs = quality(ms, theirs_index, input_index, input_volume, diagonal)
        ours = quality(ms, ours_index, input_index, input_volume, diagonal)
        for key in theirs:
            t, o = theirs[key], ours[key]
            print(f"  {key:28s} pymeshlab {t:12.6g}   ours {o:12.6g}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--big", action="store_true", help="also time the 1.3M-triangle cases (no quality measures)")
    args = ap.parse_args()
    scan = os.path.join(DATA, "finish_scan100k.ply")
    if not os.path.exists(scan):
        raise SystemExit(f"{scan} is missing: run `cargo bench -p blocksmith-kernel --bench finish` first")

    ms = pymeshlab.MeshSet()
    side_by_side(ms, scan, [
        ("decimate", "decimate_scan100k_to10k", "finish_ours_decimate10k.ply",
         lambda: ms.meshing_decimation_quadric_edge_collapse(targetfacenum=10_000, preservenormal=True,
                                                             optimalplacement=True)),
        ("remesh", "remesh_scan100k_L0.5_5it", "finish_ours_remesh.ply",
         lambda: ms.meshing_isotropic_explicit_remeshing(targetlen=ABSOLUTE(0.5), iterations=5)),
    ], args.reps)
    # The CSG plate: edges of 0.1, 6 iterations, creases above 60 degrees kept on both sides.
    side_by_side(ms, os.path.join(DATA, "finish_plate.ply"), [
        ("remesh the plate", "remesh_plate_L0.1_6it", "finish_ours_plate_remesh.ply",
         lambda: ms.meshing_isotropic_explicit_remeshing(targetlen=ABSOLUTE(0.1), iterations=6, featuredeg=60)),
    ], args.reps)
    # Smooth refinement has no pymeshlab counterpart: Manifold's own, through manifold3d (our
    # `refine` is its smooth_out by sector normals and refine, plus the half-edge build).
    try:
        import manifold3d
    except ImportError:
        manifold3d = None
    if manifold3d is not None:
        ms.set_current_mesh(0)
        m = ms.mesh(0)
        solid = manifold3d.Manifold(manifold3d.Mesh(vert_properties=m.vertex_matrix().astype(np.float32),
                                                    tri_verts=m.face_matrix().astype(np.uint32)))
        times = []
        for _ in range(args.reps):
            t = time.perf_counter()
            solid.smooth_out(60.0, 0.0).refine(2).num_tri()
            times.append(time.perf_counter() - t)
        peer_time, our_time = statistics.median(times), ours_time("refine2_scan100k")
        ratio = f"{our_time / peer_time:.2f}" if our_time else "n/a (run the bench)"
        print(f"refine 2: manifold3d {peer_time:.3f} s, ours {our_time if our_time else float('nan'):.3f} s, ratio {ratio}")
    if args.big:
        ms = pymeshlab.MeshSet()
        side_by_side(ms, os.path.join(DATA, "finish_scan1m.ply"), [
            ("remesh 1.3M", "remesh_scan1m_L0.15_3it", None,
             lambda: ms.meshing_isotropic_explicit_remeshing(targetlen=ABSOLUTE(0.15), iterations=3)),
            ("decimate 1.3M to 100k", "decimate_scan1m_to100k", None,
             lambda: ms.meshing_decimation_quadric_edge_collapse(targetfacenum=100_000, preservenormal=True,
                                                                 optimalplacement=True)),
            ("Taubin 1.3M, 10 rounds", "relax_taubin_scan1m_10", None,
             lambda: ms.apply_coord_taubin_smoothing(stepsmoothnum=10)),
        ], 1)


if __name__ == "__main__":
    main()
