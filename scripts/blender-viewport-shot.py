"""A screenshot of exao's bake in Blender's own viewport (for the README): imports a mesh (Conference
by default), bakes it with the add-on into the color attribute exao_AO, shows that attribute in
the 3D viewport (Solid shading, Attribute color, flat lighting: the AO alone) beside the add-on's
panel, and saves the whole window. Blender must run with a window; headless, Xvfb gives it one
(Mesa's llvmpipe draws it, no GPU):

    xvfb-run -a -s "-screen 0 1600x900x24" blender --factory-startup --python-use-system-env \\
        --python scripts/blender-viewport-shot.py -- ../shared/scenes/Conference/conference.obj \\
        docs/blender-viewport.png [SAMPLES] [DISTANCE_PERCENT]

PYTHONPATH must reach the exao module (build/python, or the installed one). Not a test.
"""

import math
import os
import sys

import bpy
import numpy as np
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
path, output = args[0], os.path.abspath(args[1])
samples = int(args[2]) if len(args) > 2 else 128
percent = float(args[3]) if len(args) > 3 else 5.0

# No splash screen over the viewport (the first start of a factory Blender shows one).
bpy.context.preferences.view.show_splash = False

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "blender"))
import exao_bake  # noqa: E402

exao_bake.EXAO_PT_bake.bl_options = set()  # the panel open in the picture
exao_bake.register()

# The default scene's cube, light and camera out; the mesh in.
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
bpy.ops.wm.obj_import(filepath=path)
obj = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = obj
mesh = obj.data
mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), bool))
mesh.update()
co = np.empty(len(mesh.vertices) * 3, np.float32)
mesh.vertices.foreach_get("co", co)
co = co.reshape(-1, 3)
diagonal = float(np.linalg.norm(co.max(0).astype(np.float64) - co.min(0)))

scene = bpy.context.scene
scene.view_settings.view_transform = "Standard"  # the attribute's values as they are (not Filmic's curve)
scene.render.engine = "BLENDER_WORKBENCH"  # the Render tab's shortest panel list: the add-on's panel shows
s = scene.exao_bake
s.target, s.attribute, s.samples = "COLOR_ATTRIBUTE", "exao_AO", samples
s.distance_mode, s.distance_percent = "PERCENT", percent
assert bpy.ops.object.exao_bake_ao() == {"FINISHED"}
print("exao: " + ", ".join(f"{k} {v:.2f} s" for k, v in exao_bake.last_timings.items()))


def view_and_shoot():
    window = bpy.context.window_manager.windows[0]
    screen = window.screen
    for area in screen.areas:
        if area.type == "VIEW_3D":
            space = area.spaces.active
            space.shading.type = "SOLID"
            space.shading.light = "FLAT"
            space.shading.color_type = "VERTEX"  # "Attribute": the active color attribute
            space.overlay.show_overlays = False
            space.show_gizmo = False
            space.lens = 18
            space.clip_start, space.clip_end = 1.0, 10 * diagonal
            # Conference's interior view (the README's exao render: eye -900,350,-950 -> 600,150,300,
            # Y up), in Blender's Z-up frame as the OBJ importer maps it: (x, y, z) -> (x, -z, y).
            eye, target = Vector((-900, 950, 350)), Vector((600, -300, 150))
            r3d = space.region_3d
            r3d.view_perspective = "PERSP"
            r3d.view_location = target
            r3d.view_rotation = (target - eye).to_track_quat("-Z", "Y")
            r3d.view_distance = (target - eye).length
        elif area.type == "PROPERTIES":
            area.spaces.active.context = "RENDER"
        area.tag_redraw()


def shoot_and_quit():
    window = bpy.context.window_manager.windows[0]
    # The Render tab's own panels fill the editor: scroll down to the add-on's panel, the last.
    for area in window.screen.areas:
        if area.type == "PROPERTIES":
            region = next(r for r in area.regions if r.type == "WINDOW")
            with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region):
                for _ in range(4):
                    bpy.ops.view2d.scroll_down(page=True)
    with bpy.context.temp_override(window=window, screen=window.screen):
        # Draw the window now (timers alone do not redraw it), then read it back.
        bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=2)
        bpy.ops.screen.screenshot(filepath=output)
    print(f"-> {output}")
    bpy.ops.wm.quit_blender()


bpy.app.timers.register(lambda: (view_and_shoot(), None)[1], first_interval=1.0)
bpy.app.timers.register(lambda: (shoot_and_quit(), None)[1], first_interval=4.0 + math.sqrt(len(mesh.vertices)) / 200)
