"""Peers for kernel/benches/profile.rs and the 2D file formats.

  python profile_peer.py bench   # manifold3d on the bench's inputs: best and median times (ms)
  python profile_peer.py values  # manifold3d's volumes/areas on the inputs the kernel tests use
  python profile_peer.py openscad # OpenSCAD (Debian's openscad) on the same inputs: volumes of the STLs
  python profile_peer.py dxf     # ezdxf reads target/peers/profile/plate.dxf (written by
                                 # `cargo test -p blocksmith-kernel --lib -- --ignored write_peer_samples`)
                                 # and compares its contours with plate.txt
  python profile_peer.py dxf-blocks BLOCKSMITH  # ezdxf writes a drawing of blocks, a MINSERT array,
                                 # splines, ellipses and a mirrored arc; blocksmith (the binary given)
                                 # and ezdxf's own flattening (recursive_decompose, 1e-5) give its area

Run with ~/.cache/blocksmith-peers/venv/bin/python (ezdxf: pip install ezdxf into that venv).
"""
import math, os, statistics, sys, time

HERE = os.path.dirname(os.path.abspath(__file__))
SAMPLES = os.path.join(HERE, "..", "..", "target", "peers", "profile")


def timed(f, reps):
    ts = []
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t0)
    return min(ts) * 1e3, statistics.median(ts) * 1e3


def sphere_points(n):
    # The bench's linear congruential sequence, bit for bit.
    state = 0x2545F4914F6CDD1D
    mask = (1 << 64) - 1
    out = []

    def nxt():
        nonlocal state
        state = (state * 6364136223846793005 + 1442695040888963407) & mask
        return (state >> 11) / float(1 << 53)

    for _ in range(n):
        z = 2.0 * nxt() - 1.0
        a = 2.0 * math.pi * nxt()
        r = math.sqrt(1.0 - z * z)
        out.append((r * math.cos(a), r * math.sin(a), z))
    return out


def bench():
    from manifold3d import CrossSection, Manifold, JoinType

    def rect(x0, y0, x1, y1):
        return CrossSection([[(x0, y0), (x1, y0), (x1, y1), (x0, y1)]])

    c64 = CrossSection.circle(1.0, 64)
    disc = CrossSection.circle(0.5, 64).translate((2.0, 0.0))
    pts = sphere_points(100_000)
    million = sphere_points(1_000_000)
    ell = rect(0, 0, 2, 1) + rect(0, 0, 1, 2)
    prism = Manifold.extrude(ell, 1.0)
    ball = Manifold.sphere(0.2, 32)
    sq = rect(0, 0, 10, 10)
    cases = {
        "extrude_twist_64gon": (lambda: Manifold.extrude(c64, 2.0, 31, 90.0).num_tri(), 200),
        "revolve_torus_64x128": (lambda: Manifold.revolve(disc, 128, 360.0).num_tri(), 200),
        "hull_100k_sphere_points": (lambda: Manifold.hull_points(pts).num_tri(), 20),
        "hull_1m_sphere_points": (lambda: Manifold.hull_points(million).num_tri(), 5),
        "minkowski_l_prism_sphere": (lambda: prism.minkowski_sum(ball).num_tri(), 10),
        "offset_round_square": (lambda: sq.offset(1.0, JoinType.Round, 2.0, 32).area(), 500),
    }
    for name, (f, reps) in cases.items():
        best, med = timed(f, reps)
        print(f"PROFILE_PEER {name} best_ms={best:.3f} median_ms={med:.3f}")


def values():
    from manifold3d import CrossSection, Manifold, JoinType
    import math, time
    def rect(x0,y0,x1,y1): return CrossSection([[(x0,y0),(x1,y0),(x1,y1),(x0,y1)]])
    # twisted ring
    p = rect(-2,-2,2,2) - rect(-1,-1,1,1)
    m = Manifold.extrude(p, 2.0, n_divisions=17, twist_degrees=90.0)
    print("twist_ring volume", repr(m.volume()), "genus", m.genus())
    c64 = CrossSection.circle(1.0, 64)
    m = Manifold.extrude(c64, 2.0, n_divisions=31, twist_degrees=90.0)
    print("twist_c64 volume", repr(m.volume()))
    # frustum
    c40 = CrossSection.circle(1.5, 40)
    m = Manifold.extrude(c40, 3.0, n_divisions=0, scale_top=(1.7,1.7))
    print("frustum_c40 volume", repr(m.volume()))
    # annulus revolve
    m = Manifold.revolve(rect(1,0,2,1), 48, 360)
    print("annulus48 volume", repr(m.volume()), "genus", m.genus())
    # pappus
    disc = CrossSection.circle(0.5, 32).translate((2,0))
    m = Manifold.revolve(disc, 64, 360)
    print("pappus volume", repr(m.volume()))
    # partial revolve
    m = Manifold.revolve(rect(1,0,3,1), 8, 90)
    print("partial volume", repr(m.volume()))
    # hull cube corners
    pts=[(x,y,z) for x in (-1,1) for y in (-1,1) for z in (-1,1)]+[(0,0,0)]
    print("hull volume", Manifold.hull_points(pts).volume())
    # minkowski
    a = Manifold.cube((2,2,2), True)
    b = Manifold.cube((1,1,2)).translate((-0.5,0,0))
    print("mink boxes", a.minkowski_sum(b).volume())
    L = Manifold.extrude(rect(0,0,2,1) + rect(0,0,1,2), 1.0)
    print("mink L", repr(L.minkowski_sum(Manifold.cube((1,1,1), True)).volume()))
    # offsets
    s = rect(0,0,10,10)
    print("offset round32", repr(s.offset(1.0, JoinType.Round, 2.0, 32).area()))
    print("offset square", repr(s.offset(1.0, JoinType.Square).area()))
    print("offset miter", repr(s.offset(1.0, JoinType.Miter).area()))
    # split/trim
    cube = Manifold.cube((2,2,2), True)
    up, down = cube.split_by_plane((0,0,1), 0.5)
    print("split", up.volume(), down.volume())
    print("trim", cube.trim_by_plane((1,1,1), 0.0).volume())
    ring = Manifold.revolve(rect(1,0,2,1), 48, 360)
    print("slice ring", repr(ring.slice(0.5).area()))
    print("project box", Manifold.cube((3,2,1)).project().area())


OPENSCAD_CASES = {
    "text_hello_dejavu": 'linear_extrude(height=1) text("Hello", size=10, font="DejaVu Sans");',
    "extrude_twist_64gon": "linear_extrude(height=2, twist=90, slices=32) circle(r=1, $fn=64);",
    "frustum_40gon": "linear_extrude(height=3, scale=1.7) circle(r=1.5, $fn=40);",
    "annulus_48": "rotate_extrude($fn=48) translate([1,0]) square(1);",
    "offset_round_32": "linear_extrude(height=1) offset(r=1, $fn=32) square(10);",
    "minkowski_l_cube": "minkowski() { linear_extrude(height=1) union() { square([2,1]); square([1,2]); } cube(1, center=true); }",
}


def openscad():
    import subprocess, tempfile, trimesh

    with tempfile.TemporaryDirectory() as d:
        for name, src in OPENSCAD_CASES.items():
            scad, stl = os.path.join(d, name + ".scad"), os.path.join(d, name + ".stl")
            open(scad, "w").write(src + "\n")
            subprocess.run(["openscad", "-q", "-o", stl, scad], check=True)
            m = trimesh.load(stl)
            print(f"PROFILE_OPENSCAD {name} volume={m.volume!r} watertight={m.is_watertight} bounds={m.bounds.tolist()}")


def dxf():
    import ezdxf

    doc = ezdxf.readfile(os.path.join(SAMPLES, "plate.dxf"))
    audit = doc.audit()
    polys = [e for e in doc.modelspace() if e.dxftype() == "POLYLINE"]
    ours = [line.split() for line in open(os.path.join(SAMPLES, "plate.txt")) if line.strip()]
    assert len(polys) == len(ours), (len(polys), len(ours))
    worst = 0.0
    for p, (n, area) in zip(polys, ours):
        pts = [(v.dxf.location.x, v.dxf.location.y) for v in p.vertices]
        a = 0.5 * sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1] for i in range(len(pts)))
        assert p.is_closed and len(pts) == int(n), (p.is_closed, len(pts), n)
        worst = max(worst, abs(a - float(area)))
    print(f"PROFILE_DXF ezdxf={ezdxf.__version__} audit_errors={len(audit.errors)} contours={len(polys)} closed=all max_area_diff={worst:.3e}")


def dxf_blocks():
    """A plate of blocks as CAD programs write it, read by blocksmith and by ezdxf."""
    import subprocess
    import ezdxf
    from ezdxf import disassemble, path as ezpath

    doc = ezdxf.new("R2010")
    hole = doc.blocks.new("HOLE", base_point=(1, 1))
    hole.add_circle((1, 1), 0.6)
    slot = doc.blocks.new("SLOT")
    slot.add_line((0, 0), (3, 0))
    slot.add_arc((3, 0.5), 0.5, 270, 90)
    slot.add_line((3, 1), (0, 1))
    slot.add_arc((0, 0.5), 0.5, 90, 270)
    pair = doc.blocks.new("PAIR")  # a block placing another, scaled
    pair.add_blockref("HOLE", (0, 0), dxfattribs={"xscale": 0.5, "yscale": 0.5})
    pair.add_blockref("HOLE", (2, 0), dxfattribs={"xscale": 0.5, "yscale": 0.5})
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (40, 0), (40, 25), (0, 25)], close=True)
    msp.add_blockref("HOLE", (4, 4)).grid(size=(3, 4), spacing=(5, 6))  # a MINSERT, rows x columns
    msp.add_blockref("SLOT", (26, 4), dxfattribs={"rotation": 30})
    msp.add_blockref("PAIR", (26, 18))
    msp.add_ellipse((34, 12), major_axis=(2.5, 1.0), ratio=0.4)
    msp.add_spline_control_frame([(28, 21), (31, 23.5), (35, 21), (37, 23), (33, 24.5), (28, 23)]).closed = True
    msp.add_open_spline([(22, 10), (23, 13), (25, 11), (22, 10)], degree=3)
    msp.add_circle((-30, 8), 1.2, dxfattribs={"extrusion": (0, 0, -1)})  # at x = 30 once mirrored
    path_dxf = os.path.join(SAMPLES, "blocks.dxf")
    os.makedirs(SAMPLES, exist_ok=True)
    doc.saveas(path_dxf)

    def area(pts):
        return 0.5 * sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1] for i in range(len(pts)))

    # ezdxf's reading: every entity decomposed (blocks placed) and flattened to within 1e-5.
    rings = []
    for e in disassemble.recursive_decompose(doc.modelspace()):
        if e.dxftype() in ("LWPOLYLINE", "CIRCLE", "ARC", "ELLIPSE", "SPLINE", "LINE"):
            rings.append((e.dxftype(), [(v.x, v.y) for v in ezpath.make_path(e).flattening(1e-5)]))
    closed = [abs(area(p)) for kind, p in rings if kind in ("LWPOLYLINE", "CIRCLE", "ELLIPSE", "SPLINE") and len(p) > 2]
    plate = max(closed)
    # The slot's lines and arcs close one contour: its area is a 3 x 1 rectangle and a unit disc.
    slot_area = 3.0 + math.pi * 0.25
    peer = plate - (sum(closed) - plate) - slot_area
    recipe = os.path.join(SAMPLES, "blocks_area.rhai")
    with open(recipe, "w") as f:
        f.write('let p = load("blocks.dxf"); print(`${p.area()} ${p.contours().len()}`);\n')
    out = subprocess.run([sys.argv[2], "run", recipe], capture_output=True, text=True, check=True).stdout.split()
    ours, contours = float(out[0]), int(out[1])
    print(
        f"PROFILE_DXF_BLOCKS ezdxf={ezdxf.__version__} contours ours={contours} (1 plate + 12 + 2 holes + slot + ellipse + 2 splines + arc = 20)"
        f" area ours={ours:.6f} ezdxf={peer:.6f} relative_diff={abs(ours - peer) / peer:.2e}"
    )


if __name__ == "__main__":
    {"bench": bench, "values": values, "openscad": openscad, "dxf": dxf, "dxf-blocks": dxf_blocks}[sys.argv[1] if len(sys.argv) > 1 else "bench"]()
