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
import time

import bpy
import numpy as np

try:
    import exao as _exao_module
except ImportError:  # a Blender with its own Python: use the exao command instead
    _exao_module = None


# The last bake's time split, seconds: reading Blender's data ("data access": evaluated meshes,
# receivers, occluder arrays), the AO itself ("exao": the scene's BVH and the rays), writing the
# attribute or image ("write-back"). Reported in the status bar; scripts/blender-vs-cycles.py
# prints it.
last_timings = {}


def backend_name():
    if _exao_module is not None:
        return "exao Python module"
    exe = shutil.which("exao")
    return f"exao command ({exe})" if exe else "none (install exao: neither the module nor the command was found)"


# --- Geometry from Blender -----------------------------------------------------------------------
#
# Everything is read with foreach_get into numpy buffers of the property's own type (float32 for
# positions and normals, uint32 for a loop triangle's vertices): with any other dtype Blender
# converts item by item, several times slower. Each object is read once per bake, from its
# evaluated mesh (obj_eval.data: modifiers applied, no copy); only a mesh whose corner normals may
# differ from its vertex normals is copied (to_mesh), since split normals are computed into it.


def _matrix(obj_eval):
    """The object's world matrix (4 x 4 float64), or None when it is the identity."""
    m = np.array(obj_eval.matrix_world, np.float64)
    return None if np.array_equal(m, np.eye(4)) else m


def _to_world(co, m):
    return co if m is None else (co.astype(np.float64) @ m[:3, :3].T + m[:3, 3]).astype(np.float32)


def _normals_to_world(n, m):
    return n if m is None else (n.astype(np.float64) @ np.linalg.inv(m[:3, :3])).astype(np.float32)


class EvaluatedMesh:
    """One object's evaluated mesh (modifiers applied) in world space, read once: positions
    (n, 3) float32 and triangles (m, 3) uint32."""

    def __init__(self, obj, depsgraph):
        self.obj = obj
        self.obj_eval = obj.evaluated_get(depsgraph)
        self.mesh = self.obj_eval.data
        self.mesh.calc_loop_triangles()
        self.matrix = _matrix(self.obj_eval)
        n = len(self.mesh.vertices)
        co = np.empty(n * 3, np.float32)
        self.mesh.vertices.foreach_get("co", co)
        self.vertices = _to_world(co.reshape(n, 3), self.matrix)
        tris = np.empty(len(self.mesh.loop_triangles) * 3, np.uint32)
        self.mesh.loop_triangles.foreach_get("vertices", tris)
        self.faces = tris.reshape(-1, 3)

    def corner_normals_are_vertex_normals(self):
        """True when Blender's corner normals are its vertex normals by construction: every face
        smooth, no auto smooth, no custom normals. Otherwise the caller compares them."""
        me = self.mesh
        if me.has_custom_normals or me.use_auto_smooth:
            return False
        smooth = np.empty(len(me.polygons), bool)
        me.polygons.foreach_get("use_smooth", smooth)
        return bool(smooth.all())

    def vertex_normals(self):
        n = len(self.mesh.vertices)
        vn = np.empty(n * 3, np.float32)
        self.mesh.vertices.foreach_get("normal", vn)
        return _normals_to_world(vn.reshape(n, 3), self.matrix)

    def corners(self, uv=False):
        """Per face corner: vertex index (int32), normal (split, world space), and the active UV
        map's coordinates when uv; triangles as corner indices (m, 3) int32. Split normals are
        computed into a copy of the evaluated mesh (to_mesh), never into the depsgraph's."""
        me = self.obj_eval.to_mesh()
        try:
            me.calc_loop_triangles()
            me.calc_normals_split()
            loops = len(me.loops)
            ln = np.empty(loops * 3, np.float32)
            me.loops.foreach_get("normal", ln)
            lv = np.empty(loops, np.int32)
            me.loops.foreach_get("vertex_index", lv)
            tl = np.empty(len(me.loop_triangles) * 3, np.uint32)
            me.loop_triangles.foreach_get("loops", tl)
            uvs = None
            if uv:
                if not me.uv_layers.active:
                    raise ValueError(f"{self.obj.name}: has no UV map to bake an image on")
                uvs = np.empty(loops * 2, np.float32)
                me.uv_layers.active.data.foreach_get("uv", uvs)
                uvs = uvs.reshape(loops, 2)
        finally:
            self.obj_eval.to_mesh_clear()
        return lv, _normals_to_world(ln.reshape(loops, 3), self.matrix), tl.reshape(-1, 3).astype(np.int64), uvs


def occluder_arrays(evaluated):
    """World-space triangles of these EvaluatedMesh objects, one array pair: (vertices, faces)."""
    parts = [e for e in evaluated if len(e.faces)]
    if not parts:
        raise ValueError("no visible mesh with faces to occlude")
    if len(parts) == 1:
        return parts[0].vertices, parts[0].faces
    bases = np.cumsum([0] + [len(e.vertices) for e in parts[:-1]]).astype(np.uint32)
    return (np.concatenate([e.vertices for e in parts]),
            np.concatenate([e.faces + b for e, b in zip(parts, bases)]))


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


def vertex_receivers(evaluated):
    """Receivers for a color attribute: per vertex (domain POINT) when every face corner's normal
    equals its vertex's, else per face corner (CORNER) with the corner's (split) normal.
    Returns (domain, points, normals); the jitter key of each is its vertex or corner index."""
    vn = evaluated.vertex_normals()
    if evaluated.corner_normals_are_vertex_normals():
        return "POINT", evaluated.vertices, vn
    lv, ln, _, _ = evaluated.corners()
    if np.array_equal(ln, vn[lv]):
        return "POINT", evaluated.vertices, vn
    return "CORNER", evaluated.vertices[lv], ln


# Triangles whose texel bounding box is larger than this are rasterised one at a time; the
# others in batches of about this many candidate texels (bounded memory, no Python loop over
# the many small triangles).
_TEXELS_PER_BATCH = 1 << 22


def _cover(t, lo, hi, tri_ids):
    """The texel centres inside UV triangles t (k, 3, 2) (texel units, centres at integers) with
    bounding boxes lo..hi (k, 2) inclusive: (triangle id, x, y, barycentrics (j, 3))."""
    w = hi[:, 0] - lo[:, 0] + 1
    counts = w * (hi[:, 1] - lo[:, 1] + 1)
    which = np.repeat(np.arange(len(t)), counts)
    local = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    px = (lo[which, 0] + local % w[which]).astype(np.float64)
    py = (lo[which, 1] + local // w[which]).astype(np.float64)
    x0, y0 = t[which, 0, 0], t[which, 0, 1]
    x1, y1 = t[which, 1, 0], t[which, 1, 1]
    x2, y2 = t[which, 2, 0], t[which, 2, 1]
    det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2)
    with np.errstate(divide="ignore", invalid="ignore"):
        b0 = ((y1 - y2) * (px - x2) + (x2 - x1) * (py - y2)) / det
        b1 = ((y2 - y0) * (px - x2) + (x0 - x2) * (py - y2)) / det
    b2 = 1 - b0 - b1
    inside = (det != 0) & (b0 >= 0) & (b1 >= 0) & (b2 >= 0)
    return (tri_ids[which[inside]], px[inside].astype(np.int64), py[inside].astype(np.int64),
            np.stack([b0[inside], b1[inside], b2[inside]], axis=1))


def texel_receivers(evaluated, size):
    """Receivers at the centres of the texels that the active UV map's triangles cover (the
    triangle that covers a texel centre last wins): (points, normals, texel indices y * size + x)."""
    lv, ln, tl, uv = evaluated.corners(uv=True)
    t = uv[tl].astype(np.float64) * size - 0.5  # (m, 3, 2), texel centres at integer coordinates
    lo = np.maximum(np.floor(t.min(axis=1)).astype(np.int64), 0)
    hi = np.minimum(np.ceil(t.max(axis=1)).astype(np.int64), size - 1)
    keep = np.nonzero((hi >= lo).all(axis=1))[0]
    counts = np.prod(hi[keep] - lo[keep] + 1, axis=1)
    found = []
    big = counts > _TEXELS_PER_BATCH
    for i in keep[big]:  # the few large triangles, each vectorised on its own
        found.append(_cover(t[i:i + 1], lo[i:i + 1], hi[i:i + 1], np.array([i])))
    small, small_counts = keep[~big], counts[~big]
    batch = np.cumsum(small_counts) // _TEXELS_PER_BATCH
    for b in np.unique(batch):
        ids = small[batch == b]
        found.append(_cover(t[ids], lo[ids], hi[ids], ids))
    tri = np.concatenate([f[0] for f in found]) if found else np.empty(0, np.int64)
    if not len(tri):
        raise ValueError(f"{evaluated.obj.name}: its UV map covers no texel centre of a {size} x {size} image")
    texel = np.concatenate([f[2] * size + f[1] for f in found])
    bary = np.concatenate([f[3] for f in found])
    # The last triangle (in the mesh's order) that covers a texel wins: sort by triangle, keep
    # each texel's last occurrence.
    order = np.argsort(tri, kind="stable")
    tri, texel, bary = tri[order], texel[order], bary[order]
    _, last_reversed = np.unique(texel[::-1], return_index=True)
    pick = len(texel) - 1 - last_reversed
    tri, texel, bary = tri[pick], texel[pick], bary[pick]
    corners = tl[tri]  # (j, 3) corner indices
    p = evaluated.vertices[lv[corners]].astype(np.float64)  # (j, 3, 3)
    points = np.einsum("jk,jkd->jd", bary, p)
    normals = np.einsum("jk,jkd->jd", bary, ln[corners].astype(np.float64))
    return points.astype(np.float32), normals.astype(np.float32), texel


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


class Occluders:
    """The triangles that rays are cast against (world space) and, with the module, the exao
    Scene over them, built once and kept for every target that shares these occluders (its BVH
    is built on the first query and cached for the same options)."""

    def __init__(self, vertices, faces):
        self.vertices, self.faces = vertices, faces
        self._scene = None

    def ao(self, points, normals, keys, samples, radius, offset, falloff, progress=None):
        """AO at the receivers: float32 (n,). radius and offset in scene units (float32); keys
        None: 0 .. n-1 (the vertex or corner index)."""
        if _exao_module is not None:
            if self._scene is None:
                self._scene = _exao_module.Scene.from_arrays(self.vertices, self.faces)
            return self._scene.ao(points, normals, keys=keys, samples=samples, radius=float(radius),
                                  offset=float(offset), falloff=falloff, progress=progress)
        exe = shutil.which("exao")
        if exe is None:
            raise RuntimeError("exao: neither the exao Python module nor the exao command is installed")
        with tempfile.TemporaryDirectory(prefix="exao-bake-") as tmp:
            obj_path, pts_path, out_path = (os.path.join(tmp, f) for f in ("scene.obj", "points.txt", "ao.txt"))
            write_obj(obj_path, self.vertices, self.faces)
            write_points(pts_path, points, normals, np.arange(len(points)) if keys is None else keys)
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
        wm = context.window_manager
        timings = {"data access": 0.0, "exao": 0.0, "write-back": 0.0}
        clock = time.perf_counter
        started = clock()
        try:
            depsgraph = context.evaluated_depsgraph_get()
            visible = [o for o in context.view_layer.objects if o.type == "MESH" and o.visible_get()]
            targets = [o for o in context.selected_objects if o.type == "MESH"]
            # Each object read once: as an occluder and, when selected, for its receivers.
            evaluated = {o.name: EvaluatedMesh(o, depsgraph) for o in visible}
            for o in targets:
                if o.name not in evaluated:
                    evaluated[o.name] = EvaluatedMesh(o, depsgraph)
            scene_vertices, scene_faces = occluder_arrays([evaluated[o.name] for o in visible])
            diagonal = scene_diagonal(scene_vertices)
            radius = _settings_radius(settings, diagonal)
            offset = np.float32(1e-4 * diagonal)  # the exao default, of the scene without the ground plane

            def occluders_of(vertices, faces):
                return Occluders(*(with_ground(vertices, faces, diagonal) if settings.ground else (vertices, faces)))

            shared = None if settings.only_local else occluders_of(scene_vertices, scene_faces)
            timings["data access"] += clock() - started
            self.report({"INFO"}, f"exao: baking {len(targets)} object(s) with the {backend_name()}")
            # Every target's receivers read before anything is written: an evaluated mesh is only
            # valid until the depsgraph next updates.
            jobs = []
            for obj in targets:
                mesh_eval = evaluated[obj.name]
                occluders = shared or occluders_of(*occluder_arrays([mesh_eval]))
                if settings.target == "COLOR_ATTRIBUTE":
                    domain, points, normals = vertex_receivers(mesh_eval)
                    expected = len(obj.data.vertices) if domain == "POINT" else len(obj.data.loops)
                    if len(points) != expected:
                        raise ValueError(f"{obj.name}: its modifiers change the number of vertices; apply them to bake a color attribute")
                    jobs.append((obj, occluders, points, normals, None, domain))
                else:
                    points, normals, texels = texel_receivers(mesh_eval, settings.image_size)
                    jobs.append((obj, occluders, points, normals, texels, None))
            del evaluated
            timings["data access"] += clock() - started
            self.report({"INFO"}, f"exao: baking {len(targets)} object(s) with the {backend_name()}")
            wm.progress_begin(0, 100)
            for k, (obj, occluders, points, normals, texels, domain) in enumerate(jobs):

                def progress(done, total, k=k):
                    wm.progress_update(100.0 * (k + (done / total if total else 1.0)) / len(jobs))

                t = clock()
                keys = None if texels is None else texels.astype(np.uint64)
                ao = occluders.ao(points, normals, keys, samples, radius, offset, settings.falloff, progress)
                timings["exao"] += clock() - t
                t = clock()
                if texels is None:
                    self.write_attribute(obj, domain, ao, settings)
                else:
                    self.write_image(obj, texels, ao, settings)
                timings["write-back"] += clock() - t
        except (ValueError, OSError, RuntimeError, subprocess.CalledProcessError) as e:
            self.report({"ERROR"}, f"exao: {getattr(e, 'stderr', None) or e}")
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        last_timings.clear()
        last_timings.update(timings)
        self.report({"INFO"}, "exao: " + ", ".join(f"{k} {v:.2f} s" for k, v in timings.items()))
        return {"FINISHED"}

    def write_attribute(self, obj, domain, ao, settings):
        mesh = obj.data
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

    def write_image(self, obj, texels, ao, settings):
        size = settings.image_size
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
