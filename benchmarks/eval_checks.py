#!/usr/bin/env python3
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
import sys
from pathlib import Path


def path_at_stop(runs_jsonl, method):
    """Mean over the method's runs of l_s after scan n_s (l_s_m is cumulative, index 0 = the initial scan)."""
    paths = []
    with open(runs_jsonl) as f:
        for line in f:
            r = json.loads(line)
            if r["method"] == method:
                series = r["scans"]["l_s_m"]
                paths.append(series[min(r["n_s"], len(series)) - 1])
    return sum(paths) / len(paths)


def scans_to_truth(runs_jsonl, method, share=0.95):
    """Median over the method's runs of the first scan count k with c_a(k) >= share * c_obs (n_abort + 1 if never)."""
    counts, n_abort = [], 0
    with open(runs_jsonl) as f:
        for line in f:
            r = json.loads(line)
            if r["method"] == method:
                n_abort = max(n_abort, r["n_abort"])
                c_a = r["scans"]["c_a"]
                k = next((i + 1 for i, c in enumerate(c_a) if c >= share * r["c_obs"]), r["n_abort"] + 1)
                counts.append(k)
    counts.sort()
    n = len(counts)
    median = counts[n // 2] if n % 2 else 0.5 * (counts[n // 2 - 1] + counts[n // 2])
    return f"> {n_abort}" if median > n_abort else f"{median:g}"


def row(name, summary, runs_jsonl):
    ch, cs = summary["C_H"], summary["C_S"]
    at_stop = path_at_stop(runs_jsonl, "C_H") / path_at_stop(runs_jsonl, "C_S")
    truth = f"{scans_to_truth(runs_jsonl, 'C_H')} / {scans_to_truth(runs_jsonl, 'C_S')}"
    low = min(v["median_scans"] for v in summary.values())
    lows = sorted(k for k, v in summary.items() if v["median_scans"] == low)
    apart = (ch["median_scans"] + ch["notch"] < cs["median_scans"] - cs["notch"]
             or cs["median_scans"] + cs["notch"] < ch["median_scans"] - ch["notch"])
    runs = "/".join(str(r) for r in sorted({v["runs"] for v in summary.values()}))
    return (f"| {name} | {len(summary)} × {runs} | {ch['median_scans']:.1f} (±{ch['notch']:.2f}) | "
            f"{low:.1f}: {', '.join(lows)} | {cs['median_scans']:.1f} (±{cs['notch']:.2f}) | "
            f"{'yes' if apart else 'no'} | {ch['mean_path_length_m'] / cs['mean_path_length_m']:.2f} | {at_stop:.2f} | "
            f"{ch['mean_ca_at_30'] / ch['mean_c_obs']:.3f} | {truth} |")


def main(args):
    if not args or any("=" not in a for a in args):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    rows = []
    for a in args:
        name, out = a.split("=", 1)
        summary = json.loads((Path(out) / "summary.json").read_text())
        missing = [m for m in ("C_H", "C_S") if m not in summary]
        if missing:
            print(f"eval_checks: {out} has no runs of {', '.join(missing)}", file=sys.stderr)
            return 2
        rows.append(row(name, summary, Path(out) / "runs.jsonl"))
    print("| mesh | methods × runs | C_H median n_s (notch) | lowest median n_s | C_S median n_s (notch) |"
          " notches apart | l_s(C_H) / l_s(C_S), 30 scans | at n_s | C_H c_a(30) / c_obs |"
          " scans to c_a ≥ 0.95 c_obs, C_H / C_S |")
    print("|---|---|---:|---|---:|---|---:|---:|---:|---:|")
    print("\n".join(rows))
    names = [a.split("=", 1)[0] for a in args]
    outs = [Path(a.split("=", 1)[1]) for a in args]
    order = "R_S R_B R_H I_S I_B I_H Q_S Q_B Q_H C_S C_B C_H OA_H UV_H RSV_H RSE_H PC_H AE_H VG_H".split()  # --help's
    methods = []
    for out in outs:
        methods += [m for m in json.loads((out / "summary.json").read_text()) if m not in methods]
    methods.sort(key=lambda m: (order.index(m) if m in order else len(order), m))
    print()
    print("Median scans until c_a ≥ 0.95 · c_obs (true completeness; '-' = method not run):")
    print()
    print("| method | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for m in methods:
        cells = []
        for out in outs:
            have = m in json.loads((out / "summary.json").read_text())
            cells.append(scans_to_truth(out / "runs.jsonl", m) if have else "-")
        print(f"| {m} | " + " | ".join(cells) + " |")
    ks = [2, 3, 4, 5, 6, 8, 10, 15, 30]
    print()
    print("C_H and C_S after k scans: median c_a / c_obs, mean l_s in m:")
    print()
    print("| mesh | method | " + " | ".join(f"k = {k}" for k in ks) + " |")
    print("|---|---|" + "---:|" * len(ks))
    for name, out in zip(names, outs):
        series = {}
        with open(out / "runs.jsonl") as f:
            for line in f:
                r = json.loads(line)
                if r["method"] in ("C_H", "C_S"):
                    series.setdefault(r["method"], []).append(r)
        for m in ("C_S", "C_H"):
            runs = series[m]
            cells = []
            for k in ks:
                shares = sorted(r["scans"]["c_a"][min(k, len(r["scans"]["c_a"])) - 1] / r["c_obs"] for r in runs)
                n = len(shares)
                med = shares[n // 2] if n % 2 else 0.5 * (shares[n // 2 - 1] + shares[n // 2])
                path = sum(r["scans"]["l_s_m"][min(k, len(r["scans"]["l_s_m"])) - 1] for r in runs) / n
                cells.append(f"{med:.3f}, {path:.2f} m")
            print(f"| {name} | {m} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
