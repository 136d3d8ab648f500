#!/usr/bin/env python3
"""Reference image means of crates/ppm-scene/tests/data/mitsuba/absorbing_sphere.xml from Mitsuba 3.

A glass sphere (ior 1.5) filled with a purely absorbing homogeneous medium (albedo 0,
sigma_t = (0.125, 0.5, 1) times scale 3.2 per unit length: Beer-Lambert absorption, which
ppm writes as `absorption` on the glass), on a diffuse floor under a square area light, rendered by
Mitsuba 3's `volpath` (variant scalar_rgb) at 32 x 32. The same XML file is loaded by ppm's
Mitsuba importer in crates/ppm-scene/tests/mitsuba_absorption.rs, which compares ppm's
image mean with the mean written here.

Renders SEEDS independent images and writes their image means (over pixels and the three
channels, and per channel) and the mean and standard error of those to
crates/ppm-scene/tests/data/mitsuba/absorbing_sphere_mitsuba.txt:

    /work/venv-mitsuba/bin/python scripts/mitsuba/absorption_reference.py [samples-per-pixel] [seeds]
"""

import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data", "mitsuba")
SCENE = os.path.join(DATA, "absorbing_sphere.xml")
OUT = os.path.join(DATA, "absorbing_sphere_mitsuba.txt")


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 1024
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 8
    scene = mi.load_file(SCENE, res=32)
    rows = []
    for seed in range(seeds):
        image = np.array(mi.render(scene, spp=spp, seed=seed))[:, :, :3]
        rows.append([float(image.mean())] + [float(image[:, :, c].mean()) for c in range(3)])
        print(f"seed {seed}: image mean {rows[-1][0]:.6f}", flush=True)
    m = np.array(rows)
    mean = m.mean(axis=0)
    se = m.std(axis=0, ddof=1) / np.sqrt(len(m))
    with open(OUT, "w") as f:
        f.write("# Mitsuba 3 (scalar_rgb, volpath) image means of absorbing_sphere.xml, written by\n")
        f.write("# scripts/mitsuba/absorption_reference.py: one line per seed (mean over pixels and\n")
        f.write("# channels, then red, green, blue), then the mean and its standard error.\n")
        f.write(f"# {spp} samples per pixel, {seeds} seeds, mitsuba {mi.__version__}.\n")
        for seed, r in enumerate(rows):
            f.write(f"seed {seed} " + " ".join(f"{v:.7f}" for v in r) + "\n")
        f.write("mean " + " ".join(f"{v:.7f}" for v in mean) + "\n")
        f.write("standard_error " + " ".join(f"{v:.7f}" for v in se) + "\n")
    print(f"mean {mean[0]:.6f} +- {se[0]:.6f} ({100 * se[0] / mean[0]:.3f}%)")


if __name__ == "__main__":
    main()
