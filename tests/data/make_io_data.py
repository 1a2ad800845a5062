"""Make the small mesh files the kernel's io tests read (tests/data/io/).

Run from the repository root with a Python that has numpy and trimesh (5.x):
    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install -q numpy trimesh
    /tmp/venv/bin/python tests/data/make_io_data.py

Valid files:
  quads.obj          a cube of side 2 as 6 quads, with normals, uvs, an object name and a material
  trimesh_box.glb    trimesh's box of extents 2 (12 triangles, 8 vertices)
  trimesh_scene.glb  trimesh's box + an icosphere (r 0.8, 3 subdivisions) moved to x=2.5, red
Broken files, one per error the readers must report:
  bad_index.obj      a face naming vertex 9 of 8 (line 11)
  junk_line.obj      a line with an unknown keyword (line 4)
  nan.obj            a vertex with a NaN coordinate (vertex 2)
  nonmanifold.obj    three triangles on one edge (a "polygon soup")
  broken.glb         trimesh_box.glb with its first index rewritten past the vertices
  truncated.glb      trimesh_box.glb cut in half
  truncated.stl      a binary STL cut short of its triangle count
"""
import json
import os
import struct

import numpy as np
import trimesh

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "io")
os.makedirs(OUT, exist_ok=True)


def write(name, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(OUT, name), mode) as f:
        f.write(data)


CUBE_V = "".join(
    "v %g %g %g\n" % (x, y, z) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)
)

write(
    "quads.obj",
    "# a cube of side 2 as 6 quads (vertex i: x by bit 0, y by bit 1, z by bit 2)\n"
    "mtllib cube.mtl\no cube\n" + CUBE_V + "vn 0 0 1\nvt 0 0\nusemtl grey\ns off\n"
    "f 1/1/1 5/1/1 7/1/1 3/1/1\nf 2/1/1 4/1/1 8/1/1 6/1/1\nf 1 2 6 5\nf 3 7 8 4\nf 1 3 4 2\nf 5 6 8 7\n",
)
write("bad_index.obj", "# face on line 11 names vertex 9 of 8\n" + CUBE_V + "f 1 3 4 2\nf 5 6 8 9\n")
write("junk_line.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nthis line is junk\nf 1 2 3\n")
write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n")
write(
    "nonmanifold.obj",
    "# three triangles share the edge 1-2\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 0 -1\n"
    "f 1 2 3\nf 2 1 4\nf 1 2 5\n",
)

box = trimesh.creation.box(extents=(2, 2, 2))
box_glb = box.export(file_type="glb")
write("trimesh_box.glb", box_glb)
ico = trimesh.creation.icosphere(subdivisions=3, radius=0.8)
ico.apply_translation((2.5, 0, 0))
ico.visual.face_colors = [200, 60, 60, 255]
write("trimesh_scene.glb", trimesh.Scene({"box": box, "ico": ico}).export(file_type="glb"))

# broken.glb: the first index of the box rewritten to point past the 8 vertices (as
# ../shared/peers/make_test_glb.py does).
data = bytearray(box_glb)
jlen = struct.unpack_from("<I", data, 12)[0]
gl = json.loads(data[20 : 20 + jlen])
acc = gl["accessors"][gl["meshes"][0]["primitives"][0]["indices"]]
bv = gl["bufferViews"][acc["bufferView"]]
off = 20 + jlen + 8 + bv.get("byteOffset", 0) + acc.get("byteOffset", 0)
fmt = {5125: "<I", 5123: "<H", 5121: "<B"}[acc["componentType"]]
struct.pack_into(fmt, data, off, 250 if acc["componentType"] == 5121 else 9999)
write("broken.glb", bytes(data))
write("truncated.glb", bytes(box_glb[: len(box_glb) // 2]))

stl = box.export(file_type="stl")
write("truncated.stl", bytes(stl[: len(stl) - 30]))

print("MAKE_IO_DATA box_faces=%d ico_faces=%d out=%s" % (len(box.faces), len(ico.faces), OUT))
print("box volume %.17g area %.17g; ico volume %.17g" % (box.volume, box.area, ico.volume))
