"""The add-on's demo scene: a skinned cylinder as the body (two bones; the rig walks along x
while the upper bone leans up to 12 degrees) and an open tube around it as the garment,
pinned by its top ring ("waist"), with the pb4u Cloth panel filled in. The add-on's test,
scripts/blender/addon_overhead.sh and the pictures in docs/ are made from it. To try the
add-on on it in Blender's UI:

  blender --python scripts/blender/demo_scene.py -- --pb4u build/pb4u [--frames 60]

then Properties > Physics > pb4u Cloth > Simulate with pb4u.
"""

import argparse
import math
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.dirname(HERE)]
import pb4u_addon  # noqa: E402
from blender_cloth import make_object  # noqa: E402


def ring_mesh(name, radius, z0, z1, segments, rings, capped):
    """A cylinder along z of `rings` vertex rings, outward faces; capped: closed."""
    verts = [(radius * math.cos(2 * math.pi * s / segments), radius * math.sin(2 * math.pi * s / segments),
              z0 + (z1 - z0) * r / (rings - 1)) for r in range(rings) for s in range(segments)]
    faces = [(r * segments + s, r * segments + (s + 1) % segments, (r + 1) * segments + (s + 1) % segments,
              (r + 1) * segments + s) for r in range(rings - 1) for s in range(segments)]
    if capped:
        faces.append(tuple(reversed(range(segments))))
        faces.append(tuple((rings - 1) * segments + s for s in range(segments)))
    return make_object(name, verts, faces)


def skinned_body(segments, frames):
    """A capped cylinder (r 0.12 m, z 0.6-1.6 m) on a two-bone armature: the rig moves 2 mm a
    frame along x while the upper bone leans up to 12 degrees."""
    body = ring_mesh("Body", 0.12, 0.6, 1.6, segments, 11, capped=True)
    arm_data = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", arm_data)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    with bpy.context.temp_override(active_object=rig, object=rig):
        bpy.ops.object.mode_set(mode="EDIT")
    lower = arm_data.edit_bones.new("lower")
    lower.head, lower.tail = (0, 0, 0.6), (0, 0, 1.1)
    upper = arm_data.edit_bones.new("upper")
    upper.head, upper.tail = (0, 0, 1.1), (0, 0, 1.6)
    upper.parent = lower
    with bpy.context.temp_override(active_object=rig, object=rig):
        bpy.ops.object.mode_set(mode="OBJECT")
    groups = {name: body.vertex_groups.new(name=name) for name in ("lower", "upper")}
    for v in body.data.vertices:
        w = min(max((v.co.z - 1.0) / 0.2, 0.0), 1.0)  # a 20 cm blend around the joint
        groups["upper"].add([v.index], w, "REPLACE")
        groups["lower"].add([v.index], 1.0 - w, "REPLACE")
    body.modifiers.new("Armature", "ARMATURE").object = rig
    body.parent = rig  # the rig's walk carries the body; its bones bend it
    pose_upper = rig.pose.bones["upper"]
    pose_upper.rotation_mode = "XYZ"
    for frame in (1, frames + 1):
        t = (frame - 1) / frames
        rig.location = (0.002 * (frame - 1), 0, 0)
        rig.keyframe_insert("location", frame=frame)
        pose_upper.rotation_euler = (0, 0, math.radians(12) * t)  # about the bone's z: a lean along x
        pose_upper.keyframe_insert("rotation_euler", frame=frame)
    return body


def tube_garment(segments):
    """An open tube (r 0.15 m, z 1.15-1.45 m) around the body; its top ring is the "waist" group."""
    garment = ring_mesh("Garment", 0.15, 1.15, 1.45, segments, 7, capped=False)
    waist = garment.vertex_groups.new(name="waist")
    waist.add([v.index for v in garment.data.vertices if v.co.z > 1.449], 1.0, "REPLACE")
    return garment


def build(frames, segments, pb4u, model="", threads=0, cache_dir=""):
    """The body, the garment and the add-on's settings for them in an emptied scene; returns
    (garment, body)."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    if not hasattr(bpy.types.Scene, "pb4u"):
        pb4u_addon.register()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, frames + 1
    body = skinned_body(segments, frames)
    garment = tube_garment(segments)
    settings = scene.pb4u
    settings.garment, settings.body, settings.pin_group = garment, body, "waist"
    settings.frame_start, settings.frame_end = 1, frames + 1
    settings.executable = os.path.abspath(pb4u) if pb4u else ""
    settings.model = model
    settings.threads = threads
    if cache_dir:
        settings.cache_dir = cache_dir
    bpy.context.view_layer.objects.active = garment
    garment.select_set(True)
    return garment, body


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--pb4u", default="", help="the pb4u executable (default: pb4u on PATH)")
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--segments", type=int, default=32)
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    build(args.frames, args.segments, args.pb4u)
