#!/usr/bin/env python3
"""Reference image means for crates/ppm-scene/tests/data/mitsuba/envmap/envmap.xml from Mitsuba 3.

Writes a tiny lat-long radiance map (sky.exr, 32 x 16: a blue sky brightening toward the
zenith, a dark ground, a bright 2 x 1 texel sun, coloured so that no symmetry hides a wrong
orientation) and a Mitsuba scene lighting a diffuse floor and a diffuse sphere with it
(`envmap`, scale 1.5, turned 30 degrees about y); renders the scene with Mitsuba 3's `path`
integrator (variant scalar_rgb, 32 x 32, box filter) SEEDS times and writes each render's
image mean (over pixels and the three channels), their mean and standard error, and the
mean of each channel, to envmap_mitsuba.txt next to the scene. The Rust test
(crates/ppm-scene/tests/environment.rs) loads the same XML through ppm's Mitsuba importer.

    /work/venv-mitsuba/bin/python scripts/mitsuba/envmap_reference.py [samples-per-pixel] [seeds]
"""

import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
DIR = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data", "mitsuba",
                   "envmap")

SCENE = """<scene version="3.0.0">
    <default name="spp" value="64"/>
    <default name="seed" value="0"/>
    <integrator type="path">
        <integer name="max_depth" value="8"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world">
            <lookat origin="0, 1.2, 3" target="0, 0.3, 0" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
            <integer name="seed" value="$seed"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="32"/>
            <integer name="height" value="32"/>
            <rfilter type="box"/>
            <string name="pixel_format" value="rgb"/>
        </film>
    </sensor>
    <!-- The floor: the rectangle [-1, 1]^2 in z = 0, turned to face +y, 4 x 4. -->
    <shape type="rectangle">
        <transform name="to_world">
            <rotate x="1" angle="-90"/>
            <scale value="2"/>
        </transform>
        <bsdf type="diffuse">
            <rgb name="reflectance" value="0.5, 0.5, 0.5"/>
        </bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0.5" z="0"/>
        <float name="radius" value="0.5"/>
        <bsdf type="diffuse">
            <rgb name="reflectance" value="0.7, 0.3, 0.2"/>
        </bsdf>
    </shape>
    <emitter type="envmap">
        <string name="filename" value="sky.exr"/>
        <float name="scale" value="1.5"/>
        <transform name="to_world">
            <rotate y="1" angle="30"/>
        </transform>
    </emitter>
</scene>
"""


def sky():
    """32 x 16 RGB radiance, row 0 at the top (+y)."""
    w, h = 32, 16
    img = np.zeros((h, w, 3), dtype=np.float32)
    for i in range(h):
        for j in range(w):
            if i < h // 2:
                img[i, j] = np.array([0.3, 0.5, 0.9]) * (1.5 - i / h) + [0.2 * j / w, 0, 0]
            else:
                img[i, j] = [0.1, 0.08, 0.05]
    img[4, 5:7] = [900.0, 800.0, 600.0]
    return img


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 1024
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 8
    os.makedirs(DIR, exist_ok=True)
    mi.Bitmap(sky()).write(os.path.join(DIR, "sky.exr"))
    xml = os.path.join(DIR, "envmap.xml")
    with open(xml, "w") as f:
        f.write(SCENE)
    means, channels = [], []
    for seed in range(seeds):
        scene = mi.load_file(xml, spp=spp, seed=seed)
        img = np.array(mi.render(scene, spp=spp, seed=seed))
        channels.append(img.reshape(-1, 3).mean(axis=0))
        means.append(float(img.mean()))
        print(f"seed {seed}: {means[-1]:.6f}", flush=True)
    m = np.mean(means)
    se = np.std(means, ddof=1) / np.sqrt(len(means))
    ch = np.mean(channels, axis=0)
    with open(os.path.join(DIR, "envmap_mitsuba.txt"), "w") as f:
        f.write(f"# Mitsuba 3 {mi.__version__} path, scalar_rgb, 32x32, {spp} spp, "
                f"{seeds} seeds: image mean per seed\n")
        for v in means:
            f.write(f"render {v:.7f}\n")
        f.write(f"mean {m:.7f}\n")
        f.write(f"se {se:.7f}\n")
        f.write(f"channels {ch[0]:.7f} {ch[1]:.7f} {ch[2]:.7f}\n")
    print(f"mean {m:.6f} +- {se:.6f}, channels {ch}")


if __name__ == "__main__":
    main()
