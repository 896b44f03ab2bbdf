"""The pictures of docs/blender.md and the README: Blender's window with the pb4u Cloth panel
and the simulated tube on the demo body (a screenshot), and a Workbench render of the cloth
on the body at three frames. Needs a display; headless, under Xvfb:

  xvfb-run -a -s "-screen 0 1500x1100x24" blender --factory-startup --enable-event-simulate \
      --python scripts/blender/docs_images.py -- --pb4u build/pb4u --out docs/img
"""

import argparse
import os
import shutil
import sys
import tempfile

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import demo_scene  # noqa: E402

args = argparse.ArgumentParser()
args.add_argument("--pb4u", required=True)
args.add_argument("--out", required=True)
args.add_argument("--frames", type=int, default=45)
args = args.parse_args(sys.argv[sys.argv.index("--") + 1:])
OUT = os.path.abspath(args.out)
SHOWN = (1, args.frames // 2 + 1, args.frames + 1)  # the frames of the render
WORK = tempfile.mkdtemp(prefix="pb4u_docs_")  # the add-on's cache and the single frames; removed at the end


def colour(obj, rgba):
    obj.color = rgba
    material = bpy.data.materials.new(obj.name)
    material.diffuse_color = rgba
    obj.data.materials.append(material)


def quit_on_error(step):
    def run():
        try:
            step()
        except Exception:
            import traceback
            traceback.print_exc()
            shutil.rmtree(WORK, ignore_errors=True)
            bpy.ops.wm.quit_blender()
    return run


@quit_on_error
def simulate_and_set_up_the_window():
    window = bpy.context.window_manager.windows[0]
    window.event_simulate(type="ESC", value="PRESS")  # closes the splash screen
    window.event_simulate(type="ESC", value="RELEASE")
    with bpy.context.temp_override(window=window, screen=window.screen):  # timers run without one
        garment, body = demo_scene.build(args.frames, 32, args.pb4u, threads=0,
                                         cache_dir=os.path.join(WORK, "cache"))
        bpy.ops.pb4u.simulate()
    colour(garment, (0.85, 0.33, 0.22, 1))
    colour(body, (0.75, 0.75, 0.78, 1))
    bpy.context.scene.frame_set(args.frames + 1)
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == "PROPERTIES":
            area.spaces.active.context = "PHYSICS"
        if area.type == "VIEW_3D":
            space = area.spaces.active
            space.shading.type = "SOLID"
            space.shading.color_type = "OBJECT"
            space.overlay.show_floor = True
            region = next(r for r in area.regions if r.type == "WINDOW")
            with bpy.context.temp_override(window=window, area=area, region=region):
                bpy.ops.object.select_all(action="SELECT")
                bpy.ops.view3d.view_axis(type="FRONT")
                bpy.ops.view3d.view_selected()
                bpy.ops.object.select_all(action="DESELECT")
            garment.select_set(True)
            bpy.context.view_layer.objects.active = garment
    bpy.app.timers.register(screenshot_and_render, first_interval=2.0)  # once the window has redrawn


@quit_on_error
def screenshot_and_render():
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.screen.screenshot(filepath=os.path.join(OUT, "blender_panel.png"))
    render_frames()
    shutil.rmtree(WORK, ignore_errors=True)
    bpy.ops.wm.quit_blender()


def render_frames():
    """Three frames side by side: a Workbench render per frame, then one strip (PNG)."""
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.color_type = "OBJECT"
    scene.display.shading.light = "STUDIO"
    scene.render.resolution_x, scene.render.resolution_y = 420, 560
    scene.render.film_transparent = False
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.9, -2.2, 1.35)
    camera.rotation_euler = (1.5708, 0, 0.3876)
    camera.data.lens = 50
    scene.camera = camera
    images = []
    for frame in SHOWN:
        scene.frame_set(frame)
        path = os.path.join(WORK, "frame_%04d.png" % frame)
        scene.render.filepath = path
        bpy.ops.render.render(write_still=True)
        images.append(bpy.data.images.load(path))
    width, height = images[0].size
    strip = bpy.data.images.new("strip", width * len(images), height)
    pixels = [0.0] * (4 * width * len(images) * height)
    for k, image in enumerate(images):
        src = list(image.pixels)
        for y in range(height):
            row = src[4 * width * y:4 * width * (y + 1)]
            start = 4 * (width * len(images) * y + width * k)
            pixels[start:start + 4 * width] = row
    strip.pixels = pixels
    strip.filepath_raw = os.path.join(OUT, "blender_cloth_frames.png")
    strip.file_format = "PNG"
    strip.save()


bpy.app.timers.register(simulate_and_set_up_the_window, first_interval=1.0)
