"""Makes the regression corpus of issue 19 ("real-world files"): one small file per class of
file that failed, and expected.json with what trimesh (the peer) finds in each after merging
vertices: vertices, faces (triangles), Euler characteristic, area and volume. The Rust test
kernel/tests/files_corpus.rs loads each file with blocksmith and holds it to these numbers and
to the behaviour named in `must`.

    python tests/data/files/make_files.py      # needs trimesh, numpy and DracoPy; rewrites the files

Files (all made here, no third-party data):
  cad_noise.stl        ASCII cube whose shared corners differ by CAD arithmetic noise (0 vs
                       -3.79e-33, -6.123e-17 vs -6.147e-17): must weld closed
  two_solids.stl       ASCII, two `solid` blocks (a cube and a tetrahedron): both must be read
  continued.obj        a cube whose `f` lines continue with `\\`: must read as 6 quads
  split_seams.glb      a cube with every triangle's corners apart (as glTF exporters split at
                       normal/UV seams): must weld closed
  instanced.glb        one cube mesh used by two nodes, the second moved: both instances read
  val2_pillow.obj      two skew quads glued along all four edges (valence-2 vertices): must
                       triangulate to a closed manifold mesh and save to STL and GLB
  k5_torus.obj         K5 on a torus as five skew quads: every pair of the five corners is an
                       edge, so both diagonals of every quad are edges already; must triangulate
                       (each quad about a vertex added at its centroid: 10 vertices, 20
                       triangles, a closed torus) and save to STL and GLB
  split_colored.ply    trimesh's binary little-endian PLY of the cube with every triangle's
                       corners apart and a colour per corner: must weld closed, colours read
  quads_big_endian.ply a cube of six quads, binary big-endian, float coordinates, normals
                       (ignored), uchar colours and an extra `material` element: quads kept
  quads_ascii.ply      the same cube as ASCII text, int16 coordinates, a `vertex_index`
                       list with uint indices: quads kept
  uv_normals.ply       trimesh's ASCII PLY of the cube split at every corner (as exporters split
                       at UV seams), with vertex normals and texture coordinates: must weld
                       closed (normals and UVs are read past: a mesh keeps neither)
  uv_normals_bin.ply   the same, binary little-endian
  draco_sphere.glb     an icosphere compressed by Google's Draco (through DracoPy) with
                       KHR_draco_mesh_compression required: edgebreaker (compression level 7),
                       positions quantized to 14 bits, with normals (DracoPy numbers them 0,
                       POSITION 1), moved off the origin: must decode and weld closed; the
                       peer's numbers are those of Google's own decoder's output
  draco_sequential.glb the same with sequential connectivity (level 0), no normals, positions
                       as attribute 0, strided into a buffer after 8 bytes of padding
"""
import json
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).parent
CUBE_V = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
CUBE_F = trimesh.creation.box(bounds=[[0, 0, 0], [1, 1, 1]]).faces


def facets(vertices, faces, noise):
    out = []
    for k, f in enumerate(faces):
        out.append("facet normal 0 0 0\n outer loop\n")
        for v in f:
            p = vertices[v].copy()
            # Zero coordinates become tiny noise in some facets, as a CAD kernel leaves them.
            p = np.where(p == 0.0, [0.0, -3.79e-33, -6.123e-17, -6.147e-17][k % 4] * noise, p)
            out.append("  vertex {!r} {!r} {!r}\n".format(*map(float, p)))
        out.append(" endloop\nendfacet\n")
    return "".join(out)


def draco_glb(mesh, level, normals, pad):
    """A GLB whose one primitive is stored only as Draco data (KHR_draco_mesh_compression
    required): the accessors give counts and types, the bufferView holds the bitstream."""
    import DracoPy

    kwargs = dict(quantization_bits=14, compression_level=level)
    if normals:
        radial = mesh.vertices - mesh.vertices.mean(axis=0)
        kwargs["normals"] = radial / np.linalg.norm(radial, axis=1)[:, None]
    drc = DracoPy.encode(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.uint32), **kwargs)
    back = DracoPy.decode(drc)
    points = np.asarray(back.points, dtype=np.float64)
    faces = np.asarray(back.faces).reshape(-1, 3)
    # The unique id of each attribute as the encoder numbered it (Draco's attribute types:
    # 0 position, 1 normal); DracoPy puts the normals first.
    ids = {a["attribute_type"]: a["unique_id"] for a in back.attributes}
    attributes = {"POSITION": ids[0]}
    if normals:
        attributes["NORMAL"] = ids[1]
    body = bytes(pad) + drc
    body += bytes(-len(body) % 4)
    doc = {
        "asset": {"version": "2.0", "generator": "blocksmith make_files.py (DracoPy)"},
        "extensionsUsed": ["KHR_draco_mesh_compression"],
        "extensionsRequired": ["KHR_draco_mesh_compression"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {k: i for i, k in enumerate(attributes)},
            "indices": len(attributes),
            "mode": 4,
            "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": attributes}},
        }]}],
        "accessors": [
            {"componentType": 5126, "count": len(points), "type": "VEC3",
             "min": points.min(axis=0).tolist(), "max": points.max(axis=0).tolist()},
        ] + ([{"componentType": 5126, "count": len(points), "type": "VEC3"}] if normals else []) + [
            {"componentType": 5125, "count": 3 * len(faces), "type": "SCALAR"},
        ],
        "bufferViews": [{"buffer": 0, "byteOffset": pad, "byteLength": len(drc)}],
        "buffers": [{"byteLength": len(body)}],
    }
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    glb = b"glTF" + (2).to_bytes(4, "little") + (12 + 8 + len(text) + 8 + len(body)).to_bytes(4, "little")
    glb += len(text).to_bytes(4, "little") + b"JSON" + text + len(body).to_bytes(4, "little") + b"BIN\0" + body
    return glb, trimesh.Trimesh(points, faces, process=False)


def peer(mesh):
    mesh = mesh.copy()
    mesh.merge_vertices()
    return {
        "vertices": len(mesh.vertices),
        "faces": len(mesh.faces),
        "euler": int(mesh.euler_number),
        "area": float(mesh.area),
        "volume": float(mesh.volume),
        "watertight": bool(mesh.is_watertight),
    }


def main():
    box = trimesh.Trimesh(CUBE_V, CUBE_F, process=False)
    expected = {}

    (HERE / "cad_noise.stl").write_text("solid cad\n" + facets(CUBE_V, CUBE_F, 1.0) + "endsolid cad\n")
    expected["cad_noise.stl"] = dict(peer(trimesh.load(HERE / "cad_noise.stl", process=False)), must="closed")

    tet = trimesh.Trimesh([[3, 0, 0], [4, 0, 0], [3, 1, 0], [3, 0, 1]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], process=False)
    text = "solid a\n" + facets(CUBE_V, CUBE_F, 0.0) + "endsolid a\nsolid b\n"
    text += facets(tet.vertices, tet.faces, 0.0) + "endsolid b\n"
    (HERE / "two_solids.stl").write_text(text)
    expected["two_solids.stl"] = dict(peer(trimesh.util.concatenate([box, tet])), must="closed", components=2)

    quads = [[1, 3, 4, 2], [5, 6, 8, 7], [1, 2, 6, 5], [3, 7, 8, 4], [1, 5, 7, 3], [2, 4, 8, 6]]
    lines = ["v {} {} {}".format(*map(float, p)) for p in CUBE_V]
    lines += ["f {} \\\n  {} {} \\\n {}".format(*q[::-1]) for q in quads]
    (HERE / "continued.obj").write_text("\n".join(lines) + "\n")
    expected["continued.obj"] = dict(peer(box), must="closed", polygons=6)

    corners = CUBE_V[CUBE_F].reshape(-1, 3)
    split = trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), process=False)
    split.export(HERE / "split_seams.glb")
    expected["split_seams.glb"] = dict(peer(split), must="closed")

    scene = trimesh.Scene()
    scene.add_geometry(box, geom_name="cube", node_name="first")
    scene.add_geometry(box, geom_name="cube", node_name="second", transform=trimesh.transformations.translation_matrix([2.5, 0, 0]))
    scene.export(HERE / "instanced.glb")
    expected["instanced.glb"] = dict(peer(scene.to_geometry()), must="closed", components=2)

    p = [[0, 0, 0], [1, 0, 0.5], [1, 1, 0], [0, 1, 0.5]]
    (HERE / "val2_pillow.obj").write_text("".join("v {} {} {}\n".format(*map(float, q)) for q in p) + "f 4 1 2 3\nf 4 3 2 1\n")
    # Fanning each quad from its first corner repeats the diagonal 4-2 (an edge of four
    # triangles): the peer's numbers are those of the outward tetrahedron on the four corners,
    # the only closed triangulation there is.
    pillow = trimesh.Trimesh(p, [[2, 1, 0], [3, 2, 0], [3, 1, 2], [3, 0, 1]], process=False)
    expected["val2_pillow.obj"] = dict(peer(pillow), must="triangulates", polygons=2)

    a = np.arange(5) * 2 * np.pi / 5
    k5 = np.stack([np.cos(a), np.sin(a), 0.3 * (np.arange(5) % 2) + 0.1 * np.arange(5)], axis=-1)
    k5_quads = [[0, 1, 2, 3], [0, 2, 4, 1], [0, 4, 3, 2], [0, 3, 1, 4], [1, 3, 4, 2]]
    (HERE / "k5_torus.obj").write_text("".join("v {!r} {!r} {!r}\n".format(*map(float, q)) for q in k5)
                                       + "".join("f {} {} {} {}\n".format(*[v + 1 for v in q]) for q in k5_quads))
    centres = np.array([k5[q].mean(axis=0) for q in k5_quads])
    fans = [[q[i], q[(i + 1) % 4], 5 + f] for f, q in enumerate(k5_quads) for i in range(4)]
    k5_tri = trimesh.Trimesh(np.concatenate([k5, centres]), fans, process=False)
    expected["k5_torus.obj"] = dict(peer(k5_tri), must="triangulates", polygons=5)

    colors = np.array([[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255]] * 12, dtype=np.uint8)
    split_c = trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), vertex_colors=colors, process=False)
    (HERE / "split_colored.ply").write_bytes(split_c.export(file_type="ply", encoding="binary"))
    expected["split_colored.ply"] = dict(peer(trimesh.load(HERE / "split_colored.ply", process=False)), must="closed", colors=True)

    normals = CUBE_V - 0.5
    rgb = (CUBE_V * 255).astype(np.uint8)
    head = ["ply", "format binary_big_endian 1.0", "comment a cube of quads", "element vertex 8",
            "property float x", "property float y", "property float z",
            "property float nx", "property float ny", "property float nz",
            "property uchar red", "property uchar green", "property uchar blue",
            "element face 6", "property list uchar int vertex_indices",
            "element material 1", "property uchar ambient_red", "property list uchar float tags", "end_header"]
    data = b""
    for p_, n_, c_ in zip(CUBE_V, normals, rgb):
        data += np.array(list(p_) + list(n_), dtype=">f4").tobytes() + c_.tobytes()
    for q in quads:
        data += bytes([4]) + np.array([v - 1 for v in q[::-1]], dtype=">i4").tobytes()
    data += bytes([200, 2]) + np.array([0.5, 0.25], dtype=">f4").tobytes()
    (HERE / "quads_big_endian.ply").write_bytes(("\n".join(head) + "\n").encode() + data)
    expected["quads_big_endian.ply"] = dict(peer(trimesh.load(HERE / "quads_big_endian.ply", process=False)), must="closed", polygons=6, colors=True)

    head = ["ply", "format ascii 1.0", "element vertex 8", "property short x", "property short y",
            "property short z", "element face 6", "property list uchar uint vertex_index", "end_header"]
    body = ["{} {} {}".format(*map(int, p_)) for p_ in CUBE_V]
    body += ["4 " + " ".join(str(v - 1) for v in q[::-1]) for q in quads]
    (HERE / "quads_ascii.ply").write_text("\n".join(head + body) + "\n")
    expected["quads_ascii.ply"] = dict(peer(trimesh.load(HERE / "quads_ascii.ply", process=False)), must="closed", polygons=6)

    uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] * 12)
    textured = trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), process=False,
                               visual=trimesh.visual.TextureVisuals(uv=uv))
    textured.vertex_normals  # computed, so that the export writes them
    for name, enc in [("uv_normals.ply", "ascii"), ("uv_normals_bin.ply", "binary")]:
        (HERE / name).write_bytes(textured.export(file_type="ply", encoding=enc, vertex_normal=True))
        back = trimesh.load(HERE / name, process=False)
        # Positions alone: trimesh keeps corners with different UVs apart when merging.
        expected[name] = dict(peer(trimesh.Trimesh(back.vertices, back.faces, process=False)), must="closed")

    sphere = trimesh.creation.icosphere(subdivisions=2, radius=1.5)
    sphere.apply_translation([10.0, -20.0, 5.0])
    glb, decoded = draco_glb(sphere, level=7, normals=True, pad=0)
    (HERE / "draco_sphere.glb").write_bytes(glb)
    expected["draco_sphere.glb"] = dict(peer(decoded), must="closed")
    glb, decoded = draco_glb(sphere, level=0, normals=False, pad=8)
    (HERE / "draco_sequential.glb").write_bytes(glb)
    expected["draco_sequential.glb"] = dict(peer(decoded), must="closed")

    (HERE / "expected.json").write_text(json.dumps(expected, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
