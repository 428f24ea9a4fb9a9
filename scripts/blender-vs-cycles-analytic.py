"""exao's add-on and Cycles' AO bake against the analytic answer, in one Blender session: the
vertices of a 2 x 2 grid (21 x 21 vertices, facing +Z) under a 20 x 20 plane at height H, with AO
distance D. A ray of direction w leaves under the plane when H / cos(w, n) > D, so for
cosine-weighted rays of length D the AO is (H / D)^2, for uniform ones H / D. Not a test: it
prints both bakes' means over the inner vertices beside the two formulas.

    blender -b --factory-startup --python-use-system-env --python scripts/blender-vs-cycles-analytic.py -- \
        [H] [D] [SAMPLES] [--flip]

--flip turns the plane over (its back faces the grid): both count a triangle's back as an occluder.
PYTHONPATH must reach the exao module (build/python, or the installed one).
"""

import math
import os
import sys

import bpy
import numpy as np

args = [a for a in sys.argv[sys.argv.index("--") + 1:] if not a.startswith("--")]
h = float(args[0]) if len(args) > 0 else 0.5
d = float(args[1]) if len(args) > 1 else 1.0
samples = int(args[2]) if len(args) > 2 else 256

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "blender"))
sys.path.insert(0, here)
import exao_bake  # noqa: E402
from cycles_ao import attribute_values, use_cycles_ao  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
exao_bake.register()
bpy.ops.mesh.primitive_grid_add(x_subdivisions=20, y_subdivisions=20, size=2)
grid = bpy.context.object
bpy.ops.object.shade_smooth()
bpy.ops.mesh.primitive_plane_add(size=20, location=(0, 0, h))
if "--flip" in sys.argv:
    bpy.context.object.rotation_euler = (math.pi, 0, 0)
bpy.context.view_layer.update()


def select_grid():
    bpy.ops.object.select_all(action="DESELECT")
    grid.select_set(True)
    bpy.context.view_layer.objects.active = grid


def values(name):
    return attribute_values(grid.data.color_attributes[name])


s = bpy.context.scene.exao_bake
s.samples, s.distance_mode, s.distance, s.attribute = samples, "UNITS", d, "exao_AO"
select_grid()
assert bpy.ops.object.exao_bake_ao() == {"FINISHED"}

use_cycles_ao(bpy.context.scene, samples, d)
grid.data.color_attributes.active_color = grid.data.color_attributes.new("cycles_AO", "FLOAT_COLOR", "POINT")
select_grid()
assert bpy.ops.object.bake(type="AO", target="VERTEX_COLORS") == {"FINISHED"}

co = np.empty(len(grid.data.vertices) * 3, np.float32)
grid.data.vertices.foreach_get("co", co)
co = co.reshape(-1, 3)
inner = (np.abs(co[:, 0]) < 0.95) & (np.abs(co[:, 1]) < 0.95)
c = min(1.0, h / d)
print(f"H = {h}, D = {d}, {samples} rays: mean AO exao {values('exao_AO')[inner].mean():.4f}, "
      f"Cycles {values('cycles_AO')[inner].mean():.4f}; cosine-weighted (H/D)^2 = {c * c:.4f}, uniform H/D = {c:.4f}")
