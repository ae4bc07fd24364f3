#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""How well does ĉ_m's missing surface (CoverageResult::unseen, SGU's input) locate the surface still missing?

Reads the dumps of one nbs_diagnose run with NBS_DIAG_UNCOVERED=U and NBS_DIAG_UNSEEN=S (U_<scan>.csv: the ground
truth samples not yet covered; S_<scan>.csv: the unseen fan samples with their area and distance from the loop's edge)
and prints per scan and per minimum edge distance d_min (the samples nearer their loop's edge are left out):
precision = share of the kept samples' area within R of an uncovered truth sample, recall = share of the uncovered
truth samples within R of a kept sample.

usage: benchmarks/unseen_locator.py U S SCAN... [--radius 0.006] [--dmin 0,0.005,0.0075,0.01,0.015]
"""
import argparse
import csv
from collections import defaultdict


def load(path):
    with open(path) as f:
        return [r for r in csv.DictReader(f)]


class Grid:
    def __init__(self, points, r):
        self.r, self.points, self.cells = r, points, defaultdict(list)
        for i, p in enumerate(points):
            self.cells[self.key(p)].append(i)

    def key(self, p):
        return tuple(int(c // self.r) for c in p)

    def near(self, q):
        k = self.key(q)
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for i in self.cells.get((k[0] + dx, k[1] + dy, k[2] + dz), ()):
                        if sum((a - b) ** 2 for a, b in zip(self.points[i], q)) <= self.r * self.r:
                            return True
        return False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("uncovered")
    ap.add_argument("unseen")
    ap.add_argument("scans", nargs="+")
    ap.add_argument("--radius", type=float, default=0.006)
    ap.add_argument("--dmin", default="0,0.005,0.0075,0.01,0.015")
    a = ap.parse_args()
    dmins = [float(d) for d in a.dmin.split(",")]
    print("scan | uncovered | " + " | ".join("d_min %g m: n, precision, recall" % d for d in dmins))
    for s in a.scans:
        truth = [tuple(float(r[c]) for c in "xyz") for r in load("%s_%s.csv" % (a.uncovered, s))]
        rows = load("%s_%s.csv" % (a.unseen, s))
        tg = Grid(truth, a.radius)
        cells = []
        for d in dmins:
            kept = [(tuple(float(r[c]) for c in "xyz"), float(r["area"])) for r in rows if float(r["d"]) >= d]
            if not kept:
                cells.append("0, -, -")
                continue
            area = sum(w for _, w in kept)
            precision = sum(w for p, w in kept if tg.near(p)) / area if area > 0 else 0.0
            kg = Grid([p for p, _ in kept], a.radius)
            recall = sum(1 for p in truth if kg.near(p)) / max(1, len(truth))
            cells.append("%d, %.2f, %.2f" % (len(kept), precision, recall))
        print("%s | %d | %s" % (s, len(truth), " | ".join(cells)))


if __name__ == "__main__":
    main()
