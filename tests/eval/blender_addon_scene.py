"""Headless run of the pb4u Blender add-on (tests/eval/blender_addon_test.cpp, and
scripts/blender/addon_overhead.sh for its timings):

  blender -b --factory-startup --python tests/eval/blender_addon_scene.py -- \
      --pb4u build/pb4u --out DIR [--frames 10] [--segments 16] [--threads 1] [--runs 1] [--errors]

builds the add-on's demo scene (scripts/blender/demo_scene.py: a skinned cylinder as the body,
an open tube pinned by its top ring as the garment), runs the add-on's operator and writes what Blender then shows on the garment at each frame, in pb4u's axes, as
DIR/blender_NNNN.obj (17 digits), beside the add-on's own DIR/cache/, and the same frames as
the USD layer a Blender with USD would load (DIR/garment_blender.usda). DIR/result.json: the
operator's timings per run and, with --errors, the messages of three failing runs (no pb4u
binary, a garment with a loose vertex, a model file that is not one).
"""

import argparse
import json
import os
import sys

import bpy
import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "blender"))
import demo_scene  # noqa: E402
from pb4u_addon import exchange  # noqa: E402


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
    garment, _ = demo_scene.build(args.frames, args.segments, args.pb4u, args.model, args.threads,
                                  os.path.join(os.path.abspath(args.out), "cache"))
    scene = bpy.context.scene
    settings = scene.pb4u

    result = {"runs": []}
    for _ in range(args.runs):
        error = run_operator()
        if error:
            print("pb4u add-on failed: " + error, file=sys.stderr)
            sys.exit(1)
        result["runs"].append(dict(scene["pb4u_seconds"]))
    modifier = garment.modifiers.get("pb4u")
    result["modifier"] = modifier.type if modifier else None
    # What a Blender with USD would load instead (Load as: USD): the same frames as a USD layer.
    local = exchange.read_pc2(os.path.join(args.out, "cache", "garment_blender.pc2"))
    exchange.write_usda_mesh(os.path.join(args.out, "garment_blender.usda"), "Garment", local,
                             [tuple(p.vertices) for p in garment.data.polygons], settings.frame_start, 24)
    for t, x in enumerate(shown_frames(garment, settings.frame_start, settings.frame_end)):
        with open(os.path.join(args.out, "blender_%04d.obj" % t), "w") as f:
            f.write("".join("v %.17g %.17g %.17g\n" % tuple(p) for p in x))

    if args.errors:
        errors = {}
        settings.cache_dir = os.path.join(os.path.abspath(args.out), "errors")  # the run above stays
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
