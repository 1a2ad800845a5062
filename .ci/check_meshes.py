#!/usr/bin/env python3
"""Independent check of every mesh the test suite wrote: trimesh must find each one closed.

Usage: python check_meshes.py DIR

Every .glb, .gltf, .obj, .stl, .ply and .3mf under DIR is loaded with trimesh (a peer the field trusts, not our own
reader), its vertices merged by position (normals and texture coordinates ignored, so a writer that
splits vertices for attributes still counts as one surface), and must be

  - watertight: every edge shared by exactly two faces,
  - winding-consistent: the two faces of every edge traverse it in opposite directions,
  - a volume: finite, with positive signed volume (outward-facing).

A file under a directory named `open/` is a mesh that is open on purpose (a test of open input): it is
loaded and counted, not checked. One line per failure, then `meshes: N passed, N failed, N open`; exit 1
on any failure. A .3mf is also read by lib3mf in strict mode, and any warning it gives is a failure.
"""
import pathlib
import sys
import urllib.parse

import trimesh
from trimesh.resolvers import FilePathResolver

SUFFIXES = {".glb", ".gltf", ".obj", ".stl", ".ply", ".3mf"}


class UriResolver(FilePathResolver):
    """Resolves a glTF buffer URI as the glTF spec says: percent-encoded (trimesh takes it verbatim)."""

    def get(self, name):
        return super().get(urllib.parse.unquote(name))


def meshes_of(path):
    """The meshes in one file, each with its node transforms applied."""
    loaded = trimesh.load(str(path), process=False, resolver=UriResolver(str(path)))
    if isinstance(loaded, trimesh.Scene):
        return [loaded.to_geometry()] if loaded.geometry else []
    return [loaded]


def strict_3mf_problems(path):
    """What lib3mf (the 3MF Consortium's reference library) finds in a 3MF file read in strict mode:
    any warning is a departure from the core or materials specification."""
    import lib3mf

    model = lib3mf.get_wrapper().CreateModel()
    reader = model.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromFile(str(path))
    return [f"lib3mf: {reader.GetWarning(i)[1]}" for i in range(reader.GetWarningCount())]


def problems_of(mesh):
    """What is wrong with one mesh, as short phrases (empty when nothing is)."""
    # The geometry alone: colours are checked by the tests that write them (and moving face
    # colours to merged vertices would need scipy).
    mesh = trimesh.Trimesh(vertices=mesh.vertices, faces=mesh.faces, process=False)
    mesh.merge_vertices(merge_tex=True, merge_norm=True)
    found = []
    if len(mesh.faces) == 0:
        return ["no faces"]
    if not mesh.is_watertight:
        found.append("not watertight")
    if not mesh.is_winding_consistent:
        found.append("winding not consistent")
    if found:
        return found
    volume = mesh.volume
    if not volume > 0:
        found.append(f"volume {volume:.6g} not positive")
    return found


def main(root):
    files = sorted(p for p in pathlib.Path(root).rglob("*") if p.suffix.lower() in SUFFIXES)
    passed = failed = skipped = 0
    for path in files:
        if "open" in path.relative_to(root).parts[:-1]:
            skipped += 1
            continue
        try:
            meshes = meshes_of(path)
            problems = [] if meshes else ["no mesh in the file"]
            for mesh in meshes:
                problems += problems_of(mesh)
            if path.suffix.lower() == ".3mf":
                problems += strict_3mf_problems(path)
        except Exception as error:  # a file trimesh cannot read is a failure, with its reason
            problems = [f"unreadable: {error}"]
        if problems:
            failed += 1
            print(f"FAIL {path}: {', '.join(problems)}")
        else:
            passed += 1
    print(f"meshes: {passed} passed, {failed} failed, {skipped} open")
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "target/test-output"))
