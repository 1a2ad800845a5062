"""Writes the OpenSubdiv agreement corpus in shapes/ (OBJ with OpenSubdiv's `t` tags).

Each file name starts with its scheme (cc_ or loop_). Vertices are nudged off symmetric positions
by fixed amounts so that a weight applied to the wrong neighbour shows. Run from anywhere:
    python3 tests/data/subdiv/make_shapes.py
"""
import math
import os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "shapes")


def nudge(verts):
    return [(x + 0.013 * ((i * 7) % 5), y - 0.011 * ((i * 3) % 4), z + 0.017 * ((i * 5) % 3))
            for i, (x, y, z) in enumerate(verts)]


def write(name, verts, faces, tags, note):
    with open(os.path.join(OUT, name + ".obj"), "w") as f:
        f.write(f"# {note}\n")
        for x, y, z in nudge(verts):
            f.write(f"v {x!r} {y!r} {z!r}\n")
        for face in faces:
            f.write("f " + " ".join(str(i + 1) for i in face) + "\n")
        for t in tags:
            f.write(t + "\n")


CUBE_V = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
CUBE_F = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
CUBE_E = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]


def crease(a, b, s):
    return f"t crease 2/1/0 {a} {b} {s}"


def corner(v, s):
    return f"t corner 1/1/0 {v} {s}"


def grid(n, bump=True):
    verts = [(i - n / 2, j - n / 2, (0.3 * math.sin(i + 2 * j) if bump else 0.0))
             for j in range(n + 1) for i in range(n + 1)]
    faces = [[j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i]
             for j in range(n) for i in range(n)]
    return verts, faces


def tri_grid(n):
    verts, quads = grid(n)
    faces = []
    for k, (a, b, c, d) in enumerate(quads):
        faces += [[a, b, c], [a, c, d]] if k % 2 == 0 else [[a, b, d], [b, c, d]]
    return verts, faces


def pyramid(n):
    verts = [(math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n), 0.0) for k in range(n)] + [(0, 0, 1.2)]
    faces = [list(reversed(range(n)))] + [[k, (k + 1) % n, n] for k in range(n)]
    return verts, faces


def torus(nu, nv, R=2.0, r=0.7):
    verts = [((R + r * math.cos(2 * math.pi * j / nv)) * math.cos(2 * math.pi * i / nu),
              (R + r * math.cos(2 * math.pi * j / nv)) * math.sin(2 * math.pi * i / nu),
              r * math.sin(2 * math.pi * j / nv)) for i in range(nu) for j in range(nv)]
    idx = lambda i, j: (i % nu) * nv + j % nv
    faces = [[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)] for i in range(nu) for j in range(nv)]
    return verts, faces


OCTA_V = [(1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
OCTA_F = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [1, 0, 5], [2, 1, 5], [3, 2, 5], [0, 3, 5]]


def icosahedron():
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
         [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11],
         [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    return v, f


def main():
    os.makedirs(OUT, exist_ok=True)
    top = [(4, 5), (5, 6), (6, 7), (7, 4)]
    write("cc_cube_s05", CUBE_V, CUBE_F, [crease(a, b, 0.5) for a, b in top], "cube, top loop sharpness 0.5")
    write("cc_cube_s1", CUBE_V, CUBE_F, [crease(a, b, 1) for a, b in CUBE_E], "cube, every edge sharpness 1")
    write("cc_cube_s15_corner", CUBE_V, CUBE_F, [crease(a, b, 1.5) for a, b in top] + [corner(0, 2)],
          "cube, top loop 1.5, vertex 0 corner sharpness 2")
    write("cc_cube_mixed", CUBE_V, CUBE_F,
          [crease(4, 5, 2.7), crease(5, 6, 10), crease(5, 1, 0.5), crease(6, 7, 1.5), crease(0, 1, 2.7),
           corner(3, 0.5), corner(2, 1.5)],
          "cube, sharpness 2.7, inf, 0.5 and 1.5 meeting at vertices; corners 0.5 and 1.5")
    write("cc_cube_dart", CUBE_V, CUBE_F, [crease(0, 1, 2.7)], "cube, one semi-sharp edge (darts at both ends)")
    write("cc_cube_chaikin", CUBE_V, CUBE_F,
          [crease(4, 5, 0.5), crease(5, 6, 2.7), crease(6, 7, 1.5), crease(7, 4, 2.0), crease(5, 1, 1.2),
           "t creasemethod 0/0/1 chaikin"], "cube, varying sharpness, Chaikin creasing")
    v, f = torus(6, 4)
    write("cc_torus_crease", v, f, [crease(0, 1, 1.5), crease(1, 2, 2.7), crease(2, 3, 0.5), crease(3, 0, 10)],
          "torus 6x4, one ring creased with mixed sharpness")
    v, f = grid(3)
    inner = [crease(5, 6, 1.5), crease(6, 10, 2.7)]
    write("cc_grid_edge_only", v, f, inner + ["t interpolateboundary 1/0/0 2"], "open grid, edge only")
    write("cc_grid_edge_corner", v, f, inner + ["t interpolateboundary 1/0/0 1"], "open grid, edge and corner")
    write("cc_grid_none", v, f, inner + ["t interpolateboundary 1/0/0 0"], "open grid, boundary none")
    write("cc_grid_corner_semi", v, f, [corner(0, 1.5), corner(3, 0.5), crease(1, 5, 1)],
          "open grid, semi-sharp corners on the boundary, edge only")
    v, f = pyramid(5)
    base = [crease(k, (k + 1) % 5, 2.7) for k in range(5)]
    write("cc_pyramid_ngon", v, f, base + [corner(5, 1.5)], "pentagon base, five triangles, base loop 2.7")
    write("cc_pyramid_smooth_triangles", v, f, base[:2] + ["t smoothtriangles 0/0/1 smooth"],
          "pentagon base and triangles, smooth triangle weights")
    v, f = pyramid(6)
    write("cc_hexpyramid_edge_corner_smooth_tri", v, f[1:], ["t smoothtriangles 0/0/1 smooth",
                                                            "t interpolateboundary 1/0/0 1", crease(0, 6, 0.5)],
          "open hexagonal fan of triangles, smooth triangles, edge and corner")
    write("loop_octahedron", OCTA_V, OCTA_F, [crease(a, b, 1.5) for a, b in [(0, 1), (1, 2), (2, 3), (3, 0)]]
          + [corner(5, 2.7)], "octahedron, equator 1.5, bottom corner 2.7")
    v, f = icosahedron()
    write("loop_icosahedron_mixed", v, f, [crease(0, 1, 0.5), crease(1, 7, 1), crease(7, 0, 10), crease(0, 5, 2.7)],
          "icosahedron, sharpness 0.5, 1, inf, 2.7 meeting at vertex 0")
    write("loop_icosahedron_chaikin", v, f, [crease(0, 1, 0.5), crease(1, 7, 2.2), crease(7, 0, 1.7),
                                             "t creasemethod 0/0/1 chaikin"], "icosahedron, Chaikin creasing")
    v, f = tri_grid(3)
    write("loop_grid_edge_only", v, f, [crease(5, 6, 2.7), "t interpolateboundary 1/0/0 2"], "triangle grid, edge only")
    write("loop_grid_edge_corner", v, f, [crease(5, 6, 2.7), corner(9, 0.5), "t interpolateboundary 1/0/0 1"],
          "triangle grid, edge and corner")
    write("loop_grid_none", v, f, [crease(5, 6, 1.5), "t interpolateboundary 1/0/0 0"], "triangle grid, none")
    v, f = torus(6, 4)
    write("cc_torus_darts", v, f, [crease(0, 1, 10), crease(9, 13, 0.5), crease(13, 17, 1.5)],
          "torus 6x4, an infinitely sharp edge and a two-edge semi-sharp chain, darts at their ends")
    write("cc_cube_dart_corner", CUBE_V, CUBE_F, [crease(4, 5, 1.5), corner(5, 0.7), corner(6, 2.3)],
          "cube, one semi-sharp edge ending in a fractional corner (0.7) and a dart; a lone corner 2.3")
    v, f = icosahedron()
    write("loop_icosahedron_darts", v, f, [crease(0, 11, 2.7), crease(3, 9, 10), crease(9, 4, 0.5)],
          "icosahedron, a semi-sharp edge and an infinite-then-0.5 chain between valence-5 darts")


main()
