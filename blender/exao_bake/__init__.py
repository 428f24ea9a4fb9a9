"""exao AO bake for Blender: exact ray-cast ambient occlusion (the exao engine) baked into the
selected meshes' color attributes or an image on their active UV map, in place of Cycles' AO
bake. Panel: Properties > Render > "exao AO Bake" (under Cycles' Bake panel).

Occluders are every visible mesh (or, with "Only Local", the object alone), evaluated (modifiers
applied) and in world space. The AO comes from the `exao` Python module when Blender's Python
can import it (Debian's Blender runs the system Python 3.11), else from the `exao` command
(`exao query`), for Blender builds with a Python of their own.
"""

bl_info = {
    "name": "exao AO Bake",
    "author": "exao",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > exao AO Bake",
    "description": "Bake exact ray-cast ambient occlusion (exao) into color attributes or images",
    "category": "Render",
}

import os
import shutil
import subprocess
import tempfile

import bpy
import numpy as np

try:
    import exao as _exao_module
except ImportError:  # a Blender with its own Python: use the exao command instead
    _exao_module = None


def backend_name():
    if _exao_module is not None:
        return "exao Python module"
    exe = shutil.which("exao")
    return f"exao command ({exe})" if exe else "none (install exao: neither the module nor the command was found)"


# --- Geometry from Blender -----------------------------------------------------------------------


def _world_mesh(obj, depsgraph):
    """The evaluated mesh of `obj` (modifiers applied) in world space: positions (n, 3) float32,
    triangles (m, 3) uint32, the Mesh (caller frees it with obj_eval.to_mesh_clear()), obj_eval."""
    obj_eval = obj.evaluated_get(depsgraph)
    mesh = obj_eval.to_mesh()
    mesh.calc_loop_triangles()
    n = len(mesh.vertices)
    co = np.empty(n * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    m = np.array(obj_eval.matrix_world, np.float64)
    world = (co.reshape(n, 3).astype(np.float64) @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
    tris = np.empty(len(mesh.loop_triangles) * 3, np.uint32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return world, tris.reshape(-1, 3), mesh, obj_eval


def _normal_matrix(obj_eval):
    m = np.array(obj_eval.matrix_world, np.float64)[:3, :3]
    return np.linalg.inv(m).T


def occluders(context, only=None):
    """World-space triangles of every visible mesh object (or only `only`): (vertices, faces)."""
    depsgraph = context.evaluated_depsgraph_get()
    objects = [only] if only is not None else [o for o in context.view_layer.objects if o.type == "MESH" and o.visible_get()]
    verts, faces, base = [], [], 0
    for obj in objects:
        world, tris, _, obj_eval = _world_mesh(obj, depsgraph)
        obj_eval.to_mesh_clear()
        if len(tris):
            verts.append(world)
            faces.append(tris + base)
            base += len(world)
    if not faces:
        raise ValueError("no visible mesh with faces to occlude")
    return np.concatenate(verts), np.concatenate(faces)


def scene_diagonal(vertices):
    return float(np.linalg.norm(vertices.max(axis=0).astype(np.float64) - vertices.min(axis=0)))


def with_ground(vertices, faces, diagonal):
    """Adds a two-sided ground quad just below the lowest point along Blender's up axis (+Z):
    64 float ulps lower, so it does not exempt the model's bottom from occlusion (the exao
    program's --ground auto does the same along glTF's +Y), 100 diagonals wide."""
    z = np.float32(vertices[:, 2].min())
    for _ in range(64):
        z = np.nextafter(z, np.float32(-np.inf))
    c = (vertices.min(axis=0) + vertices.max(axis=0)) / 2
    s = np.float32(100 * diagonal)
    quad = np.float32([[c[0] - s, c[1] - s, z], [c[0] + s, c[1] - s, z], [c[0] + s, c[1] + s, z], [c[0] - s, c[1] + s, z]])
    base = len(vertices)
    return np.concatenate([vertices, quad]), np.concatenate([faces, np.uint32([[base, base + 1, base + 2], [base, base + 2, base + 3]])])


# --- Receivers -----------------------------------------------------------------------------------


def vertex_receivers(obj, depsgraph):
    """Receivers for a color attribute: per vertex (domain POINT) when every face corner's normal
    equals its vertex's, else per face corner (CORNER) with the corner's (split) normal.
    Returns (domain, points, normals, keys); keys are the vertex or corner index."""
    world, _, mesh, obj_eval = _world_mesh(obj, depsgraph)
    try:
        n = len(mesh.vertices)
        vn = np.empty(n * 3, np.float32)
        mesh.vertices.foreach_get("normal", vn)
        vn = vn.reshape(n, 3)
        mesh.calc_normals_split()
        loops = len(mesh.loops)
        ln = np.empty(loops * 3, np.float32)
        mesh.loops.foreach_get("normal", ln)
        ln = ln.reshape(loops, 3)
        lv = np.empty(loops, np.int64)
        mesh.loops.foreach_get("vertex_index", lv)
        nm = _normal_matrix(obj_eval)
        if np.array_equal(ln, vn[lv]):
            normals = (vn.astype(np.float64) @ nm.T).astype(np.float32)
            return "POINT", world, normals, np.arange(n, dtype=np.uint64)
        normals = (ln.astype(np.float64) @ nm.T).astype(np.float32)
        return "CORNER", world[lv], normals, np.arange(loops, dtype=np.uint64)
    finally:
        obj_eval.to_mesh_clear()


def texel_receivers(obj, depsgraph, size):
    """Receivers at the centres of the texels that the active UV map's triangles cover (the
    triangle that covers a texel centre last wins): (points, normals, texel indices y * size + x)."""
    world, _, mesh, obj_eval = _world_mesh(obj, depsgraph)
    try:
        if not mesh.uv_layers.active:
            raise ValueError(f"{obj.name}: has no UV map to bake an image on")
        loops = len(mesh.loops)
        uv = np.empty(loops * 2, np.float32)
        mesh.uv_layers.active.data.foreach_get("uv", uv)
        uv = uv.reshape(loops, 2)
        mesh.calc_normals_split()
        ln = np.empty(loops * 3, np.float32)
        mesh.loops.foreach_get("normal", ln)
        ln = (ln.reshape(loops, 3).astype(np.float64) @ _normal_matrix(obj_eval).T)
        lv = np.empty(loops, np.int64)
        mesh.loops.foreach_get("vertex_index", lv)
        tl = np.empty(len(mesh.loop_triangles) * 3, np.int64)
        mesh.loop_triangles.foreach_get("loops", tl)
        tl = tl.reshape(-1, 3)
    finally:
        obj_eval.to_mesh_clear()
    texel_of, points, normals = [], [], []
    for corners in tl:
        t = uv[corners].astype(np.float64) * size - 0.5  # texel centres at integer coordinates
        lo = np.maximum(np.floor(t.min(axis=0)).astype(int), 0)
        hi = np.minimum(np.ceil(t.max(axis=0)).astype(int), size - 1)
        if (hi < lo).any():
            continue
        xs, ys = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1))
        px, py = xs.ravel().astype(np.float64), ys.ravel().astype(np.float64)
        (x0, y0), (x1, y1), (x2, y2) = t
        det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2)
        if det == 0:
            continue
        b0 = ((y1 - y2) * (px - x2) + (x2 - x1) * (py - y2)) / det
        b1 = ((y2 - y0) * (px - x2) + (x0 - x2) * (py - y2)) / det
        b2 = 1 - b0 - b1
        inside = (b0 >= 0) & (b1 >= 0) & (b2 >= 0)
        if not inside.any():
            continue
        b = np.stack([b0[inside], b1[inside], b2[inside]], axis=1)
        p = world[lv[corners]].astype(np.float64)
        points.append(b @ p)
        normals.append(b @ ln[corners])
        texel_of.append(ys.ravel()[inside] * size + xs.ravel()[inside])
    if not points:
        raise ValueError(f"{obj.name}: its UV map covers no texel centre of a {size} x {size} image")
    return (np.concatenate(points).astype(np.float32), np.concatenate(normals).astype(np.float32),
            np.concatenate(texel_of).astype(np.int64))


def dilate(values, filled, size, margin):
    """Blender bake's margin: `margin` rings of texels around the covered ones take the mean of
    their covered (or already filled) 8-neighbours, so filtering shows no seams."""
    img = values.reshape(size, size).copy()
    mask = filled.reshape(size, size).copy()
    for _ in range(margin):
        total = np.zeros_like(img)
        count = np.zeros_like(img)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                if dx == 0 and dy == 0:
                    continue
                shifted_v = np.roll(np.roll(img * mask, dy, 0), dx, 1)
                shifted_m = np.roll(np.roll(mask.astype(np.float32), dy, 0), dx, 1)
                total += shifted_v
                count += shifted_m
        grow = (~mask) & (count > 0)
        if not grow.any():
            break
        img[grow] = total[grow] / count[grow]
        mask = mask | grow
    return img.ravel(), mask.ravel()


# --- AO: the module, or the exao command -------------------------------------------------------


def compute_ao(vertices, faces, points, normals, keys, samples, radius, offset, falloff, progress=None):
    """AO at the receivers: float32 (n,). radius and offset in scene units (float32)."""
    if _exao_module is not None:
        scene = _exao_module.Scene.from_arrays(vertices, faces)
        return scene.ao(points, normals, keys=keys, samples=samples, radius=float(radius), offset=float(offset),
                        falloff=falloff, progress=progress)
    exe = shutil.which("exao")
    if exe is None:
        raise RuntimeError("exao: neither the exao Python module nor the exao command is installed")
    with tempfile.TemporaryDirectory(prefix="exao-bake-") as tmp:
        obj_path, pts_path, out_path = (os.path.join(tmp, f) for f in ("scene.obj", "points.txt", "ao.txt"))
        write_obj(obj_path, vertices, faces)
        write_points(pts_path, points, normals, keys)
        subprocess.run([exe, "query", obj_path, "--points", pts_path, "-o", out_path, "-n", str(samples),
                        "-r", repr(float(radius)), "--offset", repr(float(offset)), "--falloff", falloff],
                       check=True, capture_output=True, text=True)
        return np.loadtxt(out_path, dtype=np.float32, ndmin=1)


def write_obj(path, vertices, faces):
    """An OBJ whose decimal vertices read back as exactly these float32 values."""
    with open(path, "w") as f:
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in vertices.astype(np.float64).tolist())
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces.tolist())


def write_points(path, points, normals, keys):
    with open(path, "w") as f:
        f.writelines(f"{p[0]!r} {p[1]!r} {p[2]!r} {n[0]!r} {n[1]!r} {n[2]!r} {k}\n"
                     for p, n, k in zip(points.astype(np.float64).tolist(), normals.astype(np.float64).tolist(), keys.tolist()))


# --- Blender UI -------------------------------------------------------------------------------


class ExaoBakeSettings(bpy.types.PropertyGroup):
    target: bpy.props.EnumProperty(
        name="Target", default="COLOR_ATTRIBUTE",
        items=[("COLOR_ATTRIBUTE", "Color Attribute", "Per vertex, or per face corner where normals are split"),
               ("IMAGE", "Image Texture", "An image on the active UV map")])
    attribute: bpy.props.StringProperty(name="Attribute", default="exao_AO", description="Color attribute to write (float color)")
    image_size: bpy.props.IntProperty(name="Image Size", default=1024, min=16, max=16384)
    margin: bpy.props.IntProperty(name="Margin", default=16, min=0, max=64, description="Texels the bake extends past UV islands")
    samples: bpy.props.IntProperty(name="Samples", default=128, min=32, max=1024, step=32,
                                   description="Rays per point: a multiple of 32 (rounded up)")
    distance_mode: bpy.props.EnumProperty(
        name="Distance", default="PERCENT",
        items=[("PERCENT", "% of Scene", "A percentage of the visible scene's bounding-box diagonal"),
               ("UNITS", "Blender Units", "A length")])
    distance: bpy.props.FloatProperty(name="Distance", default=1.0, min=1e-6, description="Ray length, Blender units")
    distance_percent: bpy.props.FloatProperty(name="Distance %", default=5.0, min=1e-4, max=1000.0, subtype="PERCENTAGE")
    falloff: bpy.props.EnumProperty(
        name="Falloff", default="constant",
        items=[("constant", "Constant", "Every ray as long as the distance (Cycles' AO)"),
               ("linear", "Linear", ""), ("quadratic", "Quadratic", "")])
    ground: bpy.props.BoolProperty(name="Ground Plane", default=False, description="An occluding plane under the scene (not written out)")
    only_local: bpy.props.BoolProperty(name="Only Local", default=False, description="The object alone occludes itself")


def _settings_radius(settings, diagonal):
    r = settings.distance if settings.distance_mode == "UNITS" else settings.distance_percent * 0.01 * diagonal
    return np.float32(r)


class EXAO_OT_bake_ao(bpy.types.Operator):
    """Bake exao ambient occlusion into the selected meshes"""

    bl_idname = "object.exao_bake_ao"
    bl_label = "Bake AO (exao)"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return any(o.type == "MESH" for o in context.selected_objects)

    def execute(self, context):
        settings = context.scene.exao_bake
        samples = max(32, min(1024, (settings.samples + 31) // 32 * 32))
        depsgraph = context.evaluated_depsgraph_get()
        wm = context.window_manager
        try:
            all_vertices, all_faces = occluders(context)
            diagonal = scene_diagonal(all_vertices)
            radius = _settings_radius(settings, diagonal)
            offset = np.float32(1e-4 * diagonal)  # the exao default, of the scene without the ground plane
            targets = [o for o in context.selected_objects if o.type == "MESH"]
            self.report({"INFO"}, f"exao: baking {len(targets)} object(s) with the {backend_name()}")
            wm.progress_begin(0, 100)
            for k, obj in enumerate(targets):
                vertices, faces = (all_vertices, all_faces) if not settings.only_local else occluders(context, only=obj)
                if settings.ground:
                    vertices, faces = with_ground(vertices, faces, diagonal)

                def progress(done, total, k=k):
                    wm.progress_update(100.0 * (k + (done / total if total else 1.0)) / len(targets))

                if settings.target == "COLOR_ATTRIBUTE":
                    self.bake_attribute(obj, depsgraph, vertices, faces, samples, radius, offset, settings, progress)
                else:
                    self.bake_image(obj, depsgraph, vertices, faces, samples, radius, offset, settings, progress)
        except (ValueError, OSError, RuntimeError, subprocess.CalledProcessError) as e:
            self.report({"ERROR"}, f"exao: {getattr(e, 'stderr', None) or e}")
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        return {"FINISHED"}

    def bake_attribute(self, obj, depsgraph, vertices, faces, samples, radius, offset, settings, progress):
        domain, points, normals, keys = vertex_receivers(obj, depsgraph)
        mesh = obj.data
        expected = len(mesh.vertices) if domain == "POINT" else len(mesh.loops)
        if len(points) != expected:
            raise ValueError(f"{obj.name}: its modifiers change the number of vertices; apply them to bake a color attribute")
        ao = compute_ao(vertices, faces, points, normals, keys, samples, radius, offset, settings.falloff, progress)
        attr = mesh.color_attributes.get(settings.attribute)
        if attr is not None and (attr.domain != domain or attr.data_type != "FLOAT_COLOR"):
            mesh.color_attributes.remove(attr)
            attr = None
        if attr is None:
            attr = mesh.color_attributes.new(settings.attribute, "FLOAT_COLOR", domain)
        rgba = np.ones((len(ao), 4), np.float32)
        rgba[:, :3] = ao[:, None]
        attr.data.foreach_set("color", rgba.ravel())
        mesh.color_attributes.active_color = attr
        mesh.update()
        self.report({"INFO"}, f"exao: {obj.name}: {len(ao)} {'vertices' if domain == 'POINT' else 'face corners'} -> {attr.name}")

    def bake_image(self, obj, depsgraph, vertices, faces, samples, radius, offset, settings, progress):
        size = settings.image_size
        points, normals, texels = texel_receivers(obj, depsgraph, size)
        ao = compute_ao(vertices, faces, points, normals, texels.astype(np.uint64), samples, radius, offset,
                        settings.falloff, progress)
        values = np.ones(size * size, np.float32)
        filled = np.zeros(size * size, bool)
        values[texels] = ao
        filled[texels] = True
        values, filled = dilate(values, filled, size, settings.margin)
        name = f"{obj.name}_exao_AO"
        image = bpy.data.images.get(name)
        if image is None or tuple(image.size) != (size, size):
            if image is not None:
                bpy.data.images.remove(image)
            image = bpy.data.images.new(name, size, size, alpha=True, float_buffer=True)
        rgba = np.ones((size * size, 4), np.float32)
        rgba[:, :3] = values[:, None]
        rgba[~filled, 3] = 0.0  # outside the islands and the margin: transparent, as Blender bakes leave it
        image.pixels.foreach_set(rgba.ravel())
        image.update()
        image.pack()
        self.report({"INFO"}, f"exao: {obj.name}: {len(texels)} texels -> image {image.name}")


class EXAO_PT_bake(bpy.types.Panel):
    bl_label = "exao AO Bake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        s = context.scene.exao_bake
        layout = self.layout
        layout.use_property_split = True
        layout.operator(EXAO_OT_bake_ao.bl_idname, icon="RENDER_STILL")
        layout.prop(s, "target")
        if s.target == "COLOR_ATTRIBUTE":
            layout.prop(s, "attribute")
        else:
            layout.prop(s, "image_size")
            layout.prop(s, "margin")
        layout.prop(s, "samples")
        layout.prop(s, "distance_mode")
        layout.prop(s, "distance" if s.distance_mode == "UNITS" else "distance_percent")
        layout.prop(s, "falloff")
        layout.prop(s, "ground")
        layout.prop(s, "only_local")
        layout.label(text=f"Engine: {backend_name()}")


classes = (ExaoBakeSettings, EXAO_OT_bake_ao, EXAO_PT_bake)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.exao_bake = bpy.props.PointerProperty(type=ExaoBakeSettings)


def unregister():
    del bpy.types.Scene.exao_bake
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
