#!/usr/bin/env python3
"""Reference numbers for blocksmith's CSG from manifold3d (the C++ Manifold, 3.5.4).

Writes the input meshes as OBJ (coordinates printed with repr, so they read back bit-exact) and
reference.json with manifold3d's volume, surface area, genus and triangle count of each boolean.
kernel/tests/csg_reference.rs reads the same OBJ files, runs blocksmith's CSG and compares.

Run: ~/.cache/blocksmith-peers/venv/bin/python tests/data/csg_reference/make_reference.py
"""
import json
import os

import numpy as np
import manifold3d as mf

HERE = os.path.dirname(os.path.abspath(__file__))


def write_obj(name, m):
    mesh = m.to_mesh()
    v = np.asarray(mesh.vert_properties)[:, :3]
    f = np.asarray(mesh.tri_verts)
    with open(os.path.join(HERE, name + ".obj"), "w") as out:
        out.write(f"# {name}: written by make_reference.py from manifold3d 3.5.4\n")
        for p in v:
            out.write(f"v {float(p[0])!r} {float(p[1])!r} {float(p[2])!r}\n")
        for t in f:
            out.write(f"f {t[0] + 1} {t[1] + 1} {t[2] + 1}\n")
    # manifold3d exports f32 coordinates: rebuild the solid from exactly those numbers, which is
    # what blocksmith reads from the OBJ, so both tools start from the same input.
    return mf.Manifold(mesh)


def pips():
    d = 0.5
    layouts = {1: [(0, 0)], 2: [(-d, -d), (d, d)], 3: [(-d, -d), (0, 0), (d, d)],
               4: [(-d, -d), (-d, d), (d, -d), (d, d)], 5: [(-d, -d), (-d, d), (0, 0), (d, -d), (d, d)],
               6: [(-d, -d), (-d, 0), (-d, d), (d, -d), (d, 0), (d, d)]}
    faces = [(1, 2, 1), (6, 2, -1), (2, 0, 1), (5, 0, -1), (3, 1, 1), (4, 1, -1)]
    out = []
    for val, axis, sign in faces:
        others = [a for a in range(3) if a != axis]
        for u, v in layouts[val]:
            p = [0.0, 0.0, 0.0]
            p[axis] = sign * 0.95
            p[others[0]] = u
            p[others[1]] = v
            out.append(tuple(p))
    return out


def main():
    inputs = {
        "cube": mf.Manifold.cube((2.0, 2.0, 2.0), True),
        "cube_shifted": mf.Manifold.cube((2.0, 2.0, 2.0), True).translate((0.7, 0.4, 0.3)),
        "sphere": mf.Manifold.sphere(1.2, 48),
        "cylinder": mf.Manifold.cylinder(3.0, 0.5, 0.5, 40, True).rotate((20.0, 10.0, 0.0)),
        "torus": mf.Manifold.revolve(mf.CrossSection.circle(0.3, 24).translate((1.0, 0.0)), 48),
    }
    for i, p in enumerate(pips()):
        inputs[f"pip{i:02}"] = mf.Manifold.sphere(0.15, 32).translate(p)
    inputs = {name: write_obj(name, m) for name, m in inputs.items()}
    # Booleans of the OBJ meshes as written (f64 coordinates, identical to manifold's).
    cases = {
        "cube_minus_sphere": ("cube", "-", "sphere"),
        "cube_union_shifted": ("cube", "+", "cube_shifted"),
        "cube_and_shifted": ("cube", "^", "cube_shifted"),
        "sphere_minus_cylinder": ("sphere", "-", "cylinder"),
        "cube_minus_torus": ("cube", "-", "torus"),
        "torus_union_cylinder": ("torus", "+", "cylinder"),
    }
    ops = {"+": mf.OpType.Add, "-": mf.OpType.Subtract, "^": mf.OpType.Intersect}
    ref = {}
    for name, (a, op, b) in cases.items():
        r = mf.Manifold.batch_boolean([inputs[a], inputs[b]], ops[op])
        ref[name] = dict(a=a, op=op, b=b, volume=r.volume(), area=r.surface_area(), genus=r.genus(), triangles=r.num_tri())
    die = mf.Manifold.batch_boolean([inputs["cube"]] + [inputs[f"pip{i:02}"] for i in range(21)], mf.OpType.Subtract)
    ref["die"] = dict(a="cube", op="-", b=[f"pip{i:02}" for i in range(21)], volume=die.volume(), area=die.surface_area(),
                      genus=die.genus(), triangles=die.num_tri())
    with open(os.path.join(HERE, "reference.json"), "w") as out:
        json.dump(ref, out, indent=1, sort_keys=True)
        out.write("\n")


if __name__ == "__main__":
    main()
