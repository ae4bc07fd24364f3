#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Truth-based comparison of methods on the same seeded runs (issue 18, item 2).

nbs_eval seeds run r identically for every method, so an output with runs 0..n-1 of a new method compares run for run
with the same runs of another output (e.g. docs/eval/MESH/default-20runs). Prints per method, over the runs both
hold: median k95 / k97 / k99 (first scan with c_a >= share * c_obs, n_abort + 1 when never), mean l_s up to k99
(metres), median n_s, mean c_a / c_obs at n_s and after 10 scans.

usage: benchmarks/same_runs_table.py MESH OUTPUT... [--base default-20runs] [--methods C_H,RSE_H,RSV_H,PC_H,UV_H]
(run from the repository root; MESH = a folder of docs/eval; OUTPUT = nbs_eval output folders)
"""
import argparse
import json
import os
import statistics as st
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from stop_rule_table import k_share  # noqa: E402


def load(path):
    out = {}
    with open(os.path.join(path, "runs.jsonl")) as f:
        for line in f:
            r = json.loads(line)
            out.setdefault(r["method"], {})[r["run"]] = r
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("outputs", nargs="+")
    ap.add_argument("--base", default="default-20runs")
    ap.add_argument("--methods", default="C_H,RSE_H,RSV_H,PC_H,UV_H")
    a = ap.parse_args()
    rows = {}
    for d in a.outputs:
        rows.update(load(d))
    runs = sorted(set.intersection(*(set(rr) for rr in rows.values())))
    base = load(os.path.join("docs/eval", a.mesh, a.base))
    for m in a.methods.split(","):
        if m in base and m not in rows:
            rows[m] = base[m]
    print(f"{a.mesh}: runs {runs}")
    print("| method | k95 | k97 | k99 | l_s to k99 / m | n_s | c_a/c_obs at n_s | c_a/c_obs at 10 |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for m, rr in rows.items():
        rs = [rr[i] for i in runs if i in rr]
        if len(rs) < len(runs):
            print(f"{m}: missing runs, skipped", file=sys.stderr)
            continue
        k99 = [k_share(r, 0.99) for r in rs]
        path = st.mean(r["scans"]["l_s_m"][min(k, len(r["scans"]["l_s_m"])) - 1] for r, k in zip(rs, k99))
        ca = lambda r, n: r["scans"]["c_a"][min(n, len(r["scans"]["c_a"])) - 1] / r["c_obs"]
        print(f"| {m} | {st.median(k_share(r, 0.95) for r in rs):.1f} | {st.median(k_share(r, 0.97) for r in rs):.1f} "
              f"| {st.median(k99):.1f} | {path:.2f} | {st.median(r['n_s'] for r in rs):.1f} "
              f"| {st.mean(ca(r, r['n_s']) for r in rs):.3f} | {st.mean(ca(r, 10) for r in rs):.3f} |")


if __name__ == "__main__":
    main()
