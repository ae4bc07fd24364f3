#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The issue's checks of the thesis comparison, per mesh, from nbs_eval outputs, as a markdown table.

  python3 benchmarks/eval_checks.py NAME=OUT_DIR [NAME=OUT_DIR ...]

Per mesh (OUT_DIR/summary.json; needs the methods C_H and C_S): C_H's median n_s and notch (Eq. 4.41), the lowest
median n_s and the methods that have it, C_S's median and notch, whether the two notches are apart (the thesis's
95 % statement), l_s(C_H) / l_s(C_S) (mean path over the 30 scans, as in Tab. 4.5, and, from OUT_DIR/runs.jsonl,
the mean path up to each run's n_s: the path to the model that meets the quality criterion), C_H's mean c_a(30) /
c_obs, and, as a check that does not depend on the coverage estimate ĉ_m, the median number of scans after which
the true c_a first reaches 0.95 · c_obs (n_abort + 1 for a run that never does; shown as "> n_abort" if the median is
such a run) for C_H and C_S. A second table gives that truth-based count for every method in the outputs (rows in
nbs_eval --help order, one column per mesh); a third the curves of C_H and C_S: median c_a / c_obs and mean l_s after
k scans. Standard library only.
"""
import json
import statistics
import sys
from pathlib import Path

ORDER = "R_S R_B R_H I_S I_B I_H Q_S Q_B Q_H C_S C_B C_H OA_H UV_H RSV_H RSE_H PC_H AE_H VG_H".split()  # --help's
KS = [2, 3, 4, 5, 6, 8, 10, 15, 30]


def load_runs(runs_jsonl):
    """The runs of OUT_DIR/runs.jsonl grouped by method code."""
    runs = {}
    with open(runs_jsonl) as f:
        for line in f:
            r = json.loads(line)
            runs.setdefault(r["method"], []).append(r)
    return runs


def after(r, series, k):
    """The value of a per-scan series after scan k (the last one if the run ended earlier; index 0 = initial scan)."""
    values = r["scans"][series]
    return values[min(k, len(values)) - 1]


def path_at_stop(runs):
    """Mean over runs of l_s after scan n_s (l_s_m is cumulative)."""
    return statistics.mean(after(r, "l_s_m", r["n_s"]) for r in runs)


def scans_to_truth(runs, share=0.95):
    """Median over runs of the first scan count k with c_a(k) >= share * c_obs (n_abort + 1 if never)."""
    n_abort = max(r["n_abort"] for r in runs)
    median = statistics.median(
        next((i + 1 for i, c in enumerate(r["scans"]["c_a"]) if c >= share * r["c_obs"]), r["n_abort"] + 1)
        for r in runs)
    return f"> {n_abort}" if median > n_abort else f"{median:g}"


def row(name, summary, runs):
    ch, cs = summary["C_H"], summary["C_S"]
    at_stop = path_at_stop(runs["C_H"]) / path_at_stop(runs["C_S"])
    truth = f"{scans_to_truth(runs['C_H'])} / {scans_to_truth(runs['C_S'])}"
    low = min(v["median_scans"] for v in summary.values())
    lows = sorted(k for k, v in summary.items() if v["median_scans"] == low)
    apart = (ch["median_scans"] + ch["notch"] < cs["median_scans"] - cs["notch"]
             or cs["median_scans"] + cs["notch"] < ch["median_scans"] - ch["notch"])
    counts = "/".join(str(r) for r in sorted({v["runs"] for v in summary.values()}))
    return (f"| {name} | {len(summary)} × {counts} | {ch['median_scans']:.1f} (±{ch['notch']:.2f}) | "
            f"{low:.1f}: {', '.join(lows)} | {cs['median_scans']:.1f} (±{cs['notch']:.2f}) | "
            f"{'yes' if apart else 'no'} | {ch['mean_path_length_m'] / cs['mean_path_length_m']:.2f} | {at_stop:.2f} | "
            f"{ch['mean_ca_at_30'] / ch['mean_c_obs']:.3f} | {truth} |")


def main(args):
    if not args or any("=" not in a for a in args):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    meshes = []  # (name, summary, runs by method)
    for a in args:
        name, out = a.split("=", 1)
        summary = json.loads((Path(out) / "summary.json").read_text())
        missing = [m for m in ("C_H", "C_S") if m not in summary]
        if missing:
            print(f"eval_checks: {out} has no runs of {', '.join(missing)}", file=sys.stderr)
            return 2
        meshes.append((name, summary, load_runs(Path(out) / "runs.jsonl")))
    print("| mesh | methods × runs | C_H median n_s (notch) | lowest median n_s | C_S median n_s (notch) |"
          " notches apart | l_s(C_H) / l_s(C_S), 30 scans | at n_s | C_H c_a(30) / c_obs |"
          " scans to c_a ≥ 0.95 c_obs, C_H / C_S |")
    print("|---|---|---:|---|---:|---|---:|---:|---:|---:|")
    print("\n".join(row(name, summary, runs) for name, summary, runs in meshes))

    methods = sorted({m for _, summary, _ in meshes for m in summary},
                     key=lambda m: (ORDER.index(m) if m in ORDER else len(ORDER), m))
    print()
    print("Median scans until c_a ≥ 0.95 · c_obs (true completeness; '-' = method not run):")
    print()
    print("| method | " + " | ".join(name for name, _, _ in meshes) + " |")
    print("|---|" + "---:|" * len(meshes))
    for m in methods:
        cells = [scans_to_truth(runs[m]) if m in summary else "-" for _, summary, runs in meshes]
        print(f"| {m} | " + " | ".join(cells) + " |")

    print()
    print("C_H and C_S after k scans: median c_a / c_obs, mean l_s in m:")
    print()
    print("| mesh | method | " + " | ".join(f"k = {k}" for k in KS) + " |")
    print("|---|---|" + "---:|" * len(KS))
    for name, _, runs in meshes:
        for m in ("C_S", "C_H"):
            cells = [f"{statistics.median(after(r, 'c_a', k) / r['c_obs'] for r in runs[m]):.3f}, "
                     f"{statistics.mean(after(r, 'l_s_m', k) for r in runs[m]):.2f} m" for k in KS]
            print(f"| {name} | {m} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
