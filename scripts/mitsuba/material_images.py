#!/usr/bin/env python3
"""Reference images of the per-model material scenes, by Mitsuba 3 (the oracle).

The pixelwise counterpart of importer_references.py (which gives image means only): each
scene one BSDF model is shown in (a rough gold sphere, GGX and Beckmann, frosted glass, a
plastic, a rough plastic, a thin pane, water in a glass: the XML files of
crates/ppm-scene/tests/data/mitsuba/renders/; and the textured floor of
texture_reference.py, its bitmap and checkerboard lit from straight above) is rendered by
Mitsuba 3.9.1, variant scalar_rgb, 32 x 32, box filter, with the integrator the scene names,
for SEEDS independent seeds of SPP samples per pixel each. Writes, into
crates/ppm-scene/tests/data/mitsuba/renders/images/:

- `<scene>.exr`: the mean over the seeds of the image (linear RGB, float32);
- `<scene>_var.exr`: per pixel and channel, the variance of that mean (the seeds' sample
  variance over SEEDS): Mitsuba's own noise, which ppm's test (tests/mitsuba_renders.rs)
  adds to ppm's to get the relative MSE that noise alone gives.

Run from anywhere, with Mitsuba 3.9.1 installed (`pip install mitsuba==3.9.1 numpy`):

    /work/venv-mitsuba/bin/python scripts/mitsuba/material_images.py [spp] [seeds] [names]

Defaults: 1024 samples per pixel, 8 seeds (8192 samples per pixel in all, 32 times ppm's
test, so Mitsuba's noise is a few percent of the expected relMSE), every scene (about 10
minutes on a busy core); `names` (comma-separated) renders only those.
"""

import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import texture_reference  # noqa: E402  (its FLOOR scene and grid.png)

TESTS = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data")
RENDERS = os.path.join(TESTS, "mitsuba", "renders")
TEXTURES = os.path.join(TESTS, "textures")
OUT = os.path.join(RENDERS, "images")

# The scenes: name -> a function loading it. Keep in step with tests/mitsuba_renders.rs.
SCENES = {
    name: (lambda name=name: mi.load_file(os.path.join(RENDERS, name + ".xml")))
    for name in [
        "rough_gold",
        "rough_gold_beckmann",
        "frosted_glass",
        "plastic",
        "rough_plastic",
        "thin_pane",
        "water_glass",
    ]
}
SCENES["textured_floor"] = lambda: mi.load_string(
    texture_reference.FLOOR.format(spp=64, grid=os.path.join(TEXTURES, "grid.png"))
)


def write_exr(path, image):
    mi.Bitmap(np.ascontiguousarray(image, dtype=np.float32),
              pixel_format=mi.Bitmap.PixelFormat.RGB).write(path)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    spp = int(args[0]) if len(args) > 0 else 1024
    seeds = int(args[1]) if len(args) > 1 else 8
    only = args[2].split(",") if len(args) > 2 else list(SCENES)
    os.makedirs(OUT, exist_ok=True)
    for name in only:
        scene = SCENES[name]()
        images = np.array([
            np.array(mi.render(scene, spp=spp, seed=seed))[:, :, :3] for seed in range(seeds)
        ])
        mean = images.mean(axis=0)
        var = images.var(axis=0, ddof=1) / seeds
        write_exr(os.path.join(OUT, name + ".exr"), mean)
        write_exr(os.path.join(OUT, name + "_var.exr"), var)
        rel = var.mean() / (mean ** 2 + 0.01).mean()
        print("%s: %d x %d spp, image mean %s, mean variance / (m^2 + 0.01) %.3g"
              % (name, seeds, spp, mean.reshape(-1, 3).mean(axis=0), rel), flush=True)


if __name__ == "__main__":
    main()
