#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Offline study of stop rules on finished nbs_eval outputs (issue 18, item 1).

nbs_eval runs every method to n_abort and records per scan the planner's estimates (c_m = ĉ_m, d_m = d̄_m) and the
truth (c_a, c_obs), so any stop rule that reads only ĉ_m and d̄_m can be replayed exactly: the scans before the stop
do not depend on where it stops. For each rule this prints, per mesh, the medians over the runs of the stop scan n_s,
c_a / c_obs at the stop and n_s - k99 (k99: first scan with c_a >= 0.99 c_obs, n_abort + 1 when never).

usage: benchmarks/stop_rule_table.py [--method C_H] [--dir default-20runs] MESH...   (run from the repository root;
MESH = a folder of docs/eval, e.g. stanford-bunny spot teapot fandisk rocker-arm, or any nbs_eval output directory)

Rules: ĉ_m >= t (after one scan, or on 2 consecutive scans: a single high ĉ_m after a view whose loops' fans lie on
its own surface does not stop), the ĉ_m gain over w scans below a floor, and the settled rules (CoverageSettled). Runs whose records stop before n_abort
(no candidates left) are skipped. Also printed per rule: how many runs stop within 2 scans of k99 (ok), before
(early) or after (late), and how many run to n_abort although c_a reached 0.99 c_obs (runaway).
"""
import os
import argparse
import json
import statistics as st


def k_share(r, share):
    for i, c in enumerate(r["scans"]["c_a"]):
        if c >= share * r["c_obs"]:
            return i + 1
    return r["n_abort"] + 1


def threshold_rule(th, density=0.2, consecutive=1):
    def stop(r):
        s = r["scans"]
        held = 0
        for i in range(len(s["c_m"])):
            held = held + 1 if s["c_m"][i] >= th and s["d_m"][i] >= density else 0
            if held >= consecutive:
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


def settled_rule(th, floor, window, delta, density=0.2, stall_floor=None, stall_window=5):
    """ĉ_m >= th on 2 consecutive scans, or ĉ_m >= floor and within delta over the last window + 1 scans, or (with
    stall_floor) ĉ_m >= stall_floor and within delta over the last stall_window scans (CoverageSettled)."""
    def still(c, i, level, w):  # w values ending at scan i + 1
        return i + 1 >= w and c[i] >= level and max(c[i - w + 1:i + 1]) - min(c[i - w + 1:i + 1]) < delta

    def stop(r):
        c, d = r["scans"]["c_m"], r["scans"]["d_m"]
        held = 0
        for i in range(len(c)):
            held = held + 1 if c[i] >= th else 0
            if d[i] < density:  # the density now, as CoverageSettled
                continue
            if held >= 2 or still(c, i, floor, window + 1) or \
                    (stall_floor is not None and still(c, i, stall_floor, stall_window)):
                return i + 1
        return r["n_abort"]
    return stop


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--method", default="C_H")
    ap.add_argument("--dir", default="default-20runs")
    ap.add_argument("meshes", nargs="+")
    a = ap.parse_args()
    def path(m):
        return os.path.join(m, "runs.jsonl") if os.path.isdir(m) else f"docs/eval/{m}/{a.dir}/runs.jsonl"
    def name(m):  # a docs/eval folder by its mesh, a directory by its last two path components
        return "/".join(m.rstrip("/").split("/")[-2:]) if os.path.isdir(m) else m
    runs = {name(m): [r for r in map(json.loads, open(path(m)))
                                              if r["method"] == a.method and len(r["scans"]["c_a"]) == r["n_abort"]]
            for m in a.meshes}
    print("| rule | " + " | ".join(f"{m}: n_s, c_a/c_obs, n_s − k99 (ok/early/late/runaway)" for m in runs) + " |")
    print("|---|" + "---:|" * len(runs))
    print("| k97 / k98 / k99 (truth) | " + " | ".join(
        f"{st.median(k_share(r, .97) for r in R):.1f} / {st.median(k_share(r, .98) for r in R):.1f} / "
        f"{st.median(k_share(r, .99) for r in R):.1f}" for R in runs.values()) + " |")
    rules = [(f"ĉ_m ≥ {th}" + (" (the thesis's rule)" if th == 0.8 else ""), threshold_rule(th))
             for th in (0.8, 0.85, 0.9, 0.94, 0.96)]
    rules += [(f"ĉ_m ≥ {th} on 2 consecutive scans", threshold_rule(th, consecutive=2)) for th in (0.8, 0.9, 0.93)]
    rules += [(f"ĉ_m gain over {w} scans < {dl}", stagnation_rule(w, dl)) for w in (2, 3) for dl in (0.005, 0.01)]
    rules += [("ĉ_m ≥ 0.9 on 2 consecutive scans, or ≥ 0.75 and within 0.03 over 3 scans",
               settled_rule(0.9, 0.75, 2, 0.03)),
              ("the same, or ≥ 0.5 and within 0.03 over 5 scans (CoverageSettled, the default)",
               settled_rule(0.9, 0.75, 2, 0.03, stall_floor=0.5))]
    for name, rule in rules:
        cells = []
        for R in runs.values():
            ns = [rule(r) for r in R]
            ks = [k_share(r, 0.99) for r in R]
            ca = [r["scans"]["c_a"][n - 1] / r["c_obs"] for r, n in zip(R, ns)]
            d = [n - k for n, k in zip(ns, ks)]
            ok = sum(abs(x) <= 2 for x in d)
            early = sum(x < -2 for x in d)
            runaway = sum(n >= r["n_abort"] and k <= r["n_abort"] for r, n, k in zip(R, ns, ks))
            cells.append(f"{st.median(ns):.1f}, {st.median(ca):.3f}, {st.median(d):+.1f} "
                         f"({ok}/{early}/{len(R) - ok - early}/{runaway})")
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
