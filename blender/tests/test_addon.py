"""Headless test of the exao Blender add-on (CTest blender_addon):

    blender -b --factory-startup --python-use-system-env --python-exit-code 1 \
        --python blender/tests/test_addon.py -- build/blender/exao_bake.zip build/cli/exao

Installs the add-on from its zip and enables it, builds a scene (a ground plane, a flat-shaded
cube, a smooth sphere under a subdivision modifier, all transformed), bakes, and checks:
 - the color attributes equal `exao query` on the same world-space points and normals, exactly
   (per vertex for the smooth sphere, per face corner for the flat cube);
 - "Only Local" leaves the cube lighter where the ground occluded it;
 - an image bake is non-blank where the cube has UVs, its margin reaches past the islands, and
   rasterising the UV triangles in other batches gives the same image.
Any failed check raises, and --python-exit-code 1 makes blender exit 1."""

import os
import subprocess
import sys
import tempfile

import bpy
import numpy as np

zip_path, exao_binary = sys.argv[sys.argv.index("--") + 1:][:2]

bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
bpy.ops.preferences.addon_enable(module="exao_bake")
import exao_bake  # noqa: E402  (installed just now)

assert exao_bake.backend_name() == "exao Python module", exao_bake.backend_name()

# --- The scene ---------------------------------------------------------------------------------
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_enable(module="exao_bake")
bpy.ops.mesh.primitive_plane_add(size=8, location=(0, 0, 0))
plane = bpy.context.object
bpy.ops.mesh.primitive_cube_add(size=1, location=(0.4, 0.2, 0.5), rotation=(0, 0, 0.3))
cube = bpy.context.object
cube.scale = (1.0, 1.5, 1.0)
bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.6, location=(-0.8, 0.1, 0.55))
sphere = bpy.context.object
bpy.ops.object.shade_smooth()
sphere.modifiers.new("displace", "DISPLACE").strength = 0.05  # keeps the vertex count: bakeable per vertex
bpy.context.view_layer.update()

settings = bpy.context.scene.exao_bake
settings.samples = 128
settings.distance_mode = "UNITS"
settings.distance = 1.25
settings.falloff = "constant"
settings.target = "COLOR_ATTRIBUTE"
settings.attribute = "AO"


def bake(*objects):
    bpy.ops.object.select_all(action="DESELECT")
    for o in objects:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objects[0]
    assert bpy.ops.object.exao_bake_ao() == {"FINISHED"}


def attribute(obj):
    attr = obj.data.color_attributes["AO"]
    rgba = np.empty(len(attr.data) * 4, np.float32)
    attr.data.foreach_get("color", rgba)
    rgba = rgba.reshape(-1, 4)
    assert (rgba[:, 0] == rgba[:, 1]).all() and (rgba[:, 3] == 1).all()
    return attr.domain, rgba[:, 0]


# --- What the test computes itself: world-space geometry and receivers -------------------------
depsgraph = bpy.context.evaluated_depsgraph_get()


def world(obj):
    ev = obj.evaluated_get(depsgraph)
    me = ev.to_mesh()
    me.calc_loop_triangles()
    me.calc_normals_split()
    m = np.array(ev.matrix_world, np.float64)
    co = np.array([v.co for v in me.vertices], np.float32).astype(np.float64) @ m[:3, :3].T + m[:3, 3]
    nm = np.linalg.inv(m[:3, :3]).T
    vn = np.array([v.normal for v in me.vertices], np.float32).astype(np.float64) @ nm.T
    ln = np.array([l.normal for l in me.loops], np.float32).astype(np.float64) @ nm.T
    lv = np.array([l.vertex_index for l in me.loops])
    tris = np.array([t.vertices[:] for t in me.loop_triangles], np.int64)
    ev.to_mesh_clear()
    return co.astype(np.float32), vn.astype(np.float32), ln.astype(np.float32), lv, tris


tmp = tempfile.mkdtemp(prefix="exao-blender-test-")
geo = {o.name: world(o) for o in (plane, cube, sphere)}
verts, faces, base = [], [], 0
for co, _, _, _, tris in geo.values():
    verts.append(co)
    faces.append(tris + base)
    base += len(co)
verts, faces = np.concatenate(verts), np.concatenate(faces)
diagonal = float(np.linalg.norm(verts.max(0).astype(np.float64) - verts.min(0)))
offset = np.float32(1e-4 * diagonal)
obj_path = os.path.join(tmp, "scene.obj")
with open(obj_path, "w") as f:
    f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in verts.astype(np.float64).tolist())
    f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces.tolist())


def query(points, normals, keys):
    pts = os.path.join(tmp, "points.txt")
    with open(pts, "w") as f:
        f.writelines(f"{p[0]!r} {p[1]!r} {p[2]!r} {n[0]!r} {n[1]!r} {n[2]!r} {k}\n"
                     for p, n, k in zip(points.astype(np.float64).tolist(), normals.astype(np.float64).tolist(), keys))
    out = os.path.join(tmp, "ao.txt")
    subprocess.run([exao_binary, "query", obj_path, "--points", pts, "-o", out, "-n", "128",
                    "-r", repr(float(np.float32(1.25))), "--offset", repr(float(offset))], check=True, capture_output=True)
    return np.loadtxt(out, dtype=np.float32, ndmin=1)


# --- Color attributes equal exao query ---------------------------------------------------------
bake(cube, sphere)
for obj, expected_domain in ((sphere, "POINT"), (cube, "CORNER")):
    domain, baked = attribute(obj)
    assert domain == expected_domain, (obj.name, domain)
    co, vn, ln, lv, _ = geo[obj.name]
    if domain == "POINT":
        expected = query(co, vn, range(len(co)))
    else:
        expected = query(co[lv], ln, range(len(lv)))
    assert 0.0 < baked.min() < 1.0, f"{obj.name}: nothing partly occluded, the test would prove nothing"
    assert np.array_equal(baked, expected), (obj.name, np.abs(baked - expected).max(), (baked != expected).sum())
    print(f"exao add-on test: {obj.name}: {len(baked)} {domain.lower()} values equal exao query's")

# --- Only Local: the object alone occludes itself ----------------------------------------------
_, with_scene = attribute(cube)
settings.only_local = True
bake(cube)
_, alone = attribute(cube)
settings.only_local = False
assert (alone >= with_scene).all() and (alone > with_scene).any(), "only-local must drop the ground's occlusion"
assert (alone == 1.0).all(), "a convex box alone occludes none of its own corners"

# --- Ground plane: darkens the sphere's underside ----------------------------------------------
settings.ground = True
bake(sphere)
_, grounded = attribute(sphere)
settings.ground = False
bake(sphere)
_, ungrounded = attribute(sphere)
assert (grounded <= ungrounded).all(), "a ground plane only adds occlusion"

# --- Image on the active UV map, with a margin -------------------------------------------------
settings.target = "IMAGE"
settings.image_size = 64
settings.margin = 3
bake(cube)
image = bpy.data.images[f"{cube.name}_exao_AO"]
px = np.empty(64 * 64 * 4, np.float32)
image.pixels.foreach_get(px)
px = px.reshape(-1, 4)
covered = px[:, 3] > 0
assert covered.sum() > 64 * 64 // 8, f"only {covered.sum()} texels baked"
assert px[covered, 0].min() < 1.0 and px[covered, 0].max() > 0.0, "the baked image is blank"
# Rasterised in small batches (and every triangle as a "large" one), the texels are the same.
default_batch = exao_bake._TEXELS_PER_BATCH
for batch in (7, 1):
    exao_bake._TEXELS_PER_BATCH = batch
    bake(cube)
    again = np.empty(64 * 64 * 4, np.float32)
    bpy.data.images[f"{cube.name}_exao_AO"].pixels.foreach_get(again)
    assert np.array_equal(again.reshape(-1, 4), px), f"batches of {batch} texels change the image"
exao_bake._TEXELS_PER_BATCH = default_batch
settings.margin = 0
bake(cube)
px0 = np.empty(64 * 64 * 4, np.float32)
image = bpy.data.images[f"{cube.name}_exao_AO"]
image.pixels.foreach_get(px0)
assert (px0.reshape(-1, 4)[:, 3] > 0).sum() < covered.sum(), "the margin must extend the islands"
print("exao add-on test: all checks passed")
