#!/usr/bin/env python3
"""Reference image means of the Mitsuba importer's render tests, from Mitsuba 3 (the oracle).

Renders each scene of crates/ppm-scene/tests/data/mitsuba/renders/ (the XML files ppm's
tests/mitsuba_renders.rs loads through its importer) with Mitsuba 3.9.1, variant scalar_rgb,
at 32 x 32 with the integrator the scene names, for SEEDS independent seeds
of SPP samples per pixel each. Writes references.csv next to the scenes: per scene and
channel the mean over the seeds of the image mean, and its standard error (the seeds' sample
standard deviation over sqrt(SEEDS)).

Run from anywhere, with Mitsuba 3.9.1 installed (see scripts/mitsuba/bsdf_values.py):

    /work/venv-mitsuba/bin/python scripts/mitsuba/importer_references.py [spp] [seeds] [names]

Defaults: 2048 samples per pixel, 8 seeds, every scene (about 20 minutes on a busy core);
`names` (comma-separated, as in the table) renders only those and keeps the other rows.
The rough-lobe rows (`rough_lobe_metal/<alpha>`, `rough_lobe_glass/<alpha>`, read by
tests/rough_lobes.rs) were rendered at 512 samples per pixel:

    /work/venv-mitsuba/bin/python scripts/mitsuba/importer_references.py 512 8 \
        rough_lobe_metal/0.001,rough_lobe_metal/0.01,...,rough_lobe_glass/0.5 With
--png also writes /tmp/<scene>.png previews (not used by the tests).
"""

import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data", "mitsuba", "renders")
OUT = os.path.join(DATA, "references.csv")

# The scenes, in the order of the table: name -> (file relative to DATA, parameters given
# as the scene's `$name` defaults). Ours include stage.xml and lamp.xml.
SCENES = {
    "rough_gold": ("rough_gold.xml", {}),
    "rough_gold_beckmann": ("rough_gold_beckmann.xml", {}),
    "frosted_glass": ("frosted_glass.xml", {}),
    "plastic": ("plastic.xml", {}),
    "rough_plastic": ("rough_plastic.xml", {}),
    "thin_pane": ("thin_pane.xml", {}),
    "spot": ("spot.xml", {}),
    "directional": ("directional.xml", {}),
    "floor_lamp": ("floor_lamp.xml", {}),
    "water_glass": ("water_glass.xml", {}),
    # A crop window of the film: Mitsuba's image is the crop's size.
    "cropped_plastic": ("cropped_plastic.xml", {}),
}
# The rough-lobe scenes (tests/rough_lobes.rs, docs/rough-lobes.md) at each roughness.
ROUGHNESSES = ["0.001", "0.01", "0.05", "0.1", "0.23", "0.5"]
for _kind in ["metal", "glass"]:
    for _alpha in ROUGHNESSES:
        SCENES["rough_lobe_%s/%s" % (_kind, _alpha)] = ("rough_lobe_%s.xml" % _kind, {"alpha": _alpha})
HEADER = "scene,spp,seeds,mean_r,mean_g,mean_b,se_r,se_g,se_b"


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    spp = int(args[0]) if len(args) > 0 else 2048
    seeds = int(args[1]) if len(args) > 1 else 8
    only = args[2].split(",") if len(args) > 2 else list(SCENES)
    png = "--png" in sys.argv
    # Rows of scenes not rendered this time are kept.
    rows = {}
    if os.path.exists(OUT):
        for line in open(OUT).read().splitlines()[1:]:
            rows[line.split(",")[0]] = line
    for name in only:
        path, params = SCENES[name]
        scene = mi.load_file(os.path.join(DATA, path), **params)
        means = []
        for seed in range(seeds):
            image = np.array(mi.render(scene, spp=spp, seed=seed))[:, :, :3]
            means.append(image.reshape(-1, 3).mean(axis=0))
            if png and seed == 0:
                mi.util.write_bitmap(os.path.join("/tmp", name.replace("/", "_") + ".png"), image)
        means = np.array(means)
        mean = means.mean(axis=0)
        se = means.std(axis=0, ddof=1) / np.sqrt(seeds)
        row = [name, str(spp), str(seeds)] + ["%.6g" % v for v in mean] + ["%.3g" % v for v in se]
        rows[name] = ",".join(row)
        print(rows[name], flush=True)
    with open(OUT, "w") as f:
        f.write("\n".join([HEADER] + [rows[n] for n in SCENES if n in rows]) + "\n")


if __name__ == "__main__":
    main()
