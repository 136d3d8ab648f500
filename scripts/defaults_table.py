#!/usr/bin/env python3
"""Tables of scripts/defaults_study.sh: equal-time error of the old radius default against the
new `ppm` and `sppm` defaults, and of sppm's photons per iteration.

For each scene and configuration: the final relMSE of the SECONDS run (the mean of the last
three logged iterations, which steadies the value against one iteration's noise), its ratio
to the old default's, and the seconds to reach relMSE 0.05, 0.02 and 0.01.
"""
import csv
import glob
import os
import sys

THRESHOLDS = (0.05, 0.02, 0.01)
CONFIGS = ("old", "ppm-auto", "sppm-auto")


def load(path):
    """(seconds, relmse) points of a converge CSV, and its settings and last iteration."""
    points, settings = [], {}
    with open(path) as f:
        for row in csv.DictReader(f):
            points.append((float(row["seconds"]), float(row["relmse"])))
            settings = {k: row.get(k, "") for k in ("photons", "radius", "threads", "iteration")}
    return points, settings


def final(points):
    last = points[-3:]
    return sum(e for _, e in last) / len(last)


def crossing(points, threshold):
    return next((s for s, e in points if e <= threshold), None)


def main(out):
    print("| scene | configuration | radius | photons | final relMSE | vs old | "
          + " | ".join(f"s to {t}" for t in THRESHOLDS) + " |")
    print("|---|---|---|---|---|---|" + "---|" * len(THRESHOLDS))
    stems = sorted(os.path.basename(p).replace("_convergence.csv", "")
                   for p in glob.glob(f"{out}/old/*_convergence.csv"))
    for stem in stems:
        base = None
        for config in CONFIGS:
            path = f"{out}/{config}/{stem}_convergence.csv"
            if not os.path.exists(path):
                continue
            points, settings = load(path)
            e = final(points)
            base = e if config == "old" else base
            times = [crossing(points, t) for t in THRESHOLDS]
            cells = [f"{t:.2f}" if t is not None else f"> {points[-1][0]:.0f}" for t in times]
            print(f"| {stem} | {config} | {settings['radius']} | {settings['photons']} | {e:.4g} | "
                  f"{e / base:.2f} | " + " | ".join(cells) + " |")
    print()
    print("| scene | sppm photons per iteration | final relMSE | iterations in the run |")
    print("|---|---|---|---|")
    for path in sorted(glob.glob(f"{out}/photons-*/*_convergence.csv"),
                       key=lambda p: (os.path.basename(p), int(p.split("photons-")[1].split("/")[0]))):
        points, settings = load(path)
        stem = os.path.basename(path).replace("_convergence.csv", "")
        print(f"| {stem} | {settings['photons']} | {final(points):.4g} | {settings['iteration']} |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "defaults_study")
