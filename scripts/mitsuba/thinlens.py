#!/usr/bin/env python3
"""Reference region means of crates/ppm-scene/tests/data/mitsuba/cbox_thinlens.xml from Mitsuba 3.

The Cornell box seen through Mitsuba's `thinlens` sensor (aperture radius 0.15, focus
distance 3.3, fov 50 along x, 48 x 32 box-filtered film), rendered with the `path`
integrator (variant scalar_rgb). Renders SEEDS independent images and writes, for the whole
image and its four quadrants, the mean RGB over the seeds and the standard error of the
whole-image channel means, to thinlens_mitsuba.txt beside the scene:

    /work/venv-mitsuba/bin/python scripts/mitsuba/thinlens.py [samples-per-pixel] [seeds]
"""

import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data", "mitsuba")
SCENE = os.path.join(DATA, "cbox_thinlens.xml")
OUT = os.path.join(DATA, "thinlens_mitsuba.txt")


def regions(img):
    """The whole image and its quadrants (top-left, top-right, bottom-left, bottom-right)."""
    h, w = img.shape[0] // 2, img.shape[1] // 2
    return {
        "all": img,
        "top_left": img[:h, :w],
        "top_right": img[:h, w:],
        "bottom_left": img[h:, :w],
        "bottom_right": img[h:, w:],
    }


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 1024
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    scene = mi.load_file(SCENE)
    sums = {}
    per_seed = []
    for seed in range(seeds):
        img = np.array(mi.render(scene, spp=spp, seed=seed))[:, :, :3].astype(np.float64)
        for name, r in regions(img).items():
            sums[name] = sums.get(name, 0.0) + r.reshape(-1, 3).mean(axis=0)
        per_seed.append(img.reshape(-1, 3).mean(axis=0))
        print(f"seed {seed}: {per_seed[-1]}", flush=True)
    se = np.array(per_seed).std(axis=0, ddof=1) / np.sqrt(seeds) if seeds > 1 else np.zeros(3)
    with open(OUT, "w") as f:
        f.write(f"# Mitsuba {mi.__version__} scalar_rgb path, cbox_thinlens.xml, "
                f"{seeds} x {spp} spp: region mean_r mean_g mean_b\n")
        for name, s in sums.items():
            m = s / seeds
            f.write(f"{name} {m[0]:.6f} {m[1]:.6f} {m[2]:.6f}\n")
        f.write(f"se_all {se[0]:.6f} {se[1]:.6f} {se[2]:.6f}\n")
    print(open(OUT).read())


if __name__ == "__main__":
    main()
