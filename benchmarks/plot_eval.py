#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Plots of an nbs_eval output directory (thesis Figs. 4.19-4.21), written as PNGs into that directory.

  python3 benchmarks/plot_eval.py OUT_DIR

- ns_boxplot.png (Fig. 4.19): n_s per method, notched boxplot (notch = +-1.57 IQR / sqrt(s), Eq. 4.41, quartiles of
  type 7 as in benchmarks/eval/summary.hpp) overlaid with a Gaussian kernel density (Scott's bandwidth).
- ca_per_scan_search.png (Fig. 4.20): c_a after each scan, boxplots per search space (C_S, C_B, C_H).
- ca_per_scan_selection.png (Fig. 4.21): c_a after each scan, boxplots per selection criterion (R_H, I_H, Q_H, C_H).
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


def plot_ns(runs, out_dir, n_abort):
    methods = [m for m in ORDER if m in runs]
    fig, ax = plt.subplots(figsize=(max(6, 0.8 * len(methods) + 2), 4.5))
    data = [[r["n_s"] for r in runs[m]] for m in methods]
    grid = np.linspace(0.5, n_abort + 0.5, 300)
    for i, d in enumerate(data, start=1):
        dens = kde(d, grid)
        dens = 0.4 * dens / dens.max() if dens.max() > 0 else dens
        ax.fill_betweenx(grid, i - dens, i + dens, color="gold", alpha=0.5, lw=0)
    conf = []
    for d in data:
        q1, med, q3 = quartiles(d)
        half = 1.57 * (q3 - q1) / math.sqrt(len(d))
        conf.append((med - half, med + half))
    ax.boxplot(data, notch=True, conf_intervals=conf, usermedians=[quartiles(d)[1] for d in data],
               labels=methods, medianprops={"color": "red"}, boxprops={"color": "blue"})
    ax.set_ylabel("abort scan number n_s")
    ax.set_ylim(0, n_abort + 1)
    ax.set_title("n_s per method (%s runs each)" % "/".join(str(len(d)) for d in data))
    fig.tight_layout()
    fig.savefig(out_dir / "ns_boxplot.png", dpi=120)
    plt.close(fig)


def plot_ca(runs, out_dir, methods, labels, name, title):
    present = [(m, l) for m, l in zip(methods, labels) if m in runs]
    if not present:
        print("plot_eval: %s skipped (none of %s in runs.jsonl)" % (name, ", ".join(methods)))
        return
    n = max(len(r["scans"]["c_a"]) for m, _ in present for r in runs[m])
    fig, ax = plt.subplots(figsize=(max(8, 0.45 * n * len(present)), 4.5))
    width = 0.8 / len(present)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (m, label) in enumerate(present):
        pos, data = [], []
        for s in range(n):
            vals = [100 * r["scans"]["c_a"][s] for r in runs[m] if len(r["scans"]["c_a"]) > s]
            if vals:
                pos.append(s + 1 + (k - (len(present) - 1) / 2) * width)
                data.append(vals)
        bp = ax.boxplot(data, positions=pos, widths=width * 0.9, patch_artist=True, manage_ticks=False,
                        medianprops={"color": "black"}, flierprops={"markersize": 2})
        for b in bp["boxes"]:
            b.set_facecolor(colors[k % len(colors)])
        ax.plot([], [], color=colors[k % len(colors)], lw=6, label="%s (%s)" % (label, m))
    ax.set_xticks(range(1, n + 1))
    ax.set_xlabel("scan number")
    ax.set_ylabel("c_a / %")
    ax.set_title(title)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(out_dir / name, dpi=120)
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
    plot_ca(runs, out_dir, ["R_H", "I_H", "Q_H", "C_H"], ["Random", "IG", "Quality", "IG/Quality"],
            "ca_per_scan_selection.png", "c_a per scan, BS/HR search, per selection criterion (Fig. 4.21)")
    print("plot_eval: PNGs written to %s" % out_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
