#!/usr/bin/env python3
"""SmallVCM's Cornell box under its ceiling light, all diffuse (its scene mask 1), in Mitsuba 3.

Checks which of ppm and SmallVCM has the right image mean on SmallVCM's own box. The box is
scenes/compare/smallvcm_glass_box.yml without the sphere: white floor, back wall and ceiling,
green and red side walls, the light box's four white sides and its emitting underside
(radiance 25.0333). Mitsuba 3's `path` (variant scalar_rgb) renders it with at most 10 edges
per path, as SmallVCM's default and ppm's max_depth 9 do, and a box filter, and prints the
image mean:

    /work/venv-mitsuba/bin/python scripts/mitsuba/smallvcm_box.py SIZE SPP SEED OUT.exr

See docs/performance.md, "Equal time against SmallVCM on its three scenes", for the commands
that render the same box with ppm and SmallVCM and the means found.
"""
import sys
import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f


def quad(corner, u, v, bsdf=None, radiance=None):
    """ppm's quad (corner, edges u and v, normal u x v) as Mitsuba's rectangle."""
    c, u, v = (np.array(x, dtype=float) for x in (corner, u, v))
    n = np.cross(u, v)
    m = np.eye(4)
    m[:3, 0] = u / 2
    m[:3, 1] = v / 2
    m[:3, 2] = n / np.linalg.norm(n)
    m[:3, 3] = c + u / 2 + v / 2
    d = {"type": "rectangle", "to_world": T(m.tolist())}
    if bsdf is not None:
        d["bsdf"] = bsdf
    if radiance is not None:
        d["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": radiance}}
        d["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}}
    return d


def diffuse(c):
    """A Lambertian BSDF of RGB albedo c."""
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": c}}

white = diffuse([0.803922] * 3)
green = diffuse([0.156863, 0.803922, 0.172549])
red = diffuse([0.803922, 0.152941, 0.152941])
size, spp, seed, out = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
scene = {
    "type": "scene",
    "integrator": {"type": "path", "max_depth": 10},
    "sensor": {
        "type": "perspective", "fov": 45, "fov_axis": "x",
        "to_world": T().look_at(origin=[-0.0439815, -4.12529, 0.222539],
                                target=[-0.0370952, -3.1267850, 0.1683229],
                                up=[0.000373896, 0.0542148, 0.998529]),
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"}},
    },
    "floor": quad([-1.27029, -1.25549, -1.28002], [2.56004, 0, 0], [0, 2.56004, 0], white),
    "back": quad([-1.27029, 1.30455, -1.28002], [2.56004, 0, 0], [0, 0, 2.56004], white),
    "ceiling": quad([-1.27029, -1.25549, 1.28002], [0, 2.56004, 0], [2.56004, 0, 0], white),
    "left": quad([-1.27029, -1.25549, -1.28002], [0, 2.56004, 0], [0, 0, 2.56004], green),
    "right": quad([1.28975, -1.25549, -1.28002], [0, 0, 2.56004], [0, 2.56004, 0], red),
    "lb_back": quad([-0.25, 0.25, 1.26002], [0, 0, 0.02], [0.5, 0, 0], white),
    "lb_left": quad([-0.25, -0.25, 1.26002], [0, 0, 0.02], [0, 0.5, 0], white),
    "lb_right": quad([0.25, -0.25, 1.26002], [0, 0.5, 0], [0, 0, 0.02], white),
    "lb_front": quad([-0.25, -0.25, 1.26002], [0.5, 0, 0], [0, 0, 0.02], white),
    "lamp": quad([-0.25, -0.25, 1.26002], [0, 0.5, 0], [0.5, 0, 0], radiance=[25.03329895614464] * 3),
}
image = np.array(mi.render(mi.load_dict(scene), seed=seed))
mi.Bitmap(image).write(out)
print(f"{image.mean():.6f}")
