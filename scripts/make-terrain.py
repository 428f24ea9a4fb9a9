#!/usr/bin/env python3
"""A bumpy terrain as a mesh file, for scripts/bench-scale.sh and the loaders' speed (docs/scale.md).

make-terrain.py N OUT [--ascii] [--points COUNT POINTS.txt]

An N x N grid of quads over [0, 1]^2, two triangles each (2 N^2 triangles), heights from a sum
of sines. The format is OUT's extension: .ply (binary little-endian; ASCII with --ascii), .glb
(float POSITION and NORMAL, uint32 indices, as exporters write them), .obj or .off (ASCII,
vertices as %.9g, which round-trips a float). --points also writes COUNT receivers
(x y z nx ny nz a line) on the same analytic surface at fixed pseudo-random places, the same set
for every N, so that AO times compare. Standard library only.
"""
import array
import itertools
import json
import math
import os
import random
import struct
import sys


def height(x, y):
    return 0.04 * math.sin(11.0 * x) * math.cos(9.0 * y) + 0.01 * math.sin(53.0 * x + 2.0) * math.sin(47.0 * y) \
        + 0.003 * math.cos(211.0 * x) * math.cos(197.0 * y + 1.0)


def normal(x, y, h=1e-5):
    dx = (height(x + h, y) - height(x - h, y)) / (2 * h)
    dy = (height(x, y + h) - height(x, y - h)) / (2 * h)
    length = math.sqrt(dx * dx + dy * dy + 1.0)
    return -dx / length, -dy / length, 1.0 / length


def write_terrain(n, path):
    vertices = (n + 1) * (n + 1)
    faces = 2 * n * n
    with open(path + ".tmp", "wb") as out:
        out.write((f"ply\nformat binary_little_endian 1.0\ncomment bumpy terrain {n}x{n}\n"
                   f"element vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\n"
                   f"element face {faces}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        for j in range(n + 1):
            y = j / n
            row = array.array("f")
            for i in range(n + 1):
                x = i / n
                row.extend((x, y, height(x, y)))
            if sys.byteorder != "little":
                row.byteswap()
            out.write(row.tobytes())
        # A face is 13 bytes: count 3, then three int32 indices.
        quad = struct.Struct("<BiiiBiii")
        for j in range(n):
            base = j * (n + 1)
            chunk = bytearray()
            for i in range(n):
                a = base + i
                b, c, d = a + 1, a + n + 1, a + n + 2
                chunk += quad.pack(3, a, b, d, 3, a, d, c)
            out.write(chunk)
    os.replace(path + ".tmp", path)


def grid_heights(n):
    """Row-major (n + 1)^2 heights, as float32 (what every format stores)."""
    h = array.array("f")
    for j in range(n + 1):
        y = j / n
        h.extend(height(i / n, y) for i in range(n + 1))
    return h


def quads(n, rows=None):
    """Per quad (of the given rows, else all) its corners a, b, c, d; its triangles are a, b, d
    and a, d, c (the binary PLY writer's order)."""
    for j in rows if rows is not None else range(n):
        base = j * (n + 1)
        for i in range(n):
            a = base + i
            yield a, a + 1, a + n + 1, a + n + 2


def write_text(path, lines):
    with open(path + ".tmp", "w") as out:
        for chunk in lines:
            out.write(chunk)
    os.replace(path + ".tmp", path)


def vertex_rows(n, prefix=""):
    """Per grid row, its vertices as text lines "PREFIX x y z" (%.9g, which round-trips a float)."""
    h = grid_heights(n)
    for j in range(n + 1):
        y = j / n
        yield "".join(f"{prefix}{i / n:.9g} {y:.9g} {h[j * (n + 1) + i]:.9g}\n" for i in range(n + 1))


def counted_face_rows(n):
    """Per grid row, its triangles as OFF and ASCII PLY write them: the count 3, then the indices."""
    for j in range(n):
        yield "".join(f"3 {a} {b} {d}\n3 {a} {d} {c}\n" for a, b, c, d in quads(n, [j]))


def write_obj(n, path):
    def faces():
        for j in range(n):
            # OBJ numbers vertices from 1.
            yield "".join(f"f {a + 1} {b + 1} {d + 1}\nf {a + 1} {d + 1} {c + 1}\n"
                          for a, b, c, d in quads(n, [j]))

    write_text(path, itertools.chain([f"# bumpy terrain {n}x{n}\no terrain\n"], vertex_rows(n, "v "), faces()))


def write_off(n, path):
    header = f"OFF\n{(n + 1) ** 2} {2 * n * n} 0\n"
    write_text(path, itertools.chain([header], vertex_rows(n), counted_face_rows(n)))


def write_ascii_ply(n, path):
    header = (f"ply\nformat ascii 1.0\ncomment bumpy terrain {n}x{n}\nelement vertex {(n + 1) ** 2}\n"
              f"property float x\nproperty float y\nproperty float z\nelement face {2 * n * n}\n"
              f"property list uchar int vertex_indices\nend_header\n")
    write_text(path, itertools.chain([header], vertex_rows(n), counted_face_rows(n)))


def write_glb(n, path):
    """One mesh, one node: POSITION and NORMAL (normals by central differences on the grid) in
    their own buffer views, then uint32 triangle indices (glTF 2.0 section 4.4's container)."""
    h = grid_heights(n)
    side = n + 1
    positions = array.array("f")
    normals = array.array("f")
    for j in range(side):
        y = j / n
        for i in range(side):
            positions.extend((i / n, y, h[j * side + i]))
            dx = (h[j * side + min(i + 1, n)] - h[j * side + max(i - 1, 0)]) * n / (min(i + 1, n) - max(i - 1, 0))
            dy = (h[min(j + 1, n) * side + i] - h[max(j - 1, 0) * side + i]) * n / (min(j + 1, n) - max(j - 1, 0))
            length = math.sqrt(dx * dx + dy * dy + 1.0)
            normals.extend((-dx / length, -dy / length, 1.0 / length))
    indices = array.array("I")
    for a, b, c, d in quads(n):
        indices.extend((a, b, d, a, d, c))
    for part in (positions, normals, indices):
        if sys.byteorder != "little":
            part.byteswap()
    blobs = [positions.tobytes(), normals.tobytes(), indices.tobytes()]
    views, offset = [], 0
    for k, blob in enumerate(blobs):
        view = {"buffer": 0, "byteOffset": offset, "byteLength": len(blob)}
        view["target"] = 34963 if k == 2 else 34962
        views.append(view)
        offset += len(blob)
    vertex_count = side * side
    doc = {
        "asset": {"version": "2.0", "generator": "exao scripts/make-terrain.py"},
        "buffers": [{"byteLength": offset}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": vertex_count, "type": "VEC3",
             "min": [0.0, 0.0, min(h)], "max": [1.0, 1.0, max(h)]},
            {"bufferView": 1, "componentType": 5126, "count": vertex_count, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "nodes": [{"mesh": 0, "name": f"terrain {n}x{n}"}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + offset
    with open(path + ".tmp", "wb") as out:
        out.write(struct.pack("<4sII", b"glTF", 2, total))
        out.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        out.write(struct.pack("<II", offset, 0x004E4942))
        for blob in blobs:
            out.write(blob)
    os.replace(path + ".tmp", path)


def write_points(count, path):
    rng = random.Random(21)
    with open(path + ".tmp", "w") as out:
        for _ in range(count):
            x, y = rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95)
            nx, ny, nz = normal(x, y)
            out.write(f"{x:.7g} {y:.7g} {height(x, y) + 1e-4:.7g} {nx:.6f} {ny:.6f} {nz:.6f}\n")
    os.replace(path + ".tmp", path)


def main(argv):
    usage = "usage: make-terrain.py N OUT.{ply,glb,obj,off} [--ascii] [--points COUNT POINTS.txt]"
    args = argv[1:]
    ascii_ply = "--ascii" in args
    if ascii_ply:
        args.remove("--ascii")
    if len(args) not in (2, 5) or (len(args) == 5 and args[2] != "--points"):
        sys.exit(usage)
    n = int(args[0])
    if n < 1:
        sys.exit(f"make-terrain.py: N must be at least 1, got {n}")
    out = args[1]
    ext = os.path.splitext(out)[1].lower()
    writers = {".ply": write_ascii_ply if ascii_ply else write_terrain, ".glb": write_glb, ".obj": write_obj,
               ".off": write_off}
    if ext not in writers or (ascii_ply and ext != ".ply"):
        sys.exit(usage)
    writers[ext](n, out)
    if len(args) == 5:
        write_points(int(args[3]), args[4])


if __name__ == "__main__":
    main(sys.argv)
