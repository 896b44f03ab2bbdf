"""pb4u for Blender: simulate a garment on an animated body with pb4u's neural cloth, from the
Physics properties, and play the result back as a cache on the garment (docs/blender.md).

One click exports the body's evaluated frames (armature, shape keys, any deformation) and the
garment at the first frame, runs `pb4u simulate` as a subprocess (progress in the status bar,
Esc cancels), and adds a Mesh Cache modifier (PC2) named "pb4u" to the garment; Blender builds
with USD can take the USD cache through a Mesh Sequence Cache instead.
"""

bl_info = {
    "name": "pb4u neural cloth",
    "author": "pb4u",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Physics > pb4u Cloth",
    "description": "Simulate a garment on an animated body with pb4u and load it back as a cache",
    "category": "Physics",
}

import os
import subprocess
import tempfile
import time

import bpy
import numpy as np

from . import exchange

MODIFIER_NAME = "pb4u"
# USD only where this Blender reads it (Debian's 3.4 is built without USD and Alembic).
CACHE_TYPES = [("PC2", "PC2 (Mesh Cache)", "A point cache on the garment's own vertices")] + (
    [("USD", "USD (Mesh Sequence Cache)", "A USD cache of the garment")] if bpy.app.build_options.usd else [])


def mesh_poll(_props, obj):
    return obj.type == "MESH"


class Pb4uSettings(bpy.types.PropertyGroup):
    garment: bpy.props.PointerProperty(name="Garment", type=bpy.types.Object, poll=mesh_poll,
                                       description="The cloth mesh, placed on the body at the first frame")
    body: bpy.props.PointerProperty(name="Body", type=bpy.types.Object, poll=mesh_poll,
                                    description="The animated body (a mesh with an armature, shape keys, ...); "
                                                "empty: the garment alone, under gravity")
    pin_group: bpy.props.StringProperty(name="Pins", description="Vertex group of the garment held on the body "
                                                                  "(each pinned vertex follows its nearest body vertex)")
    model: bpy.props.StringProperty(name="Model", subtype="FILE_PATH",
                                    description="pb4u model file (.h5); empty: the one pb4u ships")
    executable: bpy.props.StringProperty(name="pb4u", subtype="FILE_PATH",
                                         description="The pb4u executable; empty: pb4u on PATH")
    cache_dir: bpy.props.StringProperty(name="Cache", subtype="DIR_PATH", default="//pb4u_cache/",
                                        description="Folder for the exported meshes and simulate's output "
                                                    "(// is the .blend's folder; a temporary one for an unsaved file)")
    frame_start: bpy.props.IntProperty(name="Start", default=1, description="First frame (the garment's start state)")
    frame_end: bpy.props.IntProperty(name="End", default=60, description="Last simulated frame")
    threads: bpy.props.IntProperty(name="Threads", default=0, min=0, description="pb4u's threads (0: all cores)")
    cache_type: bpy.props.EnumProperty(name="Load as", items=CACHE_TYPES)


class SimulationJob:
    """One run: export, simulate (a subprocess), load. Each step raises RuntimeError with the
    sentence to show the user."""

    def __init__(self, context, settings):
        self.scene = context.scene
        self.settings = settings
        self.process = None
        self.seconds = {}

    # ---- checks and export ----

    def prepare(self):
        s = self.settings
        start = time.perf_counter()
        self.binary = exchange.find_pb4u(bpy.path.abspath(s.executable) if s.executable else "")
        if not self.binary:
            raise RuntimeError("pb4u executable not found: %s" % (
                "'%s' is not an executable file" % s.executable if s.executable else
                "put pb4u on PATH or set its path in the panel"))
        self.model = bpy.path.abspath(s.model) if s.model else exchange.shipped_model(self.binary)
        if not self.model or not os.path.isfile(self.model):
            raise RuntimeError("model file not found: %s" % (self.model or "pb4u's shipped model (set Model)"))
        garment, body = s.garment, s.body
        if garment is None:
            raise RuntimeError("pick the garment mesh")
        if body is not None and body == garment:
            raise RuntimeError("the body and the garment are the same object")
        if s.frame_end <= s.frame_start:
            raise RuntimeError("the frame range is empty: End must be after Start")
        self.frames = s.frame_end - s.frame_start
        self.out_dir = bpy.path.abspath(s.cache_dir) if bpy.data.filepath or not s.cache_dir.startswith("//") \
            else tempfile.mkdtemp(prefix="pb4u_")
        self.sim_dir = os.path.join(self.out_dir, "simulate")
        os.makedirs(self.out_dir, exist_ok=True)
        exchange.remove_earlier_run(self.out_dir, self.sim_dir)
        self.log_path = os.path.join(self.out_dir, "simulate.log")

        frame_before = self.scene.frame_current
        try:
            self.scene.frame_set(s.frame_start)
            self.garment_matrix = np.array(garment.matrix_world, dtype=np.float64)
            positions, polygons = self.evaluated(garment, without_cache=True)
            self.check_garment(garment, positions, polygons)
            garment_obj = os.path.join(self.out_dir, "garment.obj")
            exchange.write_obj(garment_obj, exchange.blender_to_pb4u(positions), polygons)
            pinned = self.pinned_vertices(garment)
            body_pattern = ""
            if body is not None:
                body_pattern = os.path.join(self.out_dir, "body_%04d.obj")
                self.export_body(body, body_pattern)
        finally:
            self.scene.frame_set(frame_before)
        effects = ["gravity"] + (["collision", "friction"] if body is not None else []) + (["pins"] if pinned else [])
        self.scene_path = os.path.join(self.out_dir, "scene.yaml")
        with open(self.scene_path, "w") as f:
            f.write(exchange.scene_yaml(self.frames, garment_obj, body_pattern, pinned, effects))
        self.seconds["export"] = time.perf_counter() - start

    def evaluated(self, obj, without_cache=False, polygons=True):
        """World positions (n, 3) and (when asked) polygons of obj's evaluated mesh at the current frame."""
        cache = obj.modifiers.get(MODIFIER_NAME) if without_cache else None
        shown = cache.show_viewport if cache else None
        if cache:  # simulate from the garment itself, not from an earlier result
            cache.show_viewport = False
        try:
            depsgraph = bpy.context.evaluated_depsgraph_get()
            evaluated = obj.evaluated_get(depsgraph)
            mesh = evaluated.to_mesh()
            co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
            mesh.vertices.foreach_get("co", co)
            polygons = [tuple(p.vertices) for p in mesh.polygons] if polygons else None
            matrix = np.array(evaluated.matrix_world, dtype=np.float64)
            evaluated.to_mesh_clear()
        finally:
            if cache:
                cache.show_viewport = shown
        co = co.reshape(-1, 3).astype(np.float64)
        return co @ matrix[:3, :3].T + matrix[:3, 3], polygons

    def check_garment(self, garment, positions, polygons):
        name = garment.name
        if not polygons:
            raise RuntimeError("garment '%s' has no faces" % name)
        if len(positions) != len(garment.data.vertices):
            raise RuntimeError("garment '%s': its modifiers change its vertex count (%d -> %d); apply or remove them"
                               % (name, len(garment.data.vertices), len(positions)))
        used = np.zeros(len(positions), dtype=bool)
        for poly in polygons:
            used[list(poly)] = True
        if not used.all():
            raise RuntimeError("garment '%s': %d loose vertices (on no face); delete them (Mesh > Clean Up > Delete Loose)"
                               % (name, int((~used).sum())))
        if not np.isfinite(positions).all():
            raise RuntimeError("garment '%s' has non-finite vertex positions" % name)

    def pinned_vertices(self, garment):
        group_name = self.settings.pin_group
        if not group_name:
            return []
        group = garment.vertex_groups.get(group_name)
        if group is None:
            raise RuntimeError("garment '%s' has no vertex group '%s'" % (garment.name, group_name))
        pinned = [v.index for v in garment.data.vertices
                  if any(g.group == group.index and g.weight > 0 for g in v.groups)]
        if not pinned:
            raise RuntimeError("vertex group '%s' of '%s' holds no vertex" % (group_name, garment.name))
        return pinned

    def export_body(self, body, pattern):
        count = None
        for i, frame in enumerate(range(self.settings.frame_start, self.settings.frame_end + 1)):
            self.scene.frame_set(frame)
            positions, polygons = self.evaluated(body, polygons=(i == 0))
            if i == 0 and not polygons:
                raise RuntimeError("body '%s' has no faces" % body.name)
            if count is not None and len(positions) != count:
                raise RuntimeError("body '%s' changes its vertex count at frame %d (%d -> %d)"
                                   % (body.name, frame, count, len(positions)))
            count = len(positions)
            exchange.write_obj(pattern % i, exchange.blender_to_pb4u(positions), polygons if i == 0 else [])

    # ---- simulate ----

    def start(self):
        argv = [self.binary]
        if self.settings.threads:
            argv += ["--threads", str(self.settings.threads)]
        argv += ["simulate", "--checkpoint", self.model, "--scene", self.scene_path, "--out", self.sim_dir]
        self.started = time.perf_counter()
        self.log = open(self.log_path, "w")
        try:
            self.process = subprocess.Popen(argv, stdout=self.log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        except OSError as e:
            self.log.close()
            raise RuntimeError("could not start %s: %s" % (self.binary, e))

    def poll(self, wait=0.0):
        """None while simulate runs (after waiting up to `wait` s for it to end), else its exit status."""
        try:
            status = self.process.wait(timeout=wait) if wait > 0 else self.process.poll()
        except subprocess.TimeoutExpired:
            status = None
        if status is not None:
            self.seconds["simulate"] = time.perf_counter() - self.started
            self.log.close()
        return status

    def frames_done(self):
        return max(exchange.frames_written(self.sim_dir) - 1, 0)

    def cancel(self):
        if self.process and self.process.poll() is None:
            self.process.terminate()
            self.process.wait()
            self.log.close()

    # ---- load ----

    def load(self, status):
        if status != 0:
            raise RuntimeError("pb4u simulate failed: %s (log: %s)" % (exchange.last_error_line(self.log_path),
                                                                     self.log_path))
        start = time.perf_counter()
        garment = self.settings.garment
        frames = exchange.read_pc2(os.path.join(self.sim_dir, "garment.pc2")).astype(np.float64)
        if frames.shape[1] != len(garment.data.vertices):
            raise RuntimeError("simulate's cache has %d vertices, garment '%s' %d"
                               % (frames.shape[1], garment.name, len(garment.data.vertices)))
        # pb4u's world (y up) -> Blender world -> the garment's own space, where modifiers work.
        inverse = np.linalg.inv(self.garment_matrix)
        local = np.empty_like(frames)
        for t, x in enumerate(frames):
            world = exchange.pb4u_to_blender(x)
            local[t] = world @ inverse[:3, :3].T + inverse[:3, 3]
        use_usd = self.settings.cache_type == "USD" and bpy.app.build_options.usd
        for old in [m for m in garment.modifiers if m.name == MODIFIER_NAME]:
            garment.modifiers.remove(old)
        if use_usd:
            self.add_usd_cache(garment, local)
        else:
            path = os.path.join(self.out_dir, "garment_blender.pc2")
            exchange.write_pc2(path, local)
            modifier = garment.modifiers.new(MODIFIER_NAME, "MESH_CACHE")
            modifier.cache_format = "PC2"
            modifier.filepath = path
            modifier.frame_start = self.settings.frame_start
            modifier.frame_scale = 1.0
            modifier.play_mode = "SCENE"
            modifier.time_mode = "FRAME"
            modifier.deform_mode = "OVERWRITE"
            modifier.interpolation = "NONE"
        self.seconds["load"] = time.perf_counter() - start

    def add_usd_cache(self, garment, local):
        """The garment's frames (its own space, Blender's z up) as a one-mesh USD layer, read by
        a Mesh Sequence Cache (Blender builds with USD)."""
        path = os.path.join(self.out_dir, "garment_blender.usda")
        exchange.write_usda_mesh(path, "Garment", local, [tuple(p.vertices) for p in garment.data.polygons],
                                 self.settings.frame_start, self.scene.render.fps / self.scene.render.fps_base)
        cache_file = bpy.data.cache_files.load(path)
        modifier = garment.modifiers.new(MODIFIER_NAME, "MESH_SEQUENCE_CACHE")
        modifier.cache_file = cache_file
        modifier.object_path = "/Garment"
        modifier.read_data = {"VERT"}

    def summary(self):
        s = self.seconds
        return "pb4u: %d frames in %.2f s (export %.2f s, simulate %.2f s, load %.2f s)" % (
            self.frames, sum(s.values()), s.get("export", 0), s.get("simulate", 0), s.get("load", 0))


class PB4U_OT_simulate(bpy.types.Operator):
    """Simulate the garment on the body with pb4u and load the result as a cache"""
    bl_idname = "pb4u.simulate"
    bl_label = "Simulate with pb4u"
    bl_options = {"REGISTER"}

    _timer = None
    _job = None

    def finish(self, context, status):
        wm = context.window_manager
        try:
            self._job.load(status)
        except (RuntimeError, ValueError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        finally:
            wm.progress_end()
            if context.workspace:
                context.workspace.status_text_set(None)
        context.scene["pb4u_seconds"] = dict(self._job.seconds)
        self.report({"INFO"}, self._job.summary())
        return {"FINISHED"}

    def begin(self, context):
        self._job = SimulationJob(context, context.scene.pb4u)
        try:
            self._job.prepare()
            self._job.start()
        except (RuntimeError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return False
        context.window_manager.progress_begin(0, self._job.frames)
        return True

    def show_progress(self, context):
        done = self._job.frames_done()
        context.window_manager.progress_update(done)
        if context.workspace:
            context.workspace.status_text_set("pb4u: frame %d of %d (Esc cancels)" % (done, self._job.frames))

    def execute(self, context):  # scripts and background mode: run to the end
        if not self.begin(context):
            return {"CANCELLED"}
        while (status := self._job.poll(wait=0.1)) is None:
            self.show_progress(context)
        return self.finish(context, status)

    def invoke(self, context, event):  # a click: run in the background, the UI stays live
        if not self.begin(context):
            return {"CANCELLED"}
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.2, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._job.cancel()
            self.cleanup(context)
            self.report({"WARNING"}, "pb4u simulate cancelled")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        status = self._job.poll()
        if status is None:
            self.show_progress(context)
            return {"RUNNING_MODAL"}
        self.cleanup(context)
        return self.finish(context, status)

    def cleanup(self, context):
        context.window_manager.event_timer_remove(self._timer)
        context.window_manager.progress_end()
        if context.workspace:
            context.workspace.status_text_set(None)


class PHYSICS_PT_pb4u(bpy.types.Panel):
    bl_label = "pb4u Cloth"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"

    def draw(self, context):
        s = context.scene.pb4u
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "garment")
        layout.prop(s, "body")
        if s.garment:
            layout.prop_search(s, "pin_group", s.garment, "vertex_groups")
        col = layout.column(align=True)
        col.prop(s, "frame_start")
        col.prop(s, "frame_end")
        layout.prop(s, "model")
        if not s.model:
            layout.label(text="Model: the shipped pb4u.h5", icon="INFO")
        layout.prop(s, "executable")
        layout.prop(s, "cache_dir")
        layout.prop(s, "threads")
        layout.prop(s, "cache_type")
        layout.operator(PB4U_OT_simulate.bl_idname, icon="MOD_CLOTH")


CLASSES = (Pb4uSettings, PB4U_OT_simulate, PHYSICS_PT_pb4u)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.pb4u = bpy.props.PointerProperty(type=Pb4uSettings)


def unregister():
    del bpy.types.Scene.pb4u
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
