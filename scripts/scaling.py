#!/usr/bin/env python3
"""Thread scaling of each pass, measured as ratios on a noisy machine.

Runs the same render at 1 and at 2 threads alternately (so that both see the same machine
load), K times each, reads the summary lines of `ppm` and prints, for every pass, the
min/median/max seconds at each thread count and the speed-up as the ratio of the medians and
of the minimums (the least disturbed runs).

A third configuration tells the machine's part from ppm's: two 1-thread renders at once, in
separate processes, which share nothing. Their time per render is what one core delivers
while the other is busy too, so `pair / (2 x two-thread time)` is the parallel efficiency of
ppm itself, and `alone / pair` is what the machine loses when both cores work.

Usage: scripts/scaling.py [K] [-- extra ppm arguments]
Default: the speed benchmark render of docs/performance.md, cornell_box_specular.yml
--photons 262144 at 512x512, 6 iterations.
"""

import re
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PPM = ROOT / "target" / "release" / "ppm"
DEFAULT = ["cornell_box_specular.yml", "--photons", "262144", "--width", "512",
           "--height", "512", "-n", "6"]


def start(args, threads, tag):
    """Starts one render."""
    return subprocess.Popen(
        [str(PPM), *args, "--threads", str(threads), "-o", f"/tmp/ppm_scaling_{tag}.png"],
        cwd=ROOT / "scenes", stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)


def parse(process):
    """Waits for a render; returns {"total": s, "photon": s, "grid": s, "eye": s, "film": s}."""
    out = process.communicate()[1]
    if process.returncode != 0:
        sys.exit(f"ppm failed:\n{out}")
    times = {"total": float(re.search(r"iterations in ([0-9.]+) s", out).group(1))}
    passes = re.search(r"^passes: (.*)$", out, re.M).group(1)
    for name, seconds in re.findall(r"(\w+) ([0-9.]+) s", passes):
        times[name] = float(seconds)
    return times


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    k = int(argv[0]) if argv else 5
    args = extra or DEFAULT
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    runs = {"one": [], "two": [], "pair": []}
    for _ in range(k):
        runs["one"].append(parse(start(args, 1, "one")))
        runs["two"].append(parse(start(args, 2, "two")))
        pair = [start(args, 1, "pair_a"), start(args, 1, "pair_b")]
        runs["pair"].extend(parse(p) for p in pair)
    med = lambda name, key: statistics.median(r[key] for r in runs[name])
    print(f"ppm {' '.join(args)}: {k} rounds of (1 thread, 2 threads, two 1-thread renders at once)")
    print(f"{'pass':7} {'1 thread':>17} {'2 threads':>17} {'pair, each':>17}"
          f" {'speed-up':>9} {'(min)':>6} {'efficiency':>11} {'machine':>8}")
    for key in ["total", "photon", "grid", "eye", "film"]:
        if key not in runs["one"][0]:
            continue
        fmt = lambda name: "{:.2f}/{:.2f}/{:.2f}".format(
            min(r[key] for r in runs[name]), med(name, key), max(r[key] for r in runs[name]))
        two = max(med("two", key), 1e-9)
        speedup = med("one", key) / two
        best = min(r[key] for r in runs["one"]) / max(min(r[key] for r in runs["two"]), 1e-9)
        efficiency = med("pair", key) / (2 * two)
        machine = med("one", key) / max(med("pair", key), 1e-9)
        print(f"{key:7} {fmt('one'):>17} {fmt('two'):>17} {fmt('pair'):>17}"
              f" {speedup:>8.2f}x {best:>5.2f}x {efficiency:>10.0%} {machine:>8.2f}")
    print("seconds as min/median/max; speed-up = median 1 thread / median 2 threads (and of the")
    print("minimums); efficiency = median pair / (2 x median 2 threads); machine = median 1 thread")
    print("/ median pair (below 1: one core is slower while the other works)")


if __name__ == "__main__":
    main()
