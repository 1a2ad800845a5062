"""Measures of five closed meshes computed by trimesh, the independent tool the kernel's
measures are checked against (kernel/tests/measures_vs_trimesh.rs holds the printed numbers).

Run from the repository root with a Python that has numpy and trimesh (5.x):
    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install -q numpy trimesh
    /tmp/venv/bin/python tests/data/measures_trimesh.py

Meshes:
  cube      trimesh.creation.box(extents=(2, 2, 2))
  box       trimesh.creation.box(bounds=[(-1, 0, 2), (2, 0.5, 6)])
  icosphere trimesh.creation.icosphere(subdivisions=3, radius=1) — the same construction as
            blocksmith's Mesh::icosphere, so trimesh builds it itself
  cylinder  blocksmith's Mesh::cylinder(1.5, 3, 16), read from tests/data/measures/cylinder.obj
            (trimesh's own cylinder places its vertices differently)
  torus     blocksmith's Mesh::torus(2, 0.5, 24, 12), built from indexed quads, read from
            tests/data/measures/torus.obj
The OBJ files are written by `cargo test -p blocksmith-kernel --test measures_vs_trimesh --
--ignored write_measure_objs`; a normal test run checks that they are still what the kernel
writes. trimesh triangulates the polygons as it reads them (fans; volume and area do not depend
on the diagonal for planar convex faces).

Genus: for a closed mesh with c components, genus = (2c - euler) / 2.
"""
import os

import trimesh

HERE = os.path.dirname(os.path.abspath(__file__))


def load_ours(name):
    return trimesh.load(os.path.join(HERE, "measures", name), process=False, force="mesh")


meshes = {
    "cube": trimesh.creation.box(extents=(2, 2, 2)),
    "box": trimesh.creation.box(bounds=[(-1, 0, 2), (2, 0.5, 6)]),
    "icosphere": trimesh.creation.icosphere(subdivisions=3, radius=1.0),
    "cylinder": load_ours("cylinder.obj"),
    "torus": load_ours("torus.obj"),
}

print("trimesh", trimesh.__version__)
for name, m in meshes.items():
    assert m.is_watertight and m.is_winding_consistent, name
    euler = int(m.euler_number)
    genus = (2 * m.body_count - euler) // 2
    print(
        "TRIMESH_MEASURES %-9s vertices=%d faces=%d volume=%r area=%r euler=%d genus=%d"
        % (name, len(m.vertices), len(m.faces), float(m.volume), float(m.area), euler, genus)
    )
