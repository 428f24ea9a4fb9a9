#!/usr/bin/env python3
"""The pictures of the raster LOD note (paper Sec. 4.3, Fig. 7), standard library only.

  lod_figure.py figure LOD.png EXACT.png OUT.png [--scale S]
      LOD render | exact render | heat map of |dAO|, side by side, each halved. The inputs are
      `exao render` PNG previews (8-bit grey + alpha). With N = 128 the AO steps (1/128) are
      coarser than 8 bits, so the PNGs hold the AO exactly. Heat: black 0, red, yellow, white at
      |dAO| >= S (default 0.05).
  lod_figure.py curve BENCH.json [BENCH.json ...] OUT.svg
      Error against speed over eps_1: for each radius, the raster+lod rows of an `exao bench
      --json` run, mean |dAO| against Embree over the speed-up against raster without LOD.
"""
import json
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path + ": not a PNG"
    pos, idat, width, height, channels = 8, b"", 0, 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8, path + ": 8-bit PNGs only"
            channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
        elif kind == b"IDAT":
            idat += body
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = previous[i]
            c = previous[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        previous = line
    grey = [[row[x * channels] for x in range(width)] for row in rows]
    return width, height, grey


def write_png(path, width, height, rgb_rows):
    raw = b"".join(b"\x00" + bytes(row) for row in rgb_rows)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    tmp = path + ".tmp"
    open(tmp, "wb").write(png)
    import os
    os.replace(tmp, path)


def heat(t):
    t = max(0.0, min(1.0, t))
    return (int(255 * min(1.0, 3 * t)), int(255 * max(0.0, min(1.0, 3 * t - 1))), int(255 * max(0.0, 3 * t - 2)))


def figure(lod_path, exact_path, out, scale):
    w, h, lod = read_png(lod_path)
    w2, h2, exact = read_png(exact_path)
    assert (w, h) == (w2, h2), "the two renders differ in size"
    hw, hh = w // 2, h // 2
    gap = 8
    rows = []
    for y in range(hh):
        row = bytearray()
        panel_lod, panel_exact, panel_heat = bytearray(), bytearray(), bytearray()
        for x in range(hw):
            block = [(2 * y + dy, 2 * x + dx) for dy in (0, 1) for dx in (0, 1)]
            a = sum(lod[j][i] for j, i in block) // 4
            b = sum(exact[j][i] for j, i in block) // 4
            d = max(abs(lod[j][i] - exact[j][i]) for j, i in block) / 255.0
            panel_lod += bytes((a, a, a))
            panel_exact += bytes((b, b, b))
            panel_heat += bytes(heat(d / scale))
        white = bytes((255, 255, 255)) * gap
        row = panel_lod + white + panel_exact + white + panel_heat
        rows.append(row)
    write_png(out, 3 * hw + 2 * gap, hh, rows)


def curve(bench_paths, out):
    runs = []
    for path in bench_paths:
        runs += json.load(open(path))["runs"]
    lod = [r for r in runs if r["method"] == "raster+lod" and "lod_speedup_vs_raster" in r]
    series = {}
    for r in lod:
        series.setdefault((r["radius_option"], r["masks"], r.get("lod_levels", 3)), []).append(r)
    W, H, L, B, T, R = 640, 400, 70, 50, 30, 150
    xmax = max([2.5] + [r["lod_speedup_vs_raster"] * 1.1 for r in lod])
    ymax = max([0.006] + [r["mean_abs_error"] * 1.15 for r in lod])
    def px(x):
        return L + (W - L - R) * x / xmax
    def py(y):
        return H - B - (H - B - T) * y / ymax
    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]
    s = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (W, H),
         '<rect width="100%" height="100%" fill="white"/>',
         '<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="black"/>' % (L, H - B, W - R, H - B),
         '<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="black"/>' % (L, H - B, L, T),
         '<text x="%g" y="%g" text-anchor="middle">speed-up over raster without LOD</text>' % ((L + W - R) / 2, H - 12),
         '<text x="16" y="%g" transform="rotate(-90 16 %g)" text-anchor="middle">mean |dAO| against Embree</text>' % ((T + H - B) / 2, (T + H - B) / 2)]
    for i in range(0, int(xmax) + 1):
        s.append('<text x="%g" y="%g" text-anchor="middle">%dx</text>' % (px(i), H - B + 16, i))
    step = 0.001 if ymax < 0.012 else 0.005
    k = 0
    while k * step <= ymax:
        s.append('<text x="%g" y="%g" text-anchor="end">%.3f</text>' % (L - 6, py(k * step) + 4, k * step))
        k += 1
    # The goal: at least 2x, mean |dAO| <= 0.005.
    s.append('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="grey" stroke-dasharray="4 3"/>' % (px(2), T, px(2), H - B))
    s.append('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="grey" stroke-dasharray="4 3"/>' % (L, py(0.005), W - R, py(0.005)))
    s.append('<text x="%g" y="%g" fill="grey">goal</text>' % (px(2) + 4, py(0.005) - 4))
    for n, ((radius, masks, levels), rows) in enumerate(sorted(series.items())):
        rows.sort(key=lambda r: r["lod_eps1"])
        c = colours[n % len(colours)]
        pts = " ".join("%g,%g" % (px(r["lod_speedup_vs_raster"]), py(r["mean_abs_error"])) for r in rows)
        s.append('<polyline points="%s" fill="none" stroke="%s"/>' % (pts, c))
        for r in rows:
            x, y = px(r["lod_speedup_vs_raster"]), py(r["mean_abs_error"])
            s.append('<circle cx="%g" cy="%g" r="3" fill="%s"/>' % (x, y, c))
            s.append('<text x="%g" y="%g" font-size="10" fill="%s">%.3g</text>' % (x + 5, y - 5, c, r["lod_eps1"]))
        s.append('<text x="%g" y="%g" fill="%s">r = %s, L = %d (%s)</text>' % (W - R + 10, T + 16 * (n + 1), c, radius, levels, masks))
    s.append('<text x="%g" y="%g" font-size="10">labels: eps_1</text>' % (W - R + 10, T + 16 * (len(series) + 2)))
    s.append("</svg>")
    open(out, "w").write("\n".join(s) + "\n")


if __name__ == "__main__":
    if len(sys.argv) >= 5 and sys.argv[1] == "figure":
        scale = float(sys.argv[6]) if len(sys.argv) > 6 and sys.argv[5] == "--scale" else 0.05
        figure(sys.argv[2], sys.argv[3], sys.argv[4], scale)
    elif len(sys.argv) >= 4 and sys.argv[1] == "curve":
        curve(sys.argv[2:-1], sys.argv[-1])
    else:
        sys.exit(__doc__)
