#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Offline study of stop rules on finished nbs_eval outputs (issue 18, item 1).

nbs_eval runs every method to n_abort and records per scan the planner's estimates (c_m = ĉ_m, d_m = d̄_m) and the
truth (c_a, c_obs), so any stop rule that reads only ĉ_m and d̄_m can be replayed exactly: the scans before the stop
do not depend on where it stops. For each rule this prints, per mesh, the medians over the runs of the stop scan n_s,
c_a / c_obs at the stop and n_s - k99 (k99: first scan with c_a >= 0.99 c_obs, n_abort + 1 when never).

usage: benchmarks/stop_rule_table.py [--method C_H] [--dir default-20runs] MESH...   (run from the repository root;
MESH = a folder of docs/eval, e.g. stanford-bunny spot teapot fandisk rocker-arm)
"""
import argparse
import json
import statistics as st


def k_share(r, share):
    for i, c in enumerate(r["scans"]["c_a"]):
        if c >= share * r["c_obs"]:
            return i + 1
    return r["n_abort"] + 1


def threshold_rule(th, density=0.2):
    def stop(r):
        s = r["scans"]
        for i in range(len(s["c_m"])):
            if s["c_m"][i] >= th and s["d_m"][i] >= density:
                return i + 1
        return r["n_abort"]
    return stop


def stagnation_rule(window, delta, floor=0.8, density=0.2):
    def stop(r):
        c, d = r["scans"]["c_m"], r["scans"]["d_m"]
        for i in range(window, len(c)):
            if c[i] - c[i - window] < delta and c[i] >= floor and d[i] >= density:
                return i + 1
        return r["n_abort"]
    return stop


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--method", default="C_H")
    ap.add_argument("--dir", default="default-20runs")
    ap.add_argument("meshes", nargs="+")
    a = ap.parse_args()
    runs = {m: [r for r in map(json.loads, open(f"docs/eval/{m}/{a.dir}/runs.jsonl")) if r["method"] == a.method]
            for m in a.meshes}
    print("| rule | " + " | ".join(f"{m}: n_s, c_a/c_obs, n_s − k99" for m in a.meshes) + " |")
    print("|---|" + "---:|" * len(a.meshes))
    print("| k97 / k98 / k99 (truth) | " + " | ".join(
        f"{st.median(k_share(r, .97) for r in R):.1f} / {st.median(k_share(r, .98) for r in R):.1f} / "
        f"{st.median(k_share(r, .99) for r in R):.1f}" for R in runs.values()) + " |")
    rules = [(f"ĉ_m ≥ {th}" + (" (today's default)" if th == 0.8 else ""), threshold_rule(th))
             for th in (0.8, 0.85, 0.9, 0.94, 0.96)]
    rules += [(f"ĉ_m gain over {w} scans < {dl}", stagnation_rule(w, dl)) for w in (2, 3) for dl in (0.005, 0.01)]
    for name, rule in rules:
        cells = []
        for R in runs.values():
            ns = [rule(r) for r in R]
            ca = [r["scans"]["c_a"][n - 1] / r["c_obs"] for r, n in zip(R, ns)]
            d = [n - k_share(r, 0.99) for r, n in zip(R, ns)]
            cells.append(f"{st.median(ns):.1f}, {st.median(ca):.3f}, {st.median(d):+.1f}")
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
