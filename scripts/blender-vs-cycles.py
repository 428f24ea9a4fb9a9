"""exao's Blender add-on against Cycles' AO bake, in one Blender session, on the same mesh: a
per-vertex bake of Conference (or any OBJ or PLY) into a float color attribute. Not a test: it
prints both times, end to end (each includes Blender's own data access), the add-on's time split,
and how far the two bakes' values are apart, and why.

    blender -b --factory-startup --python-use-system-env --python scripts/blender-vs-cycles.py -- \
        ../shared/scenes/Conference/conference.obj [SAMPLES] [DISTANCE_PERCENT] [--ground] [--npz FILE]

Both bake per vertex (the mesh is shaded smooth, so every corner's normal is its vertex's) with
the same distance (a percentage of the mesh's bounding-box diagonal, in Blender units: the world's
AO distance for Cycles, the ray length for exao, constant falloff) and the same rays: both cast
SAMPLES cosine-weighted rays per vertex (Cycles' AO bake casts one AO ray per render sample; no
denoising, no adaptive sampling), Cycles' random per sample, exao's its stratified pattern.
--ground adds a plane just under the mesh (an occluder for both; not baked). --npz saves the
per-vertex values. PYTHONPATH must reach the exao module (build/python, or the installed one).

Where the two differ, it is where Cycles has no defined answer: Cycles bakes a vertex at the
corner of the first triangle that uses it (Blender's object_bake_api.c: "first triangle wins"),
taking front and back from that triangle, so a vertex whose first triangle has zero area, or
that no triangle uses, gets an arbitrary value (0 for a loose vertex). The script prints the
means over the vertices whose first triangle has an area, and over the others.
"""

import os
import sys
import time

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:]
path = args[0]
samples = int(args[1]) if len(args) > 1 and not args[1].startswith("--") else 128
percent = float(args[2]) if len(args) > 2 and not args[2].startswith("--") else 5.0
npz = args[args.index("--npz") + 1] if "--npz" in args else None
ground = "--ground" in args

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "blender"))
sys.path.insert(0, here)
import exao_bake  # noqa: E402
from cycles_ao import attribute_values, use_cycles_ao  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
exao_bake.register()

t = time.perf_counter()
if path.lower().endswith(".ply"):
    bpy.ops.import_mesh.ply(filepath=path)
else:
    bpy.ops.wm.obj_import(filepath=path)
obj = bpy.context.selected_objects[0]
for o in bpy.context.selected_objects[1:]:
    o.select_set(False)
bpy.context.view_layer.objects.active = obj
mesh = obj.data
mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), bool))
mesh.update()
print(f"{os.path.basename(path)}: {len(mesh.vertices)} vertices, {len(mesh.polygons)} faces, imported in {time.perf_counter() - t:.1f} s")

# The mesh in world space, as both bakes see it (the OBJ importer turns Y up into Z up).
bpy.context.view_layer.update()
world = exao_bake.EvaluatedMesh(obj, bpy.context.evaluated_depsgraph_get())
lo, hi = world.vertices.min(0).astype(np.float64), world.vertices.max(0).astype(np.float64)
diagonal = float(np.linalg.norm(hi - lo))
distance = percent * 0.01 * diagonal
if ground:
    # 3 diagonals wide, 2% of the diagonal under the lowest point (not touching the mesh).
    bpy.ops.mesh.primitive_plane_add(size=3 * diagonal, location=((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2] - 0.02 * diagonal))
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
print(f"distance {percent}% of the diagonal = {distance:.4g} Blender units, {samples} rays per vertex"
      + (", a ground plane under the mesh" if ground else ""))

# Both bakes start from an evaluated depsgraph, as in an interactive session (the first
# evaluation after the import, about 0.2 s, would otherwise be charged to whichever runs first).
bpy.context.view_layer.update()

# --- exao: the add-on's operator ------------------------------------------------------------
s = bpy.context.scene.exao_bake
s.target, s.attribute, s.samples = "COLOR_ATTRIBUTE", "exao_AO", samples
s.distance_mode, s.distance = "UNITS", distance
t = time.perf_counter()
assert bpy.ops.object.exao_bake_ao() == {"FINISHED"}
exao_seconds = time.perf_counter() - t
attr = mesh.color_attributes["exao_AO"]
assert attr.domain == "POINT"
exao_ao = attribute_values(attr)
split = dict(exao_bake.last_timings)
split["operator (undo step, reports)"] = exao_seconds - sum(split.values())
print(f"exao add-on ({exao_bake.backend_name()}): {exao_seconds:.2f} s = "
      + " + ".join(f"{k} {v:.2f} s" for k, v in split.items()))

# --- Cycles: bake type AO into a color attribute ----------------------------------------------
use_cycles_ao(bpy.context.scene, samples, distance)
cycles_attr = mesh.color_attributes.new("cycles_AO", "FLOAT_COLOR", "POINT")
mesh.color_attributes.active_color = cycles_attr
t = time.perf_counter()
result = bpy.ops.object.bake(type="AO", target="VERTEX_COLORS")
cycles_seconds = time.perf_counter() - t
assert result == {"FINISHED"}, result
cyc = attribute_values(mesh.color_attributes["cycles_AO"])
print(f"Cycles AO bake: {cycles_seconds:.2f} s")
print(f"exao is {cycles_seconds / exao_seconds:.1f}x faster; mean AO exao {exao_ao.mean():.4f}, Cycles {cyc.mean():.4f}, "
      f"mean |difference| {np.abs(exao_ao - cyc).mean():.4f}")

# --- Where they differ: the vertex's first triangle (Cycles bakes the vertex on it) -------------
v, f = world.vertices.astype(np.float64), world.faces.astype(np.int64)
area2 = np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
first = np.full(len(v), len(f))
np.minimum.at(first, f.ravel(), np.repeat(np.arange(len(f)), 3))
loose = first == len(f)
defined = ~loose & (area2[np.minimum(first, len(f) - 1)] > 0)
print(f"{(area2 == 0).sum()} of {len(f)} triangles have zero area; {loose.sum()} vertices are on no triangle")
for name, m in (("vertices whose first triangle has an area", defined),
                ("vertices whose first triangle has zero area", ~defined & ~loose), ("loose vertices", loose)):
    if m.any():
        print(f"  {name} ({m.sum()}): mean AO exao {exao_ao[m].mean():.4f}, Cycles {cyc[m].mean():.4f}, "
              f"mean |difference| {np.abs(exao_ao - cyc)[m].mean():.4f}")

if npz:
    normals = exao_bake.EvaluatedMesh(obj, bpy.context.evaluated_depsgraph_get()).vertex_normals()  # evaluated anew
    np.savez(npz, vertices=world.vertices, faces=world.faces, normals=normals, exao=exao_ao, cycles=cyc,
             distance=distance, samples=samples)
    print(f"-> {npz}")
