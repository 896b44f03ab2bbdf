"""Blender's cloth on a pb4u scene: the same garment, material, body motion and pins.

Run by Blender (3.x), not by Python:
  blender -b --factory-startup -P scripts/blender_cloth.py -- \
      --start garment_0000.obj --rest garment_rest.obj --frames 60 --out blender.pc2 \
      [--body body_0000.obj --body-cache body.pc2] [--pins pins.txt] \
      [--density 0.20022 --mu 23600 --lambda 44400 --thickness 4.7e-4 --bending 3.9625778e-5] \
      [--quality 5] [--fps 30] [--times times.csv]

Writes --out, a PC2 of frames 0..N in the OBJ's vertex order (frame 0 = --start), and
--times, the wall time of each frame's solve (ms). Coordinates are used as they are (pb4u's
y up; Blender's gravity is set to (0, -9.81, 0)), so nothing is rotated on the way in or out.
`pb4u score` measures the result with pb4u's energies; `pb4u bench` runs this per level.

Material mapping (pb4u SPEC 2 -> Blender's mass-spring cloth; printed at start):
- vertex mass (kg) = density * rest area / vertices (Blender gives every vertex the same mass);
- tension = compression = shear stiffness = (sqrt(3)/2) * Y * Lbar, where
  Y = h * 4 mu (lambda + mu) / (lambda + 2 mu) is the membrane's small-strain 2D Young modulus
  (N/m) and Lbar the mean rest edge length: Blender's linear spring force is
  stiffness / Lbar * (length - rest length), and a triangle lattice of springs of stiffness k
  has a 2D Young modulus of 2k / sqrt(3);
- bending stiffness = k_b / Lbar (Blender's angular bending springs are also divided by Lbar);
- rest lengths from --rest (a shape key used as the cloth's rest shape), start positions from
  --start; the cloth starts at rest (Blender takes no start velocity);
- body: a collision object animated by a Mesh Cache modifier reading --body-cache; collision
  distance 5 mm on both sides (pb4u's collision eps is 2 mm: Blender tunnels at that);
- pins: a vertex group "pin" used as the cloth's pin group (pin stiffness 1);
- damping, air drag and friction stay Blender's defaults: pb4u's model has none of the first
  two, so they add to the inertia term; self-collision off (pb4u has none).
"""
import argparse
import math
import struct
import sys
import time

import bpy


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="blender -b -P blender_cloth.py --")
    ap.add_argument("--start", required=True, help="garment at frame 0 (OBJ)")
    ap.add_argument("--rest", help="garment rest shape (OBJ, same vertex order); default: --start")
    ap.add_argument("--frames", type=int, required=True, help="frames to simulate after frame 0")
    ap.add_argument("--out", required=True, help="PC2 to write (frames 0..N)")
    ap.add_argument("--times", help="CSV of per-frame solve times (ms)")
    ap.add_argument("--body", help="body mesh at frame 0 (OBJ)")
    ap.add_argument("--body-cache", help="body frames 0..N (PC2, same vertex order as --body)")
    ap.add_argument("--pins", help="text file of pinned vertex indices (0-based, whitespace separated)")
    ap.add_argument("--density", type=float, default=0.20022)
    ap.add_argument("--mu", type=float, default=23600.0)
    ap.add_argument("--lambda", dest="lam", type=float, default=44400.0)
    ap.add_argument("--thickness", type=float, default=4.7e-4)
    ap.add_argument("--bending", type=float, default=3.9625778e-5)
    ap.add_argument("--quality", type=int, default=5, help="Blender's cloth steps per frame")
    ap.add_argument("--fps", type=float, default=30.0)
    ap.add_argument("--collision-distance", type=float, default=0.005)
    ap.add_argument("--stiffness-scale", type=float, default=1.0,
                    help="multiplies the mapped tension/compression/shear stiffness (to study the mapping)")
    return ap.parse_args(argv)


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                verts.append(tuple(float(c) for c in w[1:4]))
            elif w[0] == "f":
                idx = [int(c.split("/")[0]) for c in w[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(2, len(idx)):
                    faces.append((idx[0], idx[k - 1], idx[k]))
    return verts, faces


def read_pc2(path):
    with open(path, "rb") as f:
        head = f.read(32)
        if len(head) < 32 or head[:11] != b"POINTCACHE2":
            raise SystemExit(f"{path}: not a PC2 file")
        _, n, _, _, frames = struct.unpack("<iiffi", head[12:32])
    return n, frames


def write_pc2(path, frames, fps):
    n = len(frames[0]) if frames else 0
    with open(path, "wb") as f:
        f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, n, 0.0, 1.0, len(frames)))
        for verts in frames:
            f.write(struct.pack("<%df" % (3 * n), *[c for v in verts for c in v]))


def make_object(name, verts, faces):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def mean_edge_length_and_area(verts, faces):
    edges = set()
    area = 0.0
    for a, b, c in faces:
        for i, j in ((a, b), (b, c), (c, a)):
            edges.add((min(i, j), max(i, j)))
        u = [verts[b][k] - verts[a][k] for k in range(3)]
        w = [verts[c][k] - verts[a][k] for k in range(3)]
        cx = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        area += 0.5 * math.sqrt(sum(x * x for x in cx))
    length = sum(math.dist(verts[i], verts[j]) for i, j in edges) / max(len(edges), 1)
    return length, area


def main():
    a = parse_args()
    start, faces = read_obj(a.start)
    rest = read_obj(a.rest)[0] if a.rest else start
    if len(rest) != len(start):
        raise SystemExit(f"{a.rest}: {len(rest)} vertices, {a.start} {len(start)}")

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = int(round(a.fps))
    scene.render.fps_base = round(a.fps) / a.fps
    scene.gravity = (0.0, -9.81, 0.0)  # pb4u's y up, kept as is
    scene.frame_start, scene.frame_end = 1, a.frames + 1  # Blender frame 1 = pb4u frame 0

    cloth_obj = make_object("garment", start, faces)
    cloth_obj.shape_key_add(name="Basis")
    rest_key = cloth_obj.shape_key_add(name="Rest")
    for i, v in enumerate(rest):
        rest_key.data[i].co = v
    rest_key.value = 0.0

    lbar, area = mean_edge_length_and_area(rest, faces)
    young = a.thickness * 4 * a.mu * (a.lam + a.mu) / (a.lam + 2 * a.mu)
    stiffness = math.sqrt(3) / 2 * young * lbar * a.stiffness_scale
    mass = a.density * area / len(start)

    if a.body:
        body_verts, body_faces = read_obj(a.body)
        body = make_object("body", body_verts, body_faces)
        if a.body_cache:
            n, frames = read_pc2(a.body_cache)
            if n != len(body_verts):
                raise SystemExit(f"{a.body_cache}: {n} vertices, {a.body} {len(body_verts)}")
            if frames < a.frames + 1:
                raise SystemExit(f"{a.body_cache}: {frames} frames, {a.frames + 1} needed")
            cache = body.modifiers.new("motion", "MESH_CACHE")
            cache.cache_format = "PC2"
            cache.filepath = a.body_cache
            cache.frame_start = 1.0  # cache frame 0 at Blender frame 1
        body.modifiers.new("collision", "COLLISION")
        body.collision.thickness_outer = a.collision_distance
        body.collision.thickness_inner = 0.02
        body.collision.cloth_friction = 5.0

    cloth = cloth_obj.modifiers.new("cloth", "CLOTH")
    s = cloth.settings
    s.quality = a.quality
    s.mass = mass
    s.tension_stiffness = s.compression_stiffness = s.shear_stiffness = stiffness
    s.bending_stiffness = a.bending / lbar
    s.rest_shape_key = rest_key
    s.time_scale = 1.0
    cloth.collision_settings.use_collision = bool(a.body)
    cloth.collision_settings.distance_min = a.collision_distance
    cloth.collision_settings.use_self_collision = False
    cloth.point_cache.frame_start, cloth.point_cache.frame_end = 1, a.frames + 1
    if a.pins:
        with open(a.pins) as f:
            pinned = [int(w) for w in f.read().split()]
        group = cloth_obj.vertex_groups.new(name="pin")
        group.add(pinned, 1.0, "REPLACE")
        s.vertex_group_mass = "pin"
        s.pin_stiffness = 1.0
    print(f"blender_cloth: {len(start)} vertices, {len(faces)} triangles, Lbar {lbar * 1000:.2f} mm; "
          f"vertex mass {mass:.3e} kg, tension/compression/shear {stiffness:.4g}, bending {s.bending_stiffness:.4g}, "
          f"quality {a.quality}, body {'yes' if a.body else 'no'}, pins {len(pinned) if a.pins else 0}", flush=True)

    depsgraph = bpy.context.evaluated_depsgraph_get()
    frames, times = [], []
    for frame in range(1, a.frames + 2):
        t0 = time.perf_counter()
        scene.frame_set(frame)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = cloth_obj.evaluated_get(depsgraph)
        verts = [tuple(v.co) for v in evaluated.data.vertices]
        times.append((time.perf_counter() - t0) * 1000.0)
        frames.append(verts)
    write_pc2(a.out, frames, a.fps)
    if a.times:
        with open(a.times, "w") as f:
            f.write("frame,ms\n")
            for k, ms in enumerate(times):
                f.write(f"{k},{ms:.4f}\n")
    solves = sorted(times[1:])
    median = solves[len(solves) // 2] if solves else float("nan")
    print(f"blender_cloth: wrote {len(frames)} frames to {a.out}; median {median:.2f} ms per frame", flush=True)


if __name__ == "__main__":  # blender -P runs it as __main__; the add-on's test imports make_object
    main()
