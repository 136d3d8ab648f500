#!/usr/bin/env python3
"""Mitsuba 3 reference values for ppm's textures (crates/ppm-scene/tests/textures.rs).

Writes, into crates/ppm-scene/tests/data/textures/:
- grid.png: a 4 x 3 8-bit sRGB image (made here, deterministic);
- bitmap_values.csv: Mitsuba 3's `bitmap` texture of grid.png evaluated at chosen uvs, for
  both filters, the three wrap modes, raw or sRGB-decoded, with and without a to_uv scale
  and offset; and `checkerboard` at the same uvs;
- floor_mitsuba.txt: the per-channel image means of textured_floor.yml (same folder, the
  same scene written by hand for ppm): a floor lit by a directional light straight down,
  its left half a bitmap (grid.png, scaled by 1.5, mirrored) and its right half a
  checkerboard (scaled by 4), rendered by Mitsuba's path tracer (32 x 32, box filter).

    /work/venv-mitsuba/bin/python scripts/mitsuba/texture_reference.py [samples-per-pixel]

Variant scalar_rgb; runs in well under a minute.
"""

import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data", "textures")

# Rows from the top; 8-bit sRGB codes.
GRID = np.array(
    [
        [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]],
        [[128, 64, 32], [10, 200, 90], [250, 250, 5], [0, 0, 0]],
        [[40, 80, 160], [200, 30, 220], [90, 90, 90], [30, 180, 250]],
    ],
    dtype=np.uint8,
)

UVS = [
    (0.1, 0.1), (0.3, 0.2), (0.5, 0.5), (0.62, 0.77), (0.93, 0.05), (0.0, 0.0),
    (1.0, 1.0), (-0.2, 0.4), (1.3, -0.45), (2.71, 1.62), (-1.1, -2.3), (0.125, 0.8333),
]

CHECKER = {"color0": [0.8, 0.2, 0.1], "color1": [0.1, 0.5, 0.9]}

FLOOR = """
<scene version="3.0.0">
  <integrator type="path">
    <integer name="max_depth" value="4"/>
  </integrator>
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <string name="fov_axis" value="y"/>
    <transform name="to_world">
      <lookat origin="0, 2.5, 0.2" target="0, 0, 0.2" up="0, 0, -1"/>
    </transform>
    <sampler type="independent">
      <integer name="sample_count" value="{spp}"/>
    </sampler>
    <film type="hdrfilm">
      <integer name="width" value="32"/>
      <integer name="height" value="32"/>
      <rfilter type="box"/>
      <string name="pixel_format" value="rgb"/>
    </film>
  </sensor>
  <!-- Left: x in [-1, 0], z in [-1, 1]: the rectangle scaled by (0.5, 1), turned to face
       +y (local y becomes -z), moved to x = -0.5. -->
  <shape type="rectangle">
    <transform name="to_world">
      <scale x="0.5" y="1" z="1"/>
      <rotate x="1" angle="-90"/>
      <translate x="-0.5"/>
    </transform>
    <bsdf type="diffuse">
      <texture type="bitmap" name="reflectance">
        <string name="filename" value="{grid}"/>
        <string name="filter_type" value="bilinear"/>
        <string name="wrap_mode" value="mirror"/>
        <transform name="to_uv">
          <scale x="1.5" y="1.5"/>
        </transform>
      </texture>
    </bsdf>
  </shape>
  <shape type="rectangle">
    <transform name="to_world">
      <scale x="0.5" y="1" z="1"/>
      <rotate x="1" angle="-90"/>
      <translate x="0.5"/>
    </transform>
    <bsdf type="diffuse">
      <texture type="checkerboard" name="reflectance">
        <rgb name="color0" value="0.8, 0.2, 0.1"/>
        <rgb name="color1" value="0.1, 0.5, 0.9"/>
        <transform name="to_uv">
          <scale x="4" y="4"/>
        </transform>
      </texture>
    </bsdf>
  </shape>
  <emitter type="directional">
    <vector name="direction" x="0" y="-1" z="0"/>
    <rgb name="irradiance" value="3.14159265, 3.14159265, 3.14159265"/>
  </emitter>
</scene>
"""


def evaluate(texture, u, v):
    si = mi.SurfaceInteraction3f()
    si.uv = mi.Point2f(u, v)
    c = texture.eval(si)
    return [float(c[0]), float(c[1]), float(c[2])]


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 1024
    os.makedirs(OUT, exist_ok=True)
    grid = os.path.join(OUT, "grid.png")
    mi.Bitmap(GRID, pixel_format=mi.Bitmap.PixelFormat.RGB).write(grid)

    rows = ["texture,filter,wrap,raw,scale,offset,u,v,r,g,b"]
    for filt in ["nearest", "bilinear"]:
        for wrap in ["repeat", "mirror", "clamp"]:
            for raw in [False, True]:
                for scale, offset in [((1, 1), (0, 0)), ((1.5, 2.0), (0.25, -0.1))]:
                    to_uv = mi.ScalarTransform4f().translate([offset[0], offset[1], 0]) @ \
                        mi.ScalarTransform4f().scale([scale[0], scale[1], 1])
                    t = mi.load_dict({
                        "type": "bitmap", "filename": grid, "filter_type": filt,
                        "wrap_mode": wrap, "raw": raw, "to_uv": to_uv,
                    })
                    for u, v in UVS:
                        r, g, b = evaluate(t, u, v)
                        rows.append(f"bitmap,{filt},{wrap},{int(raw)},{scale[0]} {scale[1]},"
                                    f"{offset[0]} {offset[1]},{u},{v},{r:.7f},{g:.7f},{b:.7f}")
    for scale in [1, 3]:
        t = mi.load_dict({
            "type": "checkerboard",
            "color0": {"type": "rgb", "value": CHECKER["color0"]},
            "color1": {"type": "rgb", "value": CHECKER["color1"]},
            "to_uv": mi.ScalarTransform4f().scale([scale, scale, 1]),
        })
        for u, v in UVS:
            r, g, b = evaluate(t, u, v)
            rows.append(f"checkerboard,,,,{scale} {scale},0 0,{u},{v},{r:.7f},{g:.7f},{b:.7f}")
    with open(os.path.join(OUT, "bitmap_values.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")

    scene = mi.load_string(FLOOR.format(spp=spp, grid=grid))
    image = np.array(mi.render(scene, spp=spp, seed=1))[:, :, :3]
    means = image.reshape(-1, 3).mean(axis=0)
    with open(os.path.join(OUT, "floor_mitsuba.txt"), "w") as f:
        f.write("# Mitsuba 3 (scalar_rgb, path) per-channel image means of textured_floor.yml,\n")
        f.write(f"# written by scripts/mitsuba/texture_reference.py; {spp} spp, mitsuba {mi.__version__}.\n")
        f.write(f"mean {means[0]:.7f} {means[1]:.7f} {means[2]:.7f}\n")
    print("means", means)


if __name__ == "__main__":
    main()
