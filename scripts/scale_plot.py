#!/usr/bin/env python3
"""The table and the log-log plot of scripts/bench-scale.sh, from its results.tsv.

scale_plot.py RESULTS.tsv OUT.md OUT.svg CORES ISA "SKIPPED SIZES"

Standard library only: the SVG is written by hand.
"""
import csv
import math
import os
import sys


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    for r in rows:
        for k in r:
            if k != "method":
                r[k] = float(r[k]) if r[k] else float("nan")
    return rows


def write_atomic(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def table(rows, cores, isa, skipped):
    sizes = sorted({r["triangles"] for r in rows})
    by = {(r["triangles"], r["method"]): r for r in rows}
    lines = [
        f"Bumpy terrain in binary PLY (scripts/make-terrain.py), 20,000 receivers at r = 2%, N = 128, "
        f"{int(cores)} cores, {isa} mask kernels. `exao info` is the load alone; load, build and AO are "
        "`exao query`'s own phase times; peak is the process's peak resident memory (GNU time).",
        "",
        "| triangles | file | load only (`info`) | bvh: load | build | AO | wall | peak (B/tri) "
        "| embree: load | build | AO | wall | peak (B/tri) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for t in sizes:
        b, e = by.get((t, "bvh")), by.get((t, "embree"))
        if not b or not e:
            continue
        mb = lambda r: f"{r['peak_mb']:.0f} MB ({r['peak_mb'] * 1048576 / t:.0f})"
        lines.append(
            f"| {t / 1e6:.1f}M | {b['file_mb']:.0f} MB | {b['info_s']:.2f} s ({b['file_mb'] / b['info_s']:.0f} MB/s) "
            f"| {b['load_s']:.2f} s | {b['build_s']:.2f} s | {b['ao_s']:.2f} s | {b['wall_s']:.2f} s | {mb(b)} "
            f"| {e['load_s']:.2f} s | {e['build_s']:.2f} s | {e['ao_s']:.2f} s | {e['wall_s']:.2f} s | {mb(e)} |")
    if skipped.strip():
        lines += ["", "Skipped for lack of memory on this machine: " + ", ".join(s + "M" for s in skipped.split()) + " triangles."]
    lines += ["", "![time and memory against triangles](scale.svg)", ""]
    return "\n".join(lines)


def plot(rows):
    w, h, left, right, top, bottom = 760, 460, 70, 200, 30, 50
    series = [  # (label, method, key, colour, dashed)
        ("bvh: build", "bvh", "build_s", "#1f77b4", False),
        ("bvh: AO", "bvh", "ao_s", "#2ca02c", False),
        ("bvh: wall", "bvh", "wall_s", "#000000", False),
        ("embree: build", "embree", "build_s", "#1f77b4", True),
        ("embree: AO", "embree", "ao_s", "#2ca02c", True),
        ("embree: wall", "embree", "wall_s", "#000000", True),
        ("load", "bvh", "load_s", "#ff7f0e", False),
        ("bvh: peak GB", "bvh", "peak_gb", "#d62728", False),
        ("embree: peak GB", "embree", "peak_gb", "#d62728", True),
    ]
    for r in rows:
        r["peak_gb"] = r["peak_mb"] / 1024
    xs = [r["triangles"] for r in rows]
    ys = [r[s[2]] for r in rows for s in series if r[s[2]] > 0]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)) + 0.01)
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    px = lambda x: left + (math.log10(x) - x0) / (x1 - x0) * (w - left - right)
    py = lambda y: h - bottom - (math.log10(y) - y0) / max(1, y1 - y0) * (h - top - bottom)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>']
    for e in range(x0, x1 + 1):
        for m in (1, 2, 5):
            x = m * 10 ** e
            if x > 10 ** x1:
                break
            out.append(f'<line x1="{px(x):.1f}" y1="{top}" x2="{px(x):.1f}" y2="{h - bottom}" stroke="#ddd"/>')
            out.append(f'<text x="{px(x):.1f}" y="{h - bottom + 16}" text-anchor="middle">{x / 1e6:g}M</text>')
    for e in range(y0, y1 + 1):
        y = 10 ** e
        out.append(f'<line x1="{left}" y1="{py(y):.1f}" x2="{w - right}" y2="{py(y):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{py(y) + 4:.1f}" text-anchor="end">{y:g}</text>')
    out.append(f'<text x="{(left + w - right) / 2}" y="{h - 12}" text-anchor="middle">triangles</text>')
    out.append(f'<text x="16" y="{(top + h - bottom) / 2}" text-anchor="middle" '
               f'transform="rotate(-90 16 {(top + h - bottom) / 2})">seconds, or GB of peak memory</text>')
    for i, (label, method, key, colour, dashed) in enumerate(series):
        pts = sorted((r["triangles"], r[key]) for r in rows if r["method"] == method and r[key] > 0)
        if not pts:
            continue
        dash = ' stroke-dasharray="6 4"' if dashed else ""
        path = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in pts)
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"{dash}/>')
        for x, y in pts:
            out.append(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="3" fill="{colour}"/>')
        ly = top + 10 + 20 * i
        out.append(f'<line x1="{w - right + 15}" y1="{ly}" x2="{w - right + 45}" y2="{ly}" stroke="{colour}" stroke-width="2"{dash}/>')
        out.append(f'<text x="{w - right + 52}" y="{ly + 4}">{label}</text>')
    out.append("</svg>\n")
    return "\n".join(out)


def main(argv):
    if len(argv) != 7:
        sys.exit("usage: scale_plot.py RESULTS.tsv OUT.md OUT.svg CORES ISA SKIPPED")
    rows = read(argv[1])
    if not rows:
        sys.exit(f"scale_plot.py: {argv[1]}: no results")
    write_atomic(argv[2], table(rows, float(argv[4]), argv[5], argv[6]))
    write_atomic(argv[3], plot(rows))


if __name__ == "__main__":
    main(sys.argv)
