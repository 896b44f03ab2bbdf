"""Headless run of the pb4u Blender add-on (tests/eval/blender_addon_test.cpp, and
scripts/blender/addon_overhead.sh for its timings):

  blender -b --factory-startup --python tests/eval/blender_addon_scene.py -- \
      --pb4u build/pb4u --out DIR [--frames 10] [--segments 16] [--threads 1] [--runs 1] [--errors]

builds a skinned cylinder (two bones, the upper one bending and the rig walking along x) as
the body and an open tube around it as the garment, pinned by its top ring, runs the add-on's
operator and writes what Blender then shows on the garment at each frame, in pb4u's axes, as
DIR/blender_NNNN.obj (17 digits), beside the add-on's own DIR/cache/. DIR/result.json: the
operator's timings per run and, with --errors, the messages of three failing runs (no pb4u
binary, a garment with a loose vertex, a model file that is not one).
"""

import argparse
import json
import math
import os
import sys

import bpy
import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path[:0] = [os.path.join(ROOT, "scripts", "blender"), os.path.join(ROOT, "scripts")]
import pb4u_addon  # noqa: E402
from blender_cloth import make_object  # noqa: E402
from pb4u_addon import exchange  # noqa: E402


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
    bpy.ops.object.mode_set(mode="EDIT")
    lower = arm_data.edit_bones.new("lower")
    lower.head, lower.tail = (0, 0, 0.6), (0, 0, 1.1)
    upper = arm_data.edit_bones.new("upper")
    upper.head, upper.tail = (0, 0, 1.1), (0, 0, 1.6)
    upper.parent = lower
    bpy.ops.object.mode_set(mode="OBJECT")
    groups = {name: body.vertex_groups.new(name=name) for name in ("lower", "upper")}
    for v in body.data.vertices:
        w = min(max((v.co.z - 1.0) / 0.2, 0.0), 1.0)  # a 20 cm blend around the joint
        groups["upper"].add([v.index], w, "REPLACE")
        groups["lower"].add([v.index], 1.0 - w, "REPLACE")
    body.modifiers.new("Armature", "ARMATURE").object = rig
    pose_upper = rig.pose.bones["upper"]
    pose_upper.rotation_mode = "XYZ"
    for frame in (1, frames + 1):
        t = (frame - 1) / frames
        rig.location = (0.002 * (frame - 1), 0, 0)
        rig.keyframe_insert("location", frame=frame)
        pose_upper.rotation_euler = (0, math.radians(12) * t, 0)
        pose_upper.keyframe_insert("rotation_euler", frame=frame)
    return body


def tube_garment(segments):
    """An open tube (r 0.15 m, z 1.15-1.45 m) around the body; its top ring is the "waist" group."""
    garment = ring_mesh("Garment", 0.15, 1.15, 1.45, segments, 7, capped=False)
    waist = garment.vertex_groups.new(name="waist")
    waist.add([v.index for v in garment.data.vertices if v.co.z > 1.449], 1.0, "REPLACE")
    return garment


def shown_frames(garment, first, last):
    """What the garment shows at each frame (its cache evaluated), world, pb4u axes."""
    frames = []
    for frame in range(first, last + 1):
        bpy.context.scene.frame_set(frame)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = garment.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        matrix = np.array(evaluated.matrix_world, dtype=np.float64)
        evaluated.to_mesh_clear()
        world = co.reshape(-1, 3).astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
        frames.append(exchange.blender_to_pb4u(world))
    return frames


def run_operator():
    """The operator's error message, or None when it finished."""
    try:
        bpy.ops.pb4u.simulate()
    except RuntimeError as e:
        return str(e).strip()
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pb4u", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--model", default="")
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("--segments", type=int, default=16)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--errors", action="store_true")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])

    bpy.ops.wm.read_factory_settings(use_empty=True)
    pb4u_addon.register()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, args.frames + 1
    body = skinned_body(args.segments, args.frames)
    garment = tube_garment(args.segments)
    settings = scene.pb4u
    settings.garment, settings.body, settings.pin_group = garment, body, "waist"
    settings.frame_start, settings.frame_end = 1, args.frames + 1
    settings.executable = os.path.abspath(args.pb4u)
    settings.model = args.model
    settings.threads = args.threads
    settings.cache_dir = os.path.join(os.path.abspath(args.out), "cache")

    result = {"runs": []}
    for _ in range(args.runs):
        error = run_operator()
        if error:
            print("pb4u add-on failed: " + error, file=sys.stderr)
            sys.exit(1)
        result["runs"].append(dict(scene["pb4u_seconds"]))
    modifier = garment.modifiers.get("pb4u")
    result["modifier"] = modifier.type if modifier else None
    for t, x in enumerate(shown_frames(garment, settings.frame_start, settings.frame_end)):
        with open(os.path.join(args.out, "blender_%04d.obj" % t), "w") as f:
            f.write("".join("v %.17g %.17g %.17g\n" % tuple(p) for p in x))

    if args.errors:
        errors = {}
        settings.executable = "/nonexistent/pb4u"
        errors["no_binary"] = run_operator()
        settings.executable = os.path.abspath(args.pb4u)
        loose = garment.copy()
        loose.data = garment.data.copy()
        loose.modifiers.clear()
        scene.collection.objects.link(loose)
        loose.data.vertices.add(1)
        settings.garment = loose
        errors["bad_mesh"] = run_operator()
        settings.garment = garment
        settings.model = os.path.join(ROOT, "README.md")
        errors["failed_run"] = run_operator()
        result["errors"] = errors
    with open(os.path.join(args.out, "result.json"), "w") as f:
        json.dump(result, f, indent=1)


main()
