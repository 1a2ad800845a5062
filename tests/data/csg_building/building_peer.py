#!/usr/bin/env python3
"""manifold3d on the building's booleans (examples/csg_fig18_building.rhai, Figs. 18-20), on the
very inputs the recipe saved: per storey (slab + walls) - openings, then the union of the storeys
and the roof. kernel/benches/csg.rs times blocksmith on the same OBJ files.

Run:
  target/release/blocksmith run examples/csg_fig18_building.rhai -o target/peers/csg_building/b.glb \\
      --set storeys=10 --set inputs=$PWD/target/peers/csg_building
  ~/.cache/blocksmith-peers/venv/bin/python tests/data/csg_building/building_peer.py target/peers/csg_building
Prints one line: BUILDING_MANIFOLD storeys=.. tris=.. volume=.. genus=.. bool_med_s=.. bool_min_s=.. (15 runs)
"""
import glob
import os
import statistics
import sys
import time

import numpy as np
import manifold3d as mf


def load_obj(path):
    v, f = [], []
    with open(path) as src:
        for line in src:
            if line.startswith("v "):
                v.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                f.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    mesh = mf.Mesh(vert_properties=np.array(v, dtype=np.float32), tri_verts=np.array(f, dtype=np.uint32))
    m = mf.Manifold(mesh)
    assert m.status() == mf.Error.NoError, (path, m.status())
    return m


def main():
    d = sys.argv[1]
    storeys = len(glob.glob(os.path.join(d, "slab_*.obj")))
    parts = [(load_obj(os.path.join(d, f"slab_{k}.obj")), load_obj(os.path.join(d, f"walls_{k}.obj")),
              load_obj(os.path.join(d, f"openings_{k}.obj"))) for k in range(storeys)]
    roof = load_obj(os.path.join(d, "roof.obj"))
    for p in parts:
        for m in p:
            m.num_tri()

    def building():
        cut = [mf.Manifold.batch_boolean([mf.Manifold.batch_boolean([s, w], mf.OpType.Add), o], mf.OpType.Subtract)
               for s, w, o in parts]
        r = mf.Manifold.batch_boolean(cut + [roof], mf.OpType.Add)
        r.num_tri()
        return r

    ts = []
    for _ in range(15):
        t0 = time.perf_counter()
        r = building()
        ts.append(time.perf_counter() - t0)
    print(f"BUILDING_MANIFOLD storeys={storeys} tris={r.num_tri()} volume={r.volume():.9f} genus={r.genus()} "
          f"bool_med_s={statistics.median(ts):.4f} bool_min_s={min(ts):.4f}", flush=True)


if __name__ == "__main__":
    main()
