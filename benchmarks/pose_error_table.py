#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The pose-error table of docs/evaluation.md (issue 20) from nbs_eval output directories.

Usage: benchmarks/pose_error_table.py DIR...   each DIR/runs.jsonl of one (mesh, configuration) run set, made by
  nbs_eval --methods C_H --runs 20 --pose-error T,R [--registration icp] --out DIR
Prints one Markdown row per DIR: runs, median n_s, mean c_a(30) %, mean ē(30) in the world frame and in the model's
frame (vertices mapped by the first scan's error E1⁻¹), mean double-surface share (world, model frame), mean
relative residual pose error over scans 2… (mm, deg) and the mean registration time per scan (ms).
"""
import json
import statistics
import sys


def row(d):
    runs = [json.loads(line) for line in open(f"{d}/runs.jsonl") if line.strip()]
    s = [r["scans"] for r in runs]
    mean = statistics.mean
    rel_t = mean(mean(x["pose_rel_t_mm"][1:]) for x in s)
    rel_r = mean(mean(x["pose_rel_r_deg"][1:]) for x in s)
    icp_ms = 1e3 * mean(mean(x["icp_s"]) for x in s)
    return (f"| {d} | {len(runs)} | {statistics.median(r['n_s'] for r in runs):.1f} | "
            f"{100 * mean(x['c_a'][-1] for x in s):.2f} | {1e3 * mean(x['e_bar_m'][-1] for x in s):.3f} | "
            f"{1e3 * mean(x['e_bar_rel_m'][-1] for x in s):.3f} | "
            f"{100 * mean(r['double_surface_share'] for r in runs):.2f} | "
            f"{100 * mean(r['double_surface_share_rel'] for r in runs):.2f} | {rel_t:.3f} | {rel_r:.3f} | {icp_ms:.1f} |")


if __name__ == "__main__":
    print("| runs | n | median n_s | mean c_a(30) % | ē(30) world / mm | ē(30) model frame / mm | double surface world % "
          "| double surface model frame % | residual / mm | residual / deg | registration / ms |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for d in sys.argv[1:]:
        print(row(d.rstrip("/")))
