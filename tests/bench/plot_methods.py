#!/usr/bin/env python3
"""Plot and tabulate bench_methods' CSV: error against time per method.

    plot_methods.py results.csv OUT_DIR "machine description"

Writes OUT_DIR/plot.png (one panel per scene x blur field: relative L1 error
against seconds, log time axis, one curve per method, each method's settings
in order of time), OUT_DIR/table.md (per panel, every method's best-error
setting and its cheapest setting, ranked by measured error; and the edge
errors of diffusion vs the Gaussian baseline).
"""
import csv
import math
import textwrap
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

path, out_dir, machine = sys.argv[1], sys.argv[2], sys.argv[3]
rows = list(csv.DictReader(open(path)))
for r in rows:
    for k in ("seconds", "psnr", "rel_l1", "rel_l2", "ssim", "edge_rel_l1"):
        r[k] = float(r[k])
    r["away_rel_l1"] = float(r.get("away_rel_l1") or "nan")  # older CSVs have no such column

panels = defaultdict(list)
for r in rows:
    panels[(r["scene"], r["width"] + "x" + r["height"], r["field"])].append(r)

# Panels by scene, then resolution (small first), then field.
keys = sorted(panels, key=lambda k: (k[0], int(k[1].split("x")[0]), k[2]))
cols = min(3, len(keys))
nrows = (len(keys) + cols - 1) // cols
# One colour per method across panels (more methods than the default cycle's 10).
all_methods = sorted({r["method"] for r in rows})
colour = {m: plt.cm.tab20(i % 20) for i, m in enumerate(all_methods)}
fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.2 * nrows), squeeze=False)
for ax, key in zip(axes.flat, keys):
    by_method = defaultdict(list)
    for r in panels[key]:
        by_method[r["method"]].append(r)
    for method, rs in sorted(by_method.items()):
        rs.sort(key=lambda r: r["seconds"])
        ax.plot([r["seconds"] for r in rs], [r["rel_l1"] for r in rs], marker="o", markersize=3, label=method,
                color=colour[method])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds (log)")
    ax.set_ylabel("relative L1 error vs ground truth")
    ax.set_title(" / ".join(key), fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
for ax in list(axes.flat)[len(keys):]:
    ax.axis("off")
handles, labels = axes.flat[0].get_legend_handles_labels()
fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8)
# Wrapped: a merged run's description is longer than the figure is wide.
fig.suptitle(textwrap.fill("gdof: error against run time (" + machine + ")", 150), fontsize=11)
fig.tight_layout(rect=(0, 0.05 + 0.1 / nrows, 1, 0.96))
fig.savefig(out_dir + "/plot.png", dpi=90)

lines = ["Machine: " + machine + ". Relative L1 error against the ray tracer's ground truth; "
         "edge = relative L1 within 4 px (at 640 wide) of depth discontinuities. "
         "Post-process times exclude producing their inputs. Ranked by measured error.", ""]
for key in keys:
    lines += ["**" + " / ".join(key) + "**", "",
              "| rank | method | best setting | s | rel L1 | edge rel L1 | PSNR dB | SSIM | cheapest setting | s | rel L1 |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    by_method = defaultdict(list)
    for r in panels[key]:
        by_method[r["method"]].append(r)
    best = sorted(((min(rs, key=lambda r: r["rel_l1"]), min(rs, key=lambda r: r["seconds"])) for rs in by_method.values()),
                  key=lambda p: p[0]["rel_l1"])
    for i, (b, c) in enumerate(best, 1):
        lines.append("| %d | %s | %s | %.3g | %.4f | %.4f | %.2f | %.4f | %s | %.3g | %.4f |" % (
            i, b["method"], b["setting"], b["seconds"], b["rel_l1"], b["edge_rel_l1"], b["psnr"], b["ssim"],
            c["setting"], c["seconds"], c["rel_l1"]))
    lines.append("")
# The question: diffusion on the deep render vs the naive Gaussian
# baseline near depth discontinuities, at comparable time.
lines += ["**Near depth discontinuities (thin lens): diffusion on the deep render vs the Gaussian baseline**", "",
          "| scene | diffusion (deep), defaults (solver auto, layers=auto): edge rel L1 | s | diffusion (deep), best setting | s "
          "| gaussian layers, best | s | gaussian / best diffusion | fastest deep diffusion beating the best gaussian | s "
          "| its time / gaussian's |", "|---|---|---|---|---|---|---|---|---|---|---|"]
for key in keys:
    if key[2] != "thin_lens":
        continue
    d = [r for r in panels[key] if r["method"] == "diffusion auto (deep)" and r["setting"] == "layers=auto"]
    dd = [r for r in panels[key] if r["method"].startswith("diffusion") and "(deep)" in r["method"]]
    g = [r for r in panels[key] if r["method"].startswith("gaussian")]
    if d and dd and g:
        db = min(dd, key=lambda r: r["edge_rel_l1"])
        gb = min(g, key=lambda r: r["edge_rel_l1"])
        beat = sorted((r for r in dd if r["edge_rel_l1"] < gb["edge_rel_l1"]), key=lambda r: r["seconds"])
        fast = ("%.4f (%s, %s) | %.3g | %.1f" % (beat[0]["edge_rel_l1"], beat[0]["method"].split(" ")[1], beat[0]["setting"],
                                                 beat[0]["seconds"], beat[0]["seconds"] / max(gb["seconds"], 1e-30))
                if beat else "none | - | -")
        lines.append("| %s | %.4f | %.3g | %.4f (%s, %s) | %.3g | %.4f (%s) | %.3g | %.2f | %s |" % (
            " ".join(key[:2]), d[0]["edge_rel_l1"], d[0]["seconds"], db["edge_rel_l1"], db["method"].split(" ")[1],
            db["setting"], db["seconds"], gb["edge_rel_l1"], gb["setting"], gb["seconds"],
            gb["edge_rel_l1"] / max(db["edge_rel_l1"], 1e-30), fast))
# Plates (flat RGBA + Z) at their defaults against the deep render, the deep
# render reduced to one sample per pixel (what a perfect plate holds, through
# the deep path), one layer (what a continuous surface looks like uncut: no
# seams), a degraded depth map and the Gaussian baseline; away = relative L1
# away from depth discontinuities.
lines += ["", "**Plates: flat + Z at the defaults (solver auto, layers=auto)**", "",
          "| panel | flat+Z edge | flat+Z away | flat+Z overall | s | degraded Z edge (x clean) | deep edge | deep away "
          "| one-sample deep edge | one layer edge | one layer away | gaussian best edge | gaussian best away |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]


def pick(rs, method, setting):
    m = [r for r in rs if r["method"] == method and r["setting"] == setting]
    return m[0] if m else None


for key in keys:
    rs = panels[key]
    f = pick(rs, "diffusion auto (flat+Z)", "layers=auto")
    dz = pick(rs, "diffusion auto (degraded Z)", "layers=auto")
    dp = pick(rs, "diffusion auto (deep)", "layers=auto")
    one = pick(rs, "diffusion auto (flat+Z)", "layers=1")
    os1 = pick(rs, "diffusion auto (one-sample deep)", "layers=auto")
    g = [r for r in rs if r["method"].startswith("gaussian")]
    if not (f and dp and g):
        continue
    ge, ga = min(r["edge_rel_l1"] for r in g), min(r["away_rel_l1"] for r in g)
    lines.append("| %s | %.4f | %.4f | %.4f | %.3g | %s | %.4f | %.4f | %s | %s | %s | %.4f | %.4f |" % (
        " / ".join(key), f["edge_rel_l1"], f["away_rel_l1"], f["rel_l1"], f["seconds"],
        "%.4f (%.2f)" % (dz["edge_rel_l1"], dz["edge_rel_l1"] / max(f["edge_rel_l1"], 1e-30)) if dz else "-",
        dp["edge_rel_l1"], dp["away_rel_l1"], "%.4f" % os1["edge_rel_l1"] if os1 else "-",
        "%.4f" % one["edge_rel_l1"] if one else "-",
        "%.4f" % one["away_rel_l1"] if one else "-", ge, ga))

# The pyramid (the default) against the full-resolution solve (the previous
# default), both measured in this run, per input: time and error.
lines += ["", "**Diffusion defaults: the pyramid against full resolution (the previous default), same run**", "",
          "| panel | input | s (full-res) | s (pyramid) | speed-up | rel L1 full-res | rel L1 pyramid | edge full-res | edge pyramid |",
          "|---|---|---|---|---|---|---|---|---|"]
for key in keys:
    rs = panels[key]
    for inp in ("deep", "flat+Z", "degraded Z"):
        on = pick(rs, "diffusion auto (%s)" % inp, "layers=auto")
        off = pick(rs, "diffusion auto full-res (%s)" % inp, "layers=auto")
        if not (on and off):
            continue
        lines.append("| %s | %s | %.3g | %.3g | %.2fx | %.4f | %.4f | %.4f | %.4f |" % (
            " / ".join(key), inp, off["seconds"], on["seconds"], off["seconds"] / max(on["seconds"], 1e-30),
            off["rel_l1"], on["rel_l1"], off["edge_rel_l1"], on["edge_rel_l1"]))

# Ray tracing: each adaptive setting against fixed sampling at the same time
# (fixed error interpolated log-log between the fixed settings around it).
lines += ["", "**Ray tracing: adaptive against fixed sampling at equal time**", "",
          "| panel | adaptive setting | s | rel L1 adaptive | rel L1 fixed at that time | adaptive / fixed |",
          "|---|---|---|---|---|---|"]
for key in keys:
    rs = panels[key]
    fixed = sorted((r for r in rs if r["method"] == "raytrace fixed"), key=lambda r: r["seconds"])
    for a in sorted((r for r in rs if r["method"] == "raytrace adaptive"), key=lambda r: r["seconds"]):
        f_at = None
        for lo, hi in zip(fixed, fixed[1:]):
            if lo["seconds"] <= a["seconds"] <= hi["seconds"] and lo["seconds"] > 0 and hi["seconds"] > lo["seconds"]:
                t = (math.log(a["seconds"]) - math.log(lo["seconds"])) / (math.log(hi["seconds"]) - math.log(lo["seconds"]))
                f_at = math.exp(math.log(lo["rel_l1"]) + t * (math.log(hi["rel_l1"]) - math.log(lo["rel_l1"])))
        lines.append("| %s | %s | %.3g | %.4f | %s | %s |" % (
            " / ".join(key), a["setting"], a["seconds"], a["rel_l1"], "%.4f" % f_at if f_at else "- (outside the fixed range)",
            "%.2f" % (a["rel_l1"] / f_at) if f_at else "-"))
open(out_dir + "/table.md", "w").write("\n".join(lines) + "\n")

# The README's compact table: each method's best relative L1 error (and the
# time of that setting) per panel.
methods = sorted({r["method"] for r in rows})
summary = ["Best relative L1 error against the ground truth (seconds of that setting in brackets); " + machine + "."]
for size in sorted({k[1] for k in keys}, key=lambda t: int(t.split("x")[0])):
    ks = [k for k in keys if k[1] == size]
    summary += ["", "**" + size + "**", "", "| method | " + " | ".join(k[0] + " " + k[2] for k in ks) + " |",
                "|---|" + "---|" * len(ks)]
    for m in methods:
        cells = []
        for key in ks:
            rs = [r for r in panels[key] if r["method"] == m]
            if rs:
                b = min(rs, key=lambda r: r["rel_l1"])
                cells.append("%.4f (%.3g s)" % (b["rel_l1"], b["seconds"]))
            else:
                cells.append("-")
        if any(c != "-" for c in cells):  # a size a method did not run at (a partial run merged) has no row
            summary.append("| " + m + " | " + " | ".join(cells) + " |")
open(out_dir + "/summary.md", "w").write("\n".join(summary) + "\n")
