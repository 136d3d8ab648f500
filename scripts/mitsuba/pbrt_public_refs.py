#!/usr/bin/env python3
"""Reference renders of the public pbrt-v4 scenes of crates/ppm-scene/tests/data/public/bitterli-pbrt/,
by Mitsuba 3 from a translation of each file.

Mitsuba 3 cannot read pbrt files, so this script reads the numbers of the pbrt-v4 file itself
(the subset these scenes use: `Transform`, `Camera "perspective"` fov, `Film` resolution,
`Integrator` maxdepth, `MakeNamedMaterial`/`NamedMaterial` of types diffuse and conductor,
`AreaLightSource "diffuse"` rgb L, `Shape "trianglemesh"` P/N/indices and `Shape "sphere"`
radius under a `Transform`, `AttributeBegin`/`AttributeEnd`; anything else is an error) and
builds the same scene with mi.load_dict:

- camera: pbrt's `Transform` before `WorldBegin` is camera-from-world, written column-major
  (pbrt transposes it). pbrt's camera space is left-handed (x right, y up, z forward);
  Mitsuba's is right-handed with x pointing left, so Mitsuba's to_world is
  inverse(camera-from-world) times Scale(-1, 1, 1): the image's right is pbrt's +x in both,
  and the Cornell box's red wall (x = -1) is on the image's left in both.
  pbrt-v4's fov is on the shorter image axis: Mitsuba's fov_axis "smaller".
- film: the small size the test asks (the file's aspect), box pixel filter. ppm has only the
  box filter and warns that the file's `PixelFilter "triangle"` is not used; the box filter
  here makes the per-pixel comparison measure everything but the filter.
- integrator: `path` with max_depth = pbrt's maxdepth + 1 (pbrt counts bounces, Mitsuba
  path vertices including the one on the camera ray's first hit).
- materials: pbrt-v4's BSDFs answer on both sides of a surface, Mitsuba's on the normal's
  side, so each is wrapped in `twosided`. diffuse -> diffuse (rgb reflectance); conductor
  with remaproughness false -> roughconductor, GGX (pbrt's Trowbridge-Reitz) with alpha
  the roughness itself, rgb eta and k per channel.
- lights: pbrt-v4's diffuse area light is one-sided, on the side of the surface normal
  (the shading normal N of a trianglemesh, the outward normal of a sphere): Mitsuba's `area`
  emitter on the same shape, whose vertex normals are N. "rgb L" is taken as RGB radiance.
  pbrt-v4 itself renders spectrally and turns "rgb L" into an RGBIlluminantSpectrum (the
  RGB's spectrum times the colour space's illuminant); neither Mitsuba's scalar_rgb nor ppm
  does that, both use the three numbers as radiance, which is what is compared.

Each scene is rendered for SEEDS independent seeds of SPP samples per pixel. Writes to
crates/ppm-scene/tests/data/public/references/ (as scripts/mitsuba/public_refs.py does):
`<scene>.exr` (mean over the seeds), `<scene>_var.exr` (per pixel the variance of that
mean) and the scene's row of `pbrt_references.csv` (image mean and its standard error per
channel).

Run from anywhere, with Mitsuba 3.9.1 installed (`pip install mitsuba==3.9.1 numpy`):

    /work/venv-mitsuba/bin/python scripts/mitsuba/pbrt_public_refs.py [spp] [seeds] [names]

Defaults: the SPP table's samples per pixel, 8 seeds, every scene (a few minutes on a busy
core); `names` (comma-separated) renders only those and keeps the other rows.
"""

import os
import re
import sys
import tempfile

import mitsuba as mi
import numpy as np

import public_refs  # the shared recording of references (this folder)

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "crates", "ppm-scene", "tests", "data", "public")
OUT = os.path.join(DATA, "references")

# name -> (file under DATA, film width, film height). Keep in step with
# crates/ppm-scene/tests/public_scenes.rs.
SCENES = {
    "bitterli-cornell-box": ("bitterli-pbrt/cornell-box/scene-v4.pbrt", 32, 32),
    "bitterli-veach-mis": ("bitterli-pbrt/veach-mis/scene-v4.pbrt", 48, 27),
}
SPP = {"bitterli-cornell-box": 1024, "bitterli-veach-mis": 4096}
TOKEN = re.compile(r'#[^\n]*|"[^"]*"|\[|\]|[^\s\[\]"]+')


def tokens(text):
    return [t for t in TOKEN.findall(text) if not t.startswith("#")]


def parse(path):
    """The directives of a pbrt file as (name, [args], {"type name": [values]})."""
    toks = tokens(open(path).read())
    out, i = [], 0
    while i < len(toks):
        name, i = toks[i], i + 1
        args, params = [], {}
        while i < len(toks) and (toks[i].startswith('"') or toks[i] == "[" or
                                 re.match(r"^[-+.0-9]", toks[i])):
            if toks[i].startswith('"') and " " in toks[i]:
                key, i = toks[i].strip('"'), i + 1
                if toks[i] == "[":
                    j = toks.index("]", i)
                    values, i = toks[i + 1:j], j + 1
                else:
                    values, i = [toks[i]], i + 1
                params[key] = [v.strip('"') for v in values]
            elif toks[i] == "[":
                j = toks.index("]", i)
                args.extend(toks[i + 1:j])
                i = j + 1
            else:
                args.append(toks[i].strip('"'))
                i += 1
        out.append((name, args, params))
    return out


def floats(params, key):
    for k, v in params.items():
        if k.split()[1] == key:
            return [float(x) for x in v]
    return None


def pbrt_matrix(values):
    """pbrt's `Transform` numbers, written column-major, as a 4x4 row-major matrix."""
    return np.array([float(v) for v in values]).reshape(4, 4).T


def twosided(bsdf):
    return {"type": "twosided", "bsdf": bsdf}


def material(params, path):
    kind = params["string type"][0]
    allowed = {"diffuse": {"string type", "rgb reflectance"},
               "conductor": {"string type", "float uroughness", "float vroughness",
                             "bool remaproughness", "rgb eta", "rgb k"}}
    if kind not in allowed or set(params) - allowed[kind]:
        raise ValueError(f"{path}: material {params} is not translated")
    if kind == "diffuse":
        return twosided({"type": "diffuse",
                         "reflectance": {"type": "rgb", "value": floats(params, "reflectance")}})
    if params["bool remaproughness"] != ["false"]:
        raise ValueError(f"{path}: only remaproughness false is translated")
    return twosided({
        "type": "roughconductor", "distribution": "ggx",
        "alpha_u": floats(params, "uroughness")[0], "alpha_v": floats(params, "vroughness")[0],
        "eta": {"type": "rgb", "value": floats(params, "eta")},
        "k": {"type": "rgb", "value": floats(params, "k")},
    })


def write_ply(path, positions, normals, indices):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(positions))
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n"
                % len(indices))
        for p, n in zip(positions, normals):
            f.write("%r %r %r %r %r %r\n" % (*p, *n))
        for t in indices:
            f.write("3 %d %d %d\n" % tuple(t))


def translate(path, width, height, tmp):
    """The Mitsuba scene dict of the pbrt file at `path`, with a width x height film."""
    scene = {"type": "scene"}
    named, camera_from_world, fov, max_depth = {}, None, None, None
    ctm = np.eye(4)
    state = {"material": None, "light": None, "ctm": ctm}
    stack = []
    world = False
    for name, args, params in parse(path):
        if name == "Transform":
            state["ctm"] = pbrt_matrix(args)
        elif name == "Integrator":
            max_depth = int(floats(params, "maxdepth")[0])
        elif name == "Camera":
            assert args == ["perspective"], args
            camera_from_world, fov = state["ctm"], floats(params, "fov")[0]
        elif name in ("Sampler", "PixelFilter", "Film"):
            pass  # the sample count, the filter and the size are the test's
        elif name == "WorldBegin":
            world = True
            state["ctm"] = np.eye(4)
        elif name == "MakeNamedMaterial":
            named[args[0]] = material(params, path)
        elif name == "NamedMaterial":
            state["material"] = named[args[0]]
        elif name == "AttributeBegin":
            stack.append(dict(state))
        elif name == "AttributeEnd":
            state = stack.pop()
        elif name == "AreaLightSource":
            assert args == ["diffuse"] and set(params) == {"rgb L"}, (args, params)
            state["light"] = {"type": "area",
                              "radiance": {"type": "rgb", "value": floats(params, "L")}}
        elif name == "Shape" and world:
            shape = translate_shape(args[0], params, state["ctm"], tmp, len(scene))
            shape["bsdf"] = state["material"]
            if state["light"] is not None:
                shape["emitter"] = state["light"]
            scene["shape%d" % len(scene)] = shape
        else:
            raise ValueError(f"{path}: {name} {args} is not translated")
    # Mitsuba's camera: x left, y up, z forward; pbrt's x right.
    to_world = np.linalg.inv(camera_from_world) @ np.diag([-1.0, 1.0, 1.0, 1.0])
    scene["camera"] = {
        "type": "perspective", "fov": fov, "fov_axis": "smaller",
        "to_world": mi.ScalarTransform4f(to_world.tolist()),
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": "independent"},
    }
    scene["integrator"] = {"type": "path", "max_depth": max_depth + 1}
    return scene


def translate_shape(kind, params, ctm, tmp, n):
    if kind == "trianglemesh":
        p = np.array(floats(params, "P")).reshape(-1, 3)
        nn = np.array(floats(params, "N")).reshape(-1, 3)
        idx = np.array(floats(params, "indices"), dtype=int).reshape(-1, 3)
        assert set(params) <= {"point3 P", "normal N", "integer indices", "point2 uv"}, params
        assert np.allclose(ctm, np.eye(4)), ctm
        ply = os.path.join(tmp, "mesh%d.ply" % n)
        write_ply(ply, p.tolist(), nn.tolist(), idx.tolist())
        return {"type": "ply", "filename": ply, "face_normals": False}
    if kind == "sphere":
        assert set(params) == {"float radius"}, params
        assert np.allclose(ctm[:3, :3], np.eye(3)), ctm
        return {"type": "sphere", "center": ctm[:3, 3].tolist(),
                "radius": floats(params, "radius")[0]}
    raise ValueError(f"Shape {kind} is not translated")


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    default_spp = int(args[0]) if len(args) > 0 else None
    seeds = int(args[1]) if len(args) > 1 else 8
    only = args[2].split(",") if len(args) > 2 else list(SCENES)
    os.makedirs(OUT, exist_ok=True)
    csv = os.path.join(OUT, "pbrt_references.csv")
    rows = public_refs.read_rows(csv)
    for name in only:
        file, width, height = SCENES[name]
        spp = default_spp or SPP[name]
        with tempfile.TemporaryDirectory() as tmp:
            scene = mi.load_dict(translate(os.path.join(DATA, file), width, height, tmp))
            public_refs.record(name, spp, seeds,
                               lambda seed: np.array(mi.render(scene, spp=spp, seed=seed)), rows)
    public_refs.write_rows(csv, rows, SCENES)


if __name__ == "__main__":
    main()
