#!/usr/bin/env python3
"""The mean colour of the left and right halves of Mitsuba 3's render of the Cornell box
(crates/ppm-scene/tests/data/mitsuba/cbox.xml): the red wall makes the left half redder, the
green one the right half greener, so these two rows tell a mirrored image from the right one.

Writes crates/ppm-scene/tests/data/pbrt/cbox_mitsuba_halves.csv (read by
crates/ppm-scene/tests/pbrt_build.rs, which renders the pbrt-v4 version of the box,
tests/data/pbrt/cbox.pbrt, with ppm and compares). Columns: half (left | right), r, g, b.

Run from the repository root with Mitsuba 3.9.1 (scalar_rgb variant); about a minute:
  /work/venv-mitsuba/bin/python scripts/mitsuba/cbox_halves.py
"""
import os

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

RES = 16
SPP = 4096

root = os.path.join(os.path.dirname(__file__), "..", "..")
data = os.path.join(root, "crates", "ppm-scene", "tests", "data")
scene = mi.load_file(os.path.join(data, "mitsuba", "cbox.xml"), res=RES)
image = np.array(mi.render(scene, spp=SPP, seed=1))[:, :, :3]
half = RES // 2
rows = [("left", image[:, :half].mean(axis=(0, 1))), ("right", image[:, half:].mean(axis=(0, 1)))]
with open(os.path.join(data, "pbrt", "cbox_mitsuba_halves.csv"), "w") as f:
    f.write("half,r,g,b\n")
    for name, c in rows:
        f.write(f"{name},{c[0]:.6f},{c[1]:.6f},{c[2]:.6f}\n")
for name, c in rows:
    print(name, c)
