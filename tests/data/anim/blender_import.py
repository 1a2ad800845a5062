"""Imports an animated blocksmith .glb into Blender (bpy) and reports what it made: the
armature's bone count and the frame range of its action. Run with the bpy peer environment:

    ~/.cache/blocksmith-peers/venv-bpy/bin/python tests/data/anim/blender_import.py FILE.glb [JOINTS FRAMES]

Prints `BLENDER_IMPORT file=… armatures=… bones=… actions=… frame_start=… frame_end=…`; with
JOINTS and FRAMES given, exits 1 unless the armature has JOINTS bones and the action spans
FRAMES keys (frame_end − frame_start + 1, at the file's fps).
"""
import sys

import bpy

path = sys.argv[1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=path)
armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
bones = sum(len(a.data.bones) for a in armatures)
actions = list(bpy.data.actions)
start = min((a.frame_range[0] for a in actions), default=0)
end = max((a.frame_range[1] for a in actions), default=0)
print(f"BLENDER_IMPORT file={path} armatures={len(armatures)} bones={bones} actions={len(actions)} "
      f"frame_start={start:g} frame_end={end:g} fps={bpy.context.scene.render.fps}")
if len(sys.argv) >= 4:
    joints, frames = int(sys.argv[2]), int(sys.argv[3])
    ok = bones == joints and round(end - start) + 1 == frames
    sys.exit(0 if ok else 1)
