#!/usr/bin/env python3
"""Time to reach relMSE thresholds, from `ppm converge` CSVs (algorithm,seed,iteration,seconds,relmse,rmse).

Prints a Markdown table: scene, threads, algorithm, seconds to reach relMSE 0.05 / 0.02 / 0.01
(first logged point at or below the threshold; '>T' if the run of T seconds never got there).
"""
import csv
import os
import sys

THRESHOLDS = (0.05, 0.02, 0.01)


def main(paths):
    print("| scene | threads | algorithm | " + " | ".join(f"relMSE {t}" for t in THRESHOLDS) + " | final relMSE |")
    print("|---|---|---|" + "---|" * (len(THRESHOLDS) + 1))
    for path in sorted(paths):
        scene = os.path.basename(path).replace("_convergence.csv", "")
        threads = os.path.basename(os.path.dirname(path)).replace("threads", "")
        runs = {}
        with open(path) as f:
            for row in csv.DictReader(f):
                runs.setdefault(row["algorithm"], []).append((float(row["seconds"]), float(row["relmse"])))
        for algorithm, points in sorted(runs.items()):
            points.sort()
            cells = []
            for t in THRESHOLDS:
                hit = next((s for s, e in points if e <= t), None)
                cells.append(f"{hit:.2f} s" if hit is not None else f"> {points[-1][0]:.0f} s")
            print(f"| {scene} | {threads} | {algorithm} | " + " | ".join(cells) + f" | {points[-1][1]:.4f} |")


if __name__ == "__main__":
    main(sys.argv[1:])
