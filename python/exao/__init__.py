"""exao: exact ray-cast ambient occlusion (Laine & Karras 2010), from Python.

    import numpy as np, exao
    scene = exao.Scene.open("conference.obj")          # or Scene.from_arrays(vertices, faces)
    ao = scene.ao(points, normals, samples=256, radius="2%")   # float32 (n,), 1 = open
    masks = scene.masks(points, normals)                # uint64 (n, N/64): bit i = ray i blocked
    exao.bake("model.glb", "model-ao.glb", texture=1024)
    exao.render("conference.obj", "ao.exr", eye=(-900, 350, -950), target=(600, 150, 300), fov=70)

The same engine as the exao program and the C++ API (include/exao/exao.hpp): the same scene and
receivers give the same bits. Every job runs with the GIL released; `progress(done, total)` is
called from the calling thread about ten times a second, and an exception raised from it (or
Ctrl-C) cancels the job and propagates. Bad input raises ValueError or TypeError (options,
arrays) or OSError (files) with the library's one-line message.
"""

import threading

from . import _exao

__all__ = ["Scene", "bake", "render", "builtin_scenes", "default_method"]

builtin_scenes = _exao.builtin_scenes
default_method = _exao.default_method


class Scene:
    """Triangles to cast shadow rays against, and the engines built over them.

    Build one with Scene.from_arrays or Scene.open; engines (BVH, sample pattern) are built on
    the first query with a set of options and kept for the next ones (the last four sets).
    """

    __slots__ = ("_native",)

    def __init__(self, native):
        self._native = native

    @classmethod
    def from_arrays(cls, vertices, faces, two_sided=True):
        """A scene from numpy arrays.

        vertices: float32 (n, 3), scene units (float64 is rounded to float32; any strides).
        faces: uint32 (m, 3) vertex indices (any integer type; negative or >= n is an error);
            the front face is counter-clockwise (glTF): normal = cross(v1 - v0, v2 - v0).
        two_sided: True (every triangle blocks rays from both sides, the default), False (only
            rays arriving at the front face), or an array of m flags.
        Zero-area triangles are dropped (they block nothing); a NaN or infinite vertex used by a
        face is a ValueError naming it. The arrays are read once and may change afterwards.
        """
        return cls(_exao.Scene.from_arrays(vertices, faces, two_sided))

    @classmethod
    def open(cls, path):
        """A scene file (.gltf, .glb, .obj, .ply, .off, .stl) or a built-in scene's name
        (exao.builtin_scenes()). FileNotFoundError / OSError with the loader's message."""
        return cls(_exao.Scene.open(str(path)))

    @property
    def name(self):
        return self._native.name

    @property
    def triangle_count(self):
        return self._native.triangle_count

    @property
    def bounds(self):
        """((xmin, ymin, zmin), (xmax, ymax, zmax)), scene units."""
        return self._native.bounds

    @property
    def notes(self):
        """What the loader skipped, one line each."""
        return self._native.notes

    def resolve_radius(self, radius="5%"):
        """The AO radius in scene units: a number as it is, "P%" of the bounding-box diagonal."""
        return self._native.resolve_radius(radius)

    def ao(self, points, normals, samples=128, radius="5%", falloff="constant", method=None, seed=None,
           progress=None, keys=None, offset=None, sided="auto", masks=None, threads=0, isa="auto"):
        """AO at each point: float32 (n,), 1 - blocked / samples (1 = open, 0 = occluded).

        points, normals: float32 (n, 3) (float64 rounded; any strides); normals need not be unit.
        samples: rays per point, a multiple of 32 from 32 to 1024.
        radius: the longest ray, scene units, or "P%" of the bounding-box diagonal.
        falloff: "constant", "linear" or "quadratic".
        method: the engine's method by name, as `exao --method` takes it (None: the engine's
            default, exao.default_method()); masks: "exact" or "lut" (None: the default).
        seed: the sample pattern's seed (None: the default pattern, the exao program's).
        keys: uint64 (n,) per-point jitter keys (None: 0 .. n-1, the vertex index of a bake).
        offset: ray origin offset along the normal, scene units (None: 1e-4 of the diagonal).
        sided: "auto" (as the scene says), "one" or "two".
        threads: worker threads (0: one per core). isa: the kernels' instruction set ("auto").
        progress: callable(done, total), called on this thread; raising from it cancels.
        """
        return self._native._run(points, normals, keys, False, samples, radius, falloff, method, seed, offset,
                                 sided, masks, threads, isa, progress)

    def masks(self, points, normals, samples=128, radius="5%", falloff="constant", method=None, seed=None,
              progress=None, keys=None, offset=None, sided="auto", masks=None, threads=0, isa="auto"):
        """Occlusion masks: uint64 (n, ceil(samples / 64)); bit i of point p (word i // 64,
        bit i % 64) is set when ray i is blocked. Arguments as ao()."""
        return self._native._run(points, normals, keys, True, samples, radius, falloff, method, seed, offset,
                                 sided, masks, threads, isa, progress)

    def __repr__(self):
        return f"<exao.Scene {self.name!r}: {self.triangle_count} triangles>"


# The exao program's commands run in-process, one at a time (their progress and error hooks are
# process-wide, cli/program.h).
_program_lock = threading.Lock()


def _flags(options):
    """Keyword arguments as the exao program's flags: samples=256 -> --samples 256,
    texel_samples=4 -> --texel-samples 4, attribute=True -> --attribute (False: left out),
    eye=(1, 2, 3) -> --eye=1,2,3, ground=True -> --ground, ground=-0.5 -> --ground=-0.5."""
    args = []
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            args.append(flag)
        elif isinstance(value, (list, tuple)):
            args.append(flag + "=" + ",".join(repr(float(v)) if isinstance(v, float) else str(v) for v in value))
        elif value == "":
            args += [flag, ""]  # an empty value ("--preview ''": none), which "--flag=" does not carry
        else:
            args.append(flag + "=" + (repr(value) if isinstance(value, float) else str(value)))
    return args


def _keyword_message(message):
    """The program's message with its flags named as keywords: "--texel-samples: ..." ->
    "texel_samples: ..." (a message about a flag is about a keyword here)."""
    import re

    return re.sub(r"--([a-z0-9][a-z0-9-]*)", lambda m: m.group(1).replace("-", "_"), message)


def _run(args, paths, progress):
    """Runs `exao <args>`; a failure raises OSError when the message is about one of `paths`
    (the program names the file first: "model.glb: not a glTF file"), else ValueError."""
    with _program_lock:
        status, message = _exao.run_program([str(a) for a in args], progress)
    if status != 0:
        message = message or f"exao {args[0]} failed (exit status {status})"
        head = message.split(": ", 1)[0]
        if head in {str(p) for p in paths if p}:
            raise OSError(message)
        raise ValueError(_keyword_message(message))


def bake(src, dst=None, progress=None, **options):
    """`exao bake SRC -o DST` in-process: AO into a glTF (per vertex by default).

    Every flag of `exao bake --help` is a keyword: texture=1024, attribute=True, ground=True,
    samples=256, radius="2%", method="embree", uv="generate", preview="" ... Returns dst (the
    program's default name when None is given: SRC's stem + -ao.glb, or <scene>.glb).
    The program's summary lines go to the process's stdout, as the exao program prints them.
    """
    args = ["bake", str(src)] + (["-o", str(dst)] if dst is not None else []) + _flags(options)
    _run(args, [src, dst, options.get("preview")], progress)
    return dst


def render(scene="room", output="ao.exr", progress=None, **options):
    """`exao render SCENE -o OUTPUT` in-process: AO seen from a camera, to OpenEXR (and a PNG:
    png="ao.png" by default, png="" for none).

    Every flag of `exao render --help` is a keyword: eye=(x, y, z), target=(x, y, z), fov=70,
    width=1024, height=768, camera="Camera", samples=256, method="raster", lod="auto" ...
    Returns output.
    """
    args = ["render", str(scene), "-o", str(output)] + _flags(options)
    _run(args, [scene, output, options.get("png", "ao.png")], progress)
    return output
