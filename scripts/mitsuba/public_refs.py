#!/usr/bin/env python3
"""Reference renders of the public scenes of crates/ppm-scene/tests/data/public/, by Mitsuba 3.

Each scene (files from public repositories, see the SOURCE.md next to each) is rendered with
Mitsuba 3.9.1, variant scalar_rgb, with the integrator the file names (`path` when it names
none, which Mitsuba 3 then asks for), at the small size its `$name` parameters give (the same
defines ppm's tests/public_scenes.rs passes), for SEEDS independent seeds of SPP samples per
pixel each. Writes to crates/ppm-scene/tests/data/public/references/:

- `<scene>.exr`: the mean over the seeds of the image (linear RGB);
- `<scene>_var.exr`: per pixel and channel, the variance of that mean (the seeds' sample
  variance over SEEDS), which the test needs to tell noise from a difference;
- `references.csv`: per scene and channel the image mean and its standard error (the
  seeds' image means' standard deviation over sqrt(SEEDS)).

ppm has one pixel filter, the box (each pixel averages the samples inside it), and warns when
a file asks for another. So that the per-pixel comparison measures everything but that, the
references are rendered with `<rfilter type="gaussian"/>` replaced by the box filter, in a
temporary copy of the scene's folder; the committed files keep the filter they were written
with. (The image mean does not depend on the filter, which is normalised.)

Run from anywhere, with Mitsuba 3.9.1 installed (`pip install mitsuba==3.9.1 numpy`):

    /work/venv-mitsuba/bin/python scripts/mitsuba/public_refs.py [spp] [seeds] [names]

Defaults: 256 samples per pixel (2048 for veach-mis, whose small lights make it noisy),
8 seeds, every scene (about 25 minutes on a busy core); `names` (comma-separated) renders
only those and keeps the other rows.
"""

import os
import re
import shutil
import sys
import tempfile

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data", "public")
OUT = os.path.join(DATA, "references")

# name -> (folder under DATA, scene file inside it, defines). Keep in step with
# crates/ppm-scene/tests/public_scenes.rs.
SCENES = {
    "cbox": ("mitsuba-cbox", "cbox.xml", {"res": "64"}),
    "cbox-rgb": ("mitsuba-cbox", "cbox-rgb.xml", {"res": "64"}),
    "matpreview": ("mitsuba-matpreview", "matpreview.xml", {"width": "64", "height": "48"}),
    "veach-mis": ("veach-mis", "veach_mis.xml", {"width": "72", "height": "48"}),
    "copper": (
        "mitsuba-docs",
        "docs/scenes/bsdf_roughconductor_copper.xml",
        {"width": "64", "height": "48"},
    ),
    "twosided-cbox": (
        "mitsuba-docs",
        "docs/scenes/bsdf_twosided_cbox.xml",
        {"width": "64", "height": "64"},
    ),
}
# Samples per pixel where the default is too noisy.
SPP = {"veach-mis": 2048}
HEADER = "scene,spp,seeds,mean_r,mean_g,mean_b,se_r,se_g,se_b"
GAUSSIAN = re.compile(r'<rfilter\s+type="gaussian"\s*/>')


def box_filtered_copy(folder, tmp):
    """A copy of `folder` in `tmp` whose XML files use the box filter; returns its path."""
    copy = os.path.join(tmp, os.path.basename(folder))
    shutil.copytree(folder, copy)
    for root, _, files in os.walk(copy):
        for f in files:
            if f.endswith(".xml"):
                path = os.path.join(root, f)
                text = open(path).read()
                open(path, "w").write(GAUSSIAN.sub('<rfilter type="box"/>', text))
    return copy


def write_exr(path, image):
    mi.Bitmap(np.ascontiguousarray(image, dtype=np.float32),
              pixel_format=mi.Bitmap.PixelFormat.RGB).write(path)


def read_rows(csv):
    """The rows of an existing references CSV by scene name (none if it does not exist)."""
    rows = {}
    if os.path.exists(csv):
        for line in open(csv).read().splitlines()[1:]:
            rows[line.split(",")[0]] = line
    return rows


def record(name, spp, seeds, render, rows):
    """Renders `seeds` images with render(seed), writes OUT/<name>.exr (their mean) and
    OUT/<name>_var.exr (the variance of that mean), and puts the scene's CSV row (image means
    per channel and their standard errors over the seeds) in `rows`."""
    images = np.array([render(seed)[:, :, :3] for seed in range(seeds)])
    write_exr(os.path.join(OUT, name + ".exr"), images.mean(axis=0))
    write_exr(os.path.join(OUT, name + "_var.exr"), images.var(axis=0, ddof=1) / seeds)
    means = images.reshape(seeds, -1, 3).mean(axis=1)
    mean = means.mean(axis=0)
    se = means.std(axis=0, ddof=1) / np.sqrt(seeds)
    row = [name, str(spp), str(seeds)] + ["%.6g" % v for v in mean] + ["%.3g" % v for v in se]
    rows[name] = ",".join(row)
    print(rows[name], flush=True)


def write_rows(csv, rows, order):
    """Writes `rows` to `csv` in the order of the names in `order`."""
    with open(csv, "w") as f:
        f.write("\n".join([HEADER] + [rows[n] for n in order if n in rows]) + "\n")


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    default_spp = int(args[0]) if len(args) > 0 else None
    seeds = int(args[1]) if len(args) > 1 else 8
    only = args[2].split(",") if len(args) > 2 else list(SCENES)
    os.makedirs(OUT, exist_ok=True)
    csv = os.path.join(OUT, "references.csv")
    rows = read_rows(csv)
    for name in only:
        folder, file, defines = SCENES[name]
        spp = default_spp or SPP.get(name, 256)
        with tempfile.TemporaryDirectory() as tmp:
            copy = box_filtered_copy(os.path.join(DATA, folder), tmp)
            scene = mi.load_file(os.path.join(copy, file), **defines)
            integrator = scene.integrator() or mi.load_dict({"type": "path"})
            record(name, spp, seeds,
                   lambda seed: np.array(mi.render(scene, integrator=integrator, spp=spp,
                                                   seed=seed)), rows)
    write_rows(csv, rows, SCENES)


if __name__ == "__main__":
    main()
