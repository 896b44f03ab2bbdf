"""What the add-on hands to `pb4u simulate` and takes back, without bpy: meshes as OBJ,
the scene as YAML, point caches as PC2, and the axis change between Blender and pb4u.

Blender is z-up, pb4u y-up (metres both, with the scene's unit scale at 1). A Blender world
point (x, y, z) is the pb4u point (x, z, -y): the axes Blender's own OBJ exporter writes
with forward -Z, up Y.
"""

import glob
import os
import shutil
import struct

import numpy as np

PC2_MAGIC = b"POINTCACHE2\0"


def blender_to_pb4u(points):
    """(n, 3) Blender world positions -> pb4u positions (y up)."""
    p = np.asarray(points, dtype=np.float64)
    return np.stack([p[:, 0], p[:, 2], -p[:, 1]], axis=1)


def pb4u_to_blender(points):
    """(n, 3) pb4u positions (y up) -> Blender world positions (z up)."""
    p = np.asarray(points, dtype=np.float64)
    return np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)


def write_obj(path, points, polygons):
    """An OBJ of (n, 3) positions and polygons (sequences of 0-based vertex indices), the
    vertices in the given order (pb4u reads body frames and garment.keep_vertex_order in file
    order). Nine significant digits keep a float32 exactly."""
    lines = ["v %.9g %.9g %.9g" % (x, y, z) for x, y, z in np.asarray(points, dtype=np.float64)]
    lines += ["f " + " ".join(str(i + 1) for i in poly) for poly in polygons]
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines))
        f.write("\n")
    os.replace(tmp, path)


def write_pc2(path, frames, start_frame=0.0):
    """frames: (T, n, 3) positions, written as float32 with PC2's 32-byte header."""
    frames = np.ascontiguousarray(frames, dtype="<f4")
    count, n = frames.shape[0], frames.shape[1]
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(PC2_MAGIC + struct.pack("<iiffi", 1, n, float(start_frame), 1.0, count))
        f.write(frames.tobytes())
    os.replace(tmp, path)


def read_pc2(path):
    """A PC2 file as a (T, n, 3) float32 array. Raises ValueError naming the file."""
    with open(path, "rb") as f:
        head = f.read(32)
        if len(head) != 32 or head[:12] != PC2_MAGIC:
            raise ValueError("%s: not a PC2 point cache" % path)
        _, n, _, _, count = struct.unpack("<iiffi", head[12:])
        data = np.frombuffer(f.read(), dtype="<f4")
    if data.size != count * n * 3:
        raise ValueError("%s: PC2 size does not match its header" % path)
    return data.reshape(count, n, 3)


def write_usda_mesh(path, name, frames, polygons, start_frame, fps, up_axis="Z"):
    """A USD text layer holding one Mesh, /<name>, with its polygons and its (T, n, 3) frames
    as time-sampled float32 points at time codes start_frame, start_frame + 1, ..."""
    counts = ", ".join(str(len(p)) for p in polygons)
    indices = ", ".join(str(i) for p in polygons for i in p)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write('#usda 1.0\n(\n    defaultPrim = "%s"\n    metersPerUnit = 1\n    upAxis = "%s"\n'
                "    startTimeCode = %d\n    endTimeCode = %d\n    timeCodesPerSecond = %g\n"
                "    framesPerSecond = %g\n)\n\n" % (name, up_axis, start_frame, start_frame + len(frames) - 1, fps, fps))
        f.write('def Mesh "%s"\n{\n    uniform token subdivisionScheme = "none"\n' % name)
        f.write("    int[] faceVertexCounts = [%s]\n    int[] faceVertexIndices = [%s]\n" % (counts, indices))
        f.write("    point3f[] points.timeSamples = {\n")
        for t, x in enumerate(np.asarray(frames, dtype=np.float32)):
            f.write("        %d: [%s],\n" % (start_frame + t, ", ".join("(%.9g, %.9g, %.9g)" % tuple(p) for p in x)))
        f.write("    }\n}\n")
    os.replace(tmp, path)


def yaml_string(text):
    """A YAML double-quoted string (paths may hold spaces, quotes, colons)."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def scene_yaml(frames, garment_obj, body_pattern, pinned, effects):
    """The scene `pb4u simulate --scene` reads (configs/scenes/, docs/blender.md): the garment
    file in its vertex order, the body as a numbered OBJ sequence, pins riding on the body."""
    lines = [
        "# Written by the pb4u Blender add-on.",
        "frames: %d" % frames,
        "effects: [%s]" % ", ".join(effects),
        "garment: {source: file, file: %s, keep_vertex_order: true}" % yaml_string(garment_obj),
    ]
    if body_pattern:
        lines.append("body: {mesh_sequence: %s}" % yaml_string(body_pattern))
    if pinned:
        lines.append("pins: {vertices: [%s], on_body: %s}" % (", ".join(str(i) for i in pinned),
                                                             "true" if body_pattern else "false"))
    # What the add-on reads back (the PC2 cache; the OBJ frames show progress), plus the USD cache.
    lines.append("outputs: {mesh_format: obj, point_cache: true, usd: true, hdf5: false, "
                 "energies_csv: true, plot: false, preview: false}")
    return "\n".join(lines) + "\n"


def find_pb4u(setting):
    """The pb4u executable: the panel's path when set, else `pb4u` on PATH; None if neither."""
    if setting:
        path = os.path.abspath(os.path.expanduser(setting))
        return path if os.path.isfile(path) and os.access(path, os.X_OK) else None
    return shutil.which("pb4u")


def shipped_model(binary):
    """The model pb4u ships (data/pretrained/pb4u.h5) where pb4u itself finds its data:
    $PB4U_DATA_DIR, an installed <prefix>/share/pb4u, or the checkout holding build/pb4u."""
    here = os.path.dirname(os.path.realpath(binary))
    roots = [os.environ.get("PB4U_DATA_DIR", ""), os.path.join(here, "..", "share", "pb4u"),
             os.path.join(here, "..")]
    for root in roots:
        path = os.path.join(root, "data", "pretrained", "pb4u.h5")
        if root and os.path.isfile(path):
            return os.path.normpath(path)
    return None


def remove_earlier_run(out_dir, sim_dir):
    """Deletes what an earlier run left in the cache folder that a shorter run would not
    overwrite (its body frames and simulate's folder), and nothing else."""
    for path in glob.glob(os.path.join(glob.escape(out_dir), "body_[0-9][0-9][0-9][0-9].obj")):
        os.remove(path)
    if os.path.isdir(sim_dir):
        shutil.rmtree(sim_dir)


def frames_written(sim_dir):
    """How many garment frames simulate has written so far (it writes one OBJ per frame)."""
    return len(glob.glob(os.path.join(glob.escape(sim_dir), "garment_[0-9][0-9][0-9][0-9].obj")))


def last_error_line(log_path):
    """simulate's one-line reason for failing (`pb4u: error: ...`), or its last line."""
    try:
        with open(log_path, errors="replace") as f:
            lines = [line.strip() for line in f if line.strip()]
    except OSError:
        return "no output"
    errors = [line for line in lines if line.startswith("pb4u: error:")]
    return (errors or lines or ["no output"])[-1]
