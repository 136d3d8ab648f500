#!/usr/bin/env python3
"""Time to reach relMSE thresholds, from `ppm converge` CSVs (algorithm,seed,iteration,seconds,relmse,rmse).

Prints a Markdown table: scene, threads, algorithm, seconds to reach relMSE 0.05 / 0.02 / 0.01
(first logged point at or below the threshold; '>T' if the run of T seconds never got there).
With --interpolate, the crossing is interpolated log-log between the last point above the
threshold and the first at or below it: for runs logged sparsely (another renderer run at 1, 2,
4, ... iterations), where the first point below can be up to twice as late as the crossing.
"""
import csv
import math
import os
import sys

THRESHOLDS = (0.05, 0.02, 0.01)


def crossing(points, threshold, interpolate):
    """Seconds at which the sorted (seconds, relmse) points first reach `threshold`, or None."""
    for i, (s, e) in enumerate(points):
        if e <= threshold:
            if not interpolate or i == 0:
                return s
            (s0, e0) = points[i - 1]
            f = (math.log(e0) - math.log(threshold)) / (math.log(e0) - math.log(e))
            return math.exp(math.log(s0) + f * (math.log(s) - math.log(s0)))
    return None


def main(paths, interpolate=False):
    print("| scene | threads | algorithm | " + " | ".join(f"relMSE {t}" for t in THRESHOLDS) + " | final relMSE |")
    print("|---|---|---|" + "---|" * (len(THRESHOLDS) + 1))
    for path in sorted(paths):
        scene = os.path.basename(path).replace("_convergence.csv", "").replace(".csv", "")
        folder = os.path.basename(os.path.dirname(path))
        threads = folder.replace("threads", "") if folder.startswith("threads") else "-"
        runs = {}
        with open(path) as f:
            for row in csv.DictReader(f):
                runs.setdefault(row["algorithm"], []).append((float(row["seconds"]), float(row["relmse"])))
        for algorithm, points in sorted(runs.items()):
            points.sort()
            cells = []
            for t in THRESHOLDS:
                hit = crossing(points, t, interpolate)
                cells.append(f"{hit:.2f} s" if hit is not None else f"> {points[-1][0]:.0f} s")
            print(f"| {scene} | {threads} | {algorithm} | " + " | ".join(cells) + f" | {points[-1][1]:.4f} |")


if __name__ == "__main__":
    args = sys.argv[1:]
    interpolate = "--interpolate" in args
    main([a for a in args if a != "--interpolate"], interpolate)
