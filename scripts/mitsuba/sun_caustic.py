#!/usr/bin/env python3
"""Reference image means for crates/ppm-core/tests/data/sun_caustic.yml from Mitsuba 3.

A sun (directional light, irradiance 1 W/m^2) through a glass sphere (ior 1.5) onto a
diffuse floor (reflectance 0.5), rendered by Mitsuba 3's light tracer `ptracer` (variant
scalar_rgb), which handles the caustic of a delta light through glass. The scene is written
here by hand to match the ppm YAML: same camera (vertical fov 30, 32 x 32, box filter), floor,
sphere and light. The sphere is out of the frame because a light tracer cannot render a
camera looking into glass.

Renders SEEDS independent images and writes their image means (over pixels and the three
channels) and the mean and standard error of those to sun_caustic_mitsuba.txt:

    /work/venv-mitsuba/bin/python scripts/mitsuba/sun_caustic.py [samples-per-pixel] [seeds]
"""

import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "..", "crates", "ppm-core", "tests", "data",
                   "sun_caustic_mitsuba.txt")

SCENE = """
<scene version="3.0.0">
  <integrator type="ptracer">
    <integer name="max_depth" value="32"/>
  </integrator>
  <sensor type="perspective">
    <float name="fov" value="30"/>
    <string name="fov_axis" value="y"/>
    <transform name="to_world">
      <lookat origin="0, 0.3, 1.8" target="0, 0, 0" up="0, 1, 0"/>
    </transform>
    <sampler type="independent">
      <integer name="sample_count" value="{spp}"/>
      <integer name="seed" value="{seed}"/>
    </sampler>
    <film type="hdrfilm">
      <integer name="width" value="32"/>
      <integer name="height" value="32"/>
      <rfilter type="box"/>
      <string name="pixel_format" value="rgb"/>
    </film>
  </sensor>
  <!-- The floor: Mitsuba's rectangle is [-1, 1]^2 in z = 0 facing +z; turned to face +y
       and scaled to 6 x 6. -->
  <shape type="rectangle">
    <transform name="to_world">
      <rotate x="1" angle="-90"/>
      <scale value="3"/>
    </transform>
    <bsdf type="diffuse">
      <rgb name="reflectance" value="0.5, 0.5, 0.5"/>
    </bsdf>
  </shape>
  <shape type="sphere">
    <point name="center" x="0" y="1.2" z="0"/>
    <float name="radius" value="0.5"/>
    <bsdf type="dielectric">
      <float name="int_ior" value="1.5"/>
      <float name="ext_ior" value="1.0"/>
    </bsdf>
  </shape>
  <emitter type="directional">
    <vector name="direction" x="0.2" y="-1.0" z="0.1"/>
    <rgb name="irradiance" value="1, 1, 1"/>
  </emitter>
</scene>
"""


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 4096
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 8
    means = []
    for seed in range(seeds):
        scene = mi.load_string(SCENE.format(spp=spp, seed=seed))
        image = np.array(mi.render(scene, spp=spp, seed=seed))
        means.append(float(image[:, :, :3].mean()))
        print(f"seed {seed}: image mean {means[-1]:.6f}", flush=True)
    m = np.array(means)
    mean, se = m.mean(), m.std(ddof=1) / np.sqrt(len(m))
    with open(OUT, "w") as f:
        f.write("# Mitsuba 3 (scalar_rgb, ptracer) image means of sun_caustic.yml, written by\n")
        f.write("# scripts/mitsuba/sun_caustic.py: one line per seed, then the mean and its\n")
        f.write(f"# standard error. {spp} samples per pixel, {seeds} seeds, mitsuba {mi.__version__}.\n")
        for seed, v in enumerate(means):
            f.write(f"seed {seed} {v:.7f}\n")
        f.write(f"mean {mean:.7f}\n")
        f.write(f"standard_error {se:.7f}\n")
    print(f"mean {mean:.6f} +- {se:.6f} ({100 * se / mean:.3f}%)")


if __name__ == "__main__":
    main()
