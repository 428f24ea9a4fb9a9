#!/usr/bin/env python3
"""A bumpy terrain as a binary little-endian PLY, for scripts/bench-scale.sh.

make-terrain.py N OUT.ply [--points COUNT POINTS.txt]

An N x N grid of quads over [0, 1]^2, two triangles each (2 N^2 triangles), heights from a sum
of sines. --points also writes COUNT receivers (x y z nx ny nz a line) on the same analytic
surface at fixed pseudo-random places, the same set for every N, so that AO times compare.
Standard library only.
"""
import array
import math
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
    import os
    os.replace(path + ".tmp", path)


def write_points(count, path):
    rng = random.Random(21)
    with open(path + ".tmp", "w") as out:
        for _ in range(count):
            x, y = rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95)
            nx, ny, nz = normal(x, y)
            out.write(f"{x:.7g} {y:.7g} {height(x, y) + 1e-4:.7g} {nx:.6f} {ny:.6f} {nz:.6f}\n")
    import os
    os.replace(path + ".tmp", path)


def main(argv):
    if len(argv) not in (3, 6) or (len(argv) == 6 and argv[3] != "--points"):
        sys.exit("usage: make-terrain.py N OUT.ply [--points COUNT POINTS.txt]")
    n = int(argv[1])
    if n < 1:
        sys.exit(f"make-terrain.py: N must be at least 1, got {n}")
    write_terrain(n, argv[2])
    if len(argv) == 6:
        write_points(int(argv[4]), argv[5])


if __name__ == "__main__":
    main(sys.argv)
