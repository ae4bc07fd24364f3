#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Plots of an nbs_eval output directory (thesis Figs. 4.19-4.21), written as PNGs into that directory, sized to
be read at page width (1000-1200 px wide).

  python3 benchmarks/plot_eval.py OUT_DIR

- ns_boxplot.png (Fig. 4.19): per method two notched boxplots side by side -- n_s, where the planner's own
  criterion stopped it, and k99, the first scan after which the truth c_a reached 0.99 c_obs (n_abort + 1 when
  never) -- each over a Gaussian kernel density (Scott's bandwidth) drawn only over the range of its data. Notch =
  +-1.57 IQR / sqrt(s) (Eq. 4.41), quartiles of type 7 as in benchmarks/eval/summary.hpp. Thesis methods and peer
  metrics in two facets.
- ca_per_scan_search.png (Fig. 4.20): c_a / c_obs after each scan, median line and interquartile band per search
  space (C_S, C_B, C_H), with the 0.95 and 0.99 levels.
- ca_per_scan_selection.png (Fig. 4.21): the same per selection criterion (R_H, I_H, Q_H, C_H) and, where present,
  the best peer metrics (RSE_H, PC_H).
A figure whose methods are all missing from runs.jsonl is skipped with a note. Needs python3-matplotlib and
python3-numpy (Debian; scripts/install-deps.sh --with-plots).
"""
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ORDER = ["R_S", "R_B", "R_H", "I_S", "I_B", "I_H", "Q_S", "Q_B", "Q_H", "C_S", "C_B", "C_H",
         "OA_H", "UV_H", "RSV_H", "RSE_H", "PC_H", "AE_H", "VG_H"]


def load(out_dir):
    runs = {}
    with open(out_dir / "runs.jsonl") as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            try:
                r = json.loads(line)
            except json.JSONDecodeError:
                continue  # partial last line of an interrupted run
            runs.setdefault(r["method"], []).append(r)
    return runs


def quartiles(x):
    return np.percentile(x, [25, 50, 75])  # numpy's default "linear" = type 7


def kde(x, grid):
    x = np.asarray(x, dtype=float)
    sd = x.std(ddof=1) if len(x) > 1 else 0.0
    h = 1.06 * sd * len(x) ** (-1 / 5) if sd > 0 else 0.5  # Scott's rule; 0.5 scans for a constant sample
    z = (grid[:, None] - x[None, :]) / h
    return np.exp(-0.5 * z * z).sum(axis=1) / (len(x) * h * math.sqrt(2 * math.pi))


def k_of(run, share):
    """First scan (1-based) after which c_a >= share * c_obs; n_abort + 1 when never (as summary.hpp)."""
    for i, c in enumerate(run["scans"]["c_a"]):
        if c >= share * run["c_obs"]:
            return i + 1
    return run["n_abort"] + 1


def violin_box(ax, data, pos, width, color):
    """Kernel density over [min, max] of the data only (no shading outside it) and a notched box at `pos`."""
    lo, hi = min(data), max(data)
    if hi > lo:
        grid = np.linspace(lo, hi, 200)
        dens = kde(data, grid)
        dens = 0.5 * width * dens / dens.max()
        ax.fill_betweenx(grid, pos - dens, pos + dens, color=color, alpha=0.25, lw=0)
    q1, med, q3 = quartiles(data)
    half = 1.57 * (q3 - q1) / math.sqrt(len(data))
    ax.boxplot([data], positions=[pos], widths=0.6 * width, notch=True, conf_intervals=[(med - half, med + half)],
               usermedians=[med], manage_ticks=False, patch_artist=True,
               boxprops={"facecolor": "white", "edgecolor": color}, medianprops={"color": color, "lw": 2},
               whiskerprops={"color": color}, capprops={"color": color},
               flierprops={"markeredgecolor": color, "markersize": 3})


def plot_ns(runs, out_dir, n_abort):
    thesis = [m for m in ORDER[:12] if m in runs]
    peers = [m for m in ORDER[12:] if m in runs]
    facets = [(f, t) for f, t in ((thesis, "thesis methods"), (peers, "peer metrics (BS/HR search)")) if f]
    fig, axes = plt.subplots(1, len(facets), figsize=(12, 4.6), sharey=True,
                             gridspec_kw={"width_ratios": [len(f) for f, _ in facets]}, squeeze=False)
    colors = {"n_s": "tab:blue", "k99": "tab:orange"}
    for ax, (methods, title) in zip(axes[0], facets):
        for i, m in enumerate(methods, start=1):
            violin_box(ax, [r["n_s"] for r in runs[m]], i - 0.2, 0.38, colors["n_s"])
            violin_box(ax, [k_of(r, 0.99) for r in runs[m]], i + 0.2, 0.38, colors["k99"])
        ax.set_xticks(range(1, len(methods) + 1))
        ax.set_xticklabels(methods, rotation=45 if len(methods) > 8 else 0)
        ax.set_xlim(0.4, len(methods) + 0.6)
        ax.set_title(title)
        ax.grid(axis="y", alpha=0.3)
    axes[0][0].set_ylabel("scans")
    axes[0][0].set_ylim(0, n_abort + 2)
    handles = [plt.Rectangle((0, 0), 1, 1, fc="white", ec=colors["n_s"], lw=2),
               plt.Rectangle((0, 0), 1, 1, fc="white", ec=colors["k99"], lw=2),
               plt.Rectangle((0, 0), 1, 1, fc="grey", alpha=0.25, lw=0)]
    fig.legend(handles, ["n_s: the planner's stop", "k99: truth c_a >= 0.99 c_obs (%d = never)" % (n_abort + 1),
                         "density over the data's range"], loc="upper center", ncol=3, frameon=False)
    counts = sorted({len(runs[m]) for f, _ in facets for m in f})
    fig.text(0.99, 0.01, "runs per method: %s; notch = median +- 1.57 IQR / sqrt(runs) (Eq. 4.41)"
             % "/".join(map(str, counts)), ha="right", fontsize=8)
    fig.tight_layout(rect=(0, 0.03, 1, 0.92))
    fig.savefig(out_dir / "ns_boxplot.png", dpi=100)
    plt.close(fig)


def plot_ca(runs, out_dir, methods, labels, name, title):
    present = [(m, l) for m, l in zip(methods, labels) if m in runs]
    if not present:
        print("plot_eval: %s skipped (none of %s in runs.jsonl)" % (name, ", ".join(methods)))
        return
    n = max(len(r["scans"]["c_a"]) for m, _ in present for r in runs[m])
    fig, ax = plt.subplots(figsize=(10, 4.6))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (m, label) in enumerate(present):
        xs, q = [], []
        for s in range(n):
            vals = [r["scans"]["c_a"][s] / r["c_obs"] for r in runs[m] if len(r["scans"]["c_a"]) > s]
            if vals:
                xs.append(s + 1)
                q.append(quartiles(vals))
        q = np.array(q)
        c = colors[k % len(colors)]
        ax.fill_between(xs, q[:, 0], q[:, 2], color=c, alpha=0.18, lw=0)
        ax.plot(xs, q[:, 1], color=c, lw=2, marker="o", markersize=3,
                label="%s (%s), %d runs" % (label, m, len(runs[m])))
    for level in (0.95, 0.99):
        ax.axhline(level, color="grey", lw=0.8, ls="--")
        ax.text(n + 0.55, level, "%.2f" % level, va="center", fontsize=8, color="grey")
    ax.set_xlim(0.5, n + 1.5)
    lo = min(r["scans"]["c_a"][0] / r["c_obs"] for m, _ in present for r in runs[m])
    ax.set_ylim(max(0.0, lo - 0.05), 1.005)
    ax.set_xlabel("scan number")
    ax.set_ylabel("c_a / c_obs (median, IQR band)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(out_dir / name, dpi=100)
    plt.close(fig)


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(argv) == 2 else 2
    out_dir = Path(argv[1])
    runs = load(out_dir)
    if not runs:
        print("plot_eval: no runs in %s" % (out_dir / "runs.jsonl"), file=sys.stderr)
        return 1
    n_abort = max(r["n_abort"] for rs in runs.values() for r in rs)
    plot_ns(runs, out_dir, n_abort)
    plot_ca(runs, out_dir, ["C_S", "C_B", "C_H"], ["Sphere", "BS", "BS/HR"], "ca_per_scan_search.png",
            "c_a per scan, IG/Quality selection, per search space (Fig. 4.20)")
    plot_ca(runs, out_dir, ["R_H", "I_H", "Q_H", "C_H", "RSE_H", "PC_H"],
            ["Random", "IG", "Quality", "IG/Quality", "RSE", "PC"],
            "ca_per_scan_selection.png", "c_a per scan, BS/HR search, per selection criterion (Fig. 4.21)")
    print("plot_eval: PNGs written to %s" % out_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
