#!/usr/bin/env python3
"""Gathers bench/cells_study.sh's runs into study.csv, study.json, SVG plots and index.html.

    bench/cells_study.py OUT_DIR
"""
import csv
import html
import json
import math
import os
import shutil
import sys


def load(path):
    with open(path) as f:
        return json.load(f)


def frames(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def svg_lines(title, xlabel, ylabel, series, path, marks=()):
    """series: [(label, colour, [(x, y), ...])]; marks: x positions of vertical lines."""
    w, h, left, bottom, top, right = 760, 360, 60, 40, 30, 150
    xs = [x for _, _, pts in series for x, _ in pts] or [0, 1]
    ys = [y for _, _, pts in series for _, y in pts if math.isfinite(y)] or [0, 1]
    x0, x1 = min(xs), max(xs) or 1
    y0, y1 = 0.0, max(ys) * 1.05 or 1
    if x1 == x0:
        x1 = x0 + 1

    def px(x):
        return left + (x - x0) / (x1 - x0) * (w - left - right)

    def py(y):
        return h - bottom - (y - y0) / (y1 - y0) * (h - bottom - top)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{w / 2}" y="18" text-anchor="middle" font-size="14">{html.escape(title)}</text>',
           f'<line x1="{left}" y1="{h - bottom}" x2="{w - right}" y2="{h - bottom}" stroke="black"/>',
           f'<line x1="{left}" y1="{top}" x2="{left}" y2="{h - bottom}" stroke="black"/>',
           f'<text x="{(w - right + left) / 2}" y="{h - 8}" text-anchor="middle">{html.escape(xlabel)}</text>',
           f'<text x="14" y="{h / 2}" transform="rotate(-90 14 {h / 2})" text-anchor="middle">{html.escape(ylabel)}</text>']
    for k in range(6):
        y = y0 + (y1 - y0) * k / 5
        out.append(f'<text x="{left - 6}" y="{py(y) + 4:.1f}" text-anchor="end">{y:.3g}</text>')
        out.append(f'<line x1="{left}" y1="{py(y):.1f}" x2="{w - right}" y2="{py(y):.1f}" stroke="#ddd"/>')
    for k in range(6):
        x = x0 + (x1 - x0) * k / 5
        out.append(f'<text x="{px(x):.1f}" y="{h - bottom + 16}" text-anchor="middle">{x:.4g}</text>')
    for m in marks:
        out.append(f'<line x1="{px(m):.1f}" y1="{top}" x2="{px(m):.1f}" y2="{h - bottom}" stroke="#f0c040" '
                   'stroke-width="0.7"/>')
    for i, (label, colour, pts) in enumerate(series):
        p = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in pts if math.isfinite(y))
        out.append(f'<polyline points="{p}" fill="none" stroke="{colour}" stroke-width="1.2"/>')
        out.append(f'<text x="{w - right + 10}" y="{top + 16 * i + 10}" fill="{colour}">{html.escape(label)}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    out = sys.argv[1]
    runs = os.path.join(out, "runs")
    rows = []
    for name in sorted(n[:-len(".build.json")] for n in os.listdir(runs) if n.endswith(".build.json")):
        b = load(os.path.join(runs, name + ".build.json"))
        w = load(os.path.join(runs, name + ".walk.json"))
        plain = load(os.path.join(runs, name + ".walk_plain.json"))
        rows.append({
            "config": name, "scene_faces": b["scene_faces"], "objects": b["objects"], "cells": b["cells"],
            "full": b["entries"]["full"], "svmesh": b["entries"]["svmesh"], "mvmesh": b["entries"]["mvmesh"],
            "build_s": round(b["seconds"]["total"], 1),
            "build_s_per_cell": round(b["seconds"]["total"] / b["cells"], 3),
            "faces_per_cell": round(b["mean_faces_per_cell"]),
            "original_to_simplified": round(b["original_to_simplified"], 1),
            "faces_a": round(w["faces"]["a"]), "faces_b": round(w["faces"]["b"]), "faces_c": round(w["faces"]["c"]),
            "ms_a": round(w["ms"]["a"], 2), "ms_b": round(w["ms"]["b"], 2), "ms_c": round(w["ms"]["c"], 2),
            "speedup_a_over_c": round(w["speedup"]["a_over_c"], 1),
            "speedup_b_over_c": round(w["speedup"]["b_over_c"], 1),
            "faces_a_over_c": round(w["speedup"]["faces_a_over_c"], 1),
            "psnr_textured": round(w["psnr"]["mean"], 2), "psnr_textured_min": round(w["psnr"]["min"], 2),
            "psnr_plain": round(plain["psnr"]["mean"], 2), "psnr_plain_min": round(plain["psnr"]["min"], 2),
            "ms_c_plain": round(plain["ms"]["c"], 2),
        })
    prefetch = []
    for p in ("on", "off"):
        for c in ("cold", "warm"):
            path = os.path.join(runs, f"prefetch_{p}_{c}.json")
            if not os.path.exists(path):
                continue
            d = load(path)
            prefetch.append({"prefetch": p, "cache": c, "frames": d["frames"], "crossings": d["crossings"],
                             "ms_inside_mean": round(d["ms"]["c_inside_mean"], 2),
                             "ms_crossing_mean": round(d["ms"]["c_crossing_mean"], 2),
                             "ms_crossing_max": round(d["ms"]["c_crossing_max"], 2)})
    with open(os.path.join(out, "study.csv"), "w", newline="") as f:
        if rows:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    with open(os.path.join(out, "study.json"), "w") as f:
        json.dump({"configs": rows, "prefetch": prefetch}, f, indent=1)

    # Plots: PSNR along the path per scene; frame time around crossings with and without prefetch.
    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    series = []
    for i, size in enumerate(("2M", "4M", "8M")):
        path = os.path.join(runs, f"{size}-50-5-4.5.walk", "frames.csv")
        if os.path.exists(path):
            pts = [(int(r["frame"]), float(r["psnr"])) for r in frames(path) if r["psnr"]]
            series.append((size, colours[i], pts))
    svg_lines("PSNR of C against A along the path (textured)", "frame", "PSNR (dB)", series,
              os.path.join(out, "psnr.svg"))
    series, marks = [], []
    for i, p in enumerate(prefetch):
        path = os.path.join(runs, f"prefetch_{p['prefetch']}_{p['cache']}.walk", "frames.csv")
        if os.path.exists(path):
            fr = frames(path)[:300]
            series.append((f"prefetch {p['prefetch']}, {p['cache']}", colours[i],
                           [(int(r["frame"]), float(r["ms_c"])) for r in fr]))
            if not marks:
                marks = [int(r["frame"]) for r in fr if r["crossing"] == "1"]
    svg_lines("Frame time of C around cell crossings (yellow)", "frame", "ms", series,
              os.path.join(out, "prefetch.svg"), marks)

    # The page.
    def table(items, keys):
        head = "".join(f"<th>{html.escape(k)}</th>" for k in keys)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(str(r[k]))}</td>" for k in keys) + "</tr>" for r in items)
        return f"<table><tr>{head}</tr>{body}</table>"

    images = ""
    for size in ("4M",):
        d = os.path.join(runs, f"{size}-50-5-4.5.walk")
        for name in ("worst_a", "worst_c", "first_a", "first_c"):
            if os.path.exists(os.path.join(d, name + ".png")):
                shutil.copy(os.path.join(d, name + ".png"), os.path.join(out, f"{size}_{name}.png"))
                images += f'<figure><img src="{size}_{name}.png" width="400"><figcaption>{size} {name}</figcaption></figure>'
    page = f"""<!doctype html><meta charset="utf-8"><title>visimp walkthrough-LOD study</title>
<style>body{{font-family:sans-serif;max-width:1200px;margin:auto}} table{{border-collapse:collapse;font-size:12px}}
td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}} figure{{display:inline-block;margin:4px}}</style>
<h1>Walkthrough LOD per navigation cell</h1>
<p>Configurations are kM-cell-Ts-Tl as in the paper. A: the full scene; B: the full scene frustum-culled per object;
C: the cell's LOD set (SVMesh/MVMesh outside, full inside, frustum-culled). Frame times are draw + shade on the CPU
rasterizer at 1024&sup2;; PSNR on luminance, textured and not (plain). See docs/cells.md.</p>
<h2>Configurations (Tables 2 and 3, sweeps)</h2>{table(rows, list(rows[0]) if rows else [])}
<h2>Prefetching (Fig. 9)</h2>{table(prefetch, list(prefetch[0]) if prefetch else [])}
<img src="psnr.svg"><img src="prefetch.svg">
<h2>Frames (A full, C cells)</h2>{images}
"""
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write(page)


if __name__ == "__main__":
    main()
