"""Loading and welding a 1M-triangle STL and a 1M-triangle glTF, and loading a 1M-triangle PLY
and 3MF, trimesh beside blocksmith on the same files (issue 19's speed target: at most trimesh's
time).

    python tests/data/files/bench_load.py DIR            # writes DIR/torus_1m.{stl,ply,3mf}, DIR/torus_1m_split.glb
    cargo run --release --example load_weld -- DIR/torus_1m.stl 5
    cargo run --release --example load_weld -- DIR/torus_1m_split.glb 5
    cargo run --release --example load_weld -- DIR/torus_1m.ply 5
    cargo run --release --example load_weld -- DIR/torus_1m.3mf 5

Measured on 2026-12-03 (release build, 2 shared cores, medians of 5; blocksmith / trimesh): split glTF
0.60 s / 1.68 s (0.35x), STL 0.55 s / 1.99 s (0.27x), PLY 0.21 s / 0.59 s (0.36x), 3MF 0.96 s /
4.22 s (0.23x). PLY was 0.83 s (1.41x) before its reader stopped formatting a location string
for every value it read.

The PLY (binary) and the 3MF store the torus indexed, as those formats usually are (3MF needs
lxml and networkx for trimesh).

The model is a torus grid of 1000 x 500 quads, 1,000,000 triangles. Both files store every
triangle's corners apart (the STL by its format, the glTF as a file split at every seam would),
so both readers must weld 3,000,000 corners into 500,000 vertices. This script prints, per file,
`TRIMESH_LOAD file=... median_s=... min_s=... vertices=... faces=... watertight=...` for
trimesh.load (process=True: it merges vertices) followed by is_watertight (the edge check that
blocksmith's loader does while building its half-edges); medians of 5 runs.
"""
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import trimesh


def torus(nu=1000, nv=500, big=2.0, small=0.5):
    u = np.linspace(0, 2 * np.pi, nu, endpoint=False)
    v = np.linspace(0, 2 * np.pi, nv, endpoint=False)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    r = big + small * np.cos(vv)
    verts = np.stack([r * np.cos(uu), r * np.sin(uu), small * np.sin(vv)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = i * nv + j
    b = ((i + 1) % nu) * nv + j
    c = ((i + 1) % nu) * nv + (j + 1) % nv
    d = i * nv + (j + 1) % nv
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return verts, faces


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "target/bench-data")
    out.mkdir(parents=True, exist_ok=True)
    verts, faces = torus()
    # f32 first, so that the STL and the glTF hold the same numbers.
    corners = verts[faces].reshape(-1, 3).astype(np.float32).astype(np.float64)
    soup = trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), process=False)
    stl, glb = out / "torus_1m.stl", out / "torus_1m_split.glb"
    soup.export(stl)
    soup.export(glb)
    indexed = trimesh.Trimesh(verts.astype(np.float32).astype(np.float64), faces, process=False)
    ply, tmf = out / "torus_1m.ply", out / "torus_1m.3mf"
    indexed.export(ply)
    indexed.export(tmf)
    for path in (stl, glb, ply, tmf):
        times = []
        for _ in range(5):
            start = time.perf_counter()
            m = trimesh.load(str(path), force="mesh", process=True)
            watertight = m.is_watertight
            times.append(time.perf_counter() - start)
        print(
            f"TRIMESH_LOAD file={path} median_s={statistics.median(times):.4f} min_s={min(times):.4f} "
            f"vertices={len(m.vertices)} faces={len(m.faces)} watertight={watertight}"
        )


if __name__ == "__main__":
    main()
