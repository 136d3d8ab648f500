#!/usr/bin/env python3
"""Reference values of ppm's microfacet and coated BSDFs from Mitsuba 3 (the oracle).

Writes
  crates/ppm-core/tests/data/mitsuba_bsdf_values.csv  (read by tests/bsdf_mitsuba.rs)
  crates/ppm-core/src/bsdf/metals.rs                   (the named conductors' RGB eta and k)

Run from the repository root with Mitsuba 3.9.1 in the scalar_rgb variant (the LLVM variants
are not needed):
  python3 -m venv /work/venv-mitsuba && /work/venv-mitsuba/bin/pip install mitsuba==3.9.1 numpy
  /work/venv-mitsuba/bin/python scripts/mitsuba/bsdf_values.py

CSV rows, all directions in ppm's convention: `wo` toward the viewer (Mitsuba's si.wi), `wi`
toward the light (Mitsuba's wo). Columns:
  kind   eval   | value = Mitsuba's eval (it INCLUDES |cos(wi)|), pdf = Mitsuba's pdf
         sample | Mitsuba's sample with (u_lobe, u1, u2): wi, value = weight, pdf
                  (only delta lobes are compared: the two samplers map u differently)
         albedo | value = mean sample weight over n samples (a lost one counts 0), se = its
                  standard errors, in n = pdf column
  mode   radiance | importance (Mitsuba's BSDFContext TransportMode)
The case names are built by `case()` in tests/bsdf_mitsuba.rs with the same parameters.
"""
import math
import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CSV = os.path.join(ROOT, "crates/ppm-core/tests/data/mitsuba_bsdf_values.csv")
METALS_RS = os.path.join(ROOT, "crates/ppm-core/src/bsdf/metals.rs")

# Mitsuba's named conductor presets (its conductor-ior-list); those it refuses are skipped.
METAL_NAMES = [
    "a-C", "Ag", "Al", "AlAs", "AlSb", "Au", "Be", "Cr", "CsI", "Cu", "Cu2O", "CuO", "d-C",
    "Hg", "HgTe", "Ir", "K", "Li", "MgO", "Mo", "Na_palik", "Nb", "Ni_palik", "Rh", "Se",
    "SiC", "SnTe", "Ta", "Te", "ThF4", "TiC", "TiN", "TiO2", "VC", "V_palik", "VN", "W",
]

# name -> Mitsuba dict. The rough ones name their distribution; the Beckmann cases (appended
# last, with their own random stream, so that the earlier rows do not move) sample D(m) cos(m)
# (`sample_visible` false), as ppm's Beckmann does, so that their pdfs are comparable.
ANISO_ETA = [0.2, 0.9, 1.1]
ANISO_K = [3.9, 2.4, 2.2]
CASES = {
    "rc_au_010": {"type": "roughconductor", "distribution": "ggx", "alpha": 0.1, "material": "Au"},
    "rc_cu_030": {"type": "roughconductor", "distribution": "ggx", "alpha": 0.3, "material": "Cu"},
    "rc_al_100": {"type": "roughconductor", "distribution": "ggx", "alpha": 1.0, "material": "Al"},
    "rc_aniso": {"type": "roughconductor", "distribution": "ggx", "alpha_u": 0.05, "alpha_v": 0.3,
                 "eta": {"type": "rgb", "value": ANISO_ETA}, "k": {"type": "rgb", "value": ANISO_K},
                 "specular_reflectance": {"type": "rgb", "value": [0.9, 0.8, 0.7]}},
    "rd_010": {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.1,
               "int_ior": 1.5, "ext_ior": 1.0},
    "rd_050": {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.5},
    "rd_water_glass": {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.2,
                       "int_ior": 1.33, "ext_ior": 1.5},
    "rd_aniso": {"type": "roughdielectric", "distribution": "ggx", "alpha_u": 0.1, "alpha_v": 0.4,
                 "int_ior": 1.5, "ext_ior": 1.0},
    "rp_010": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.1,
               "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.8]}},
    "rp_040": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.4, "int_ior": 1.6,
               "diffuse_reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.5]},
               "specular_reflectance": {"type": "rgb", "value": [0.9, 0.7, 0.5]}},
    "pl": {"type": "plastic", "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.8]}},
    "pl_tinted": {"type": "plastic", "int_ior": 1.7,
                  "diffuse_reflectance": {"type": "rgb", "value": [0.6, 0.3, 0.1]},
                  "specular_reflectance": {"type": "rgb", "value": [0.5, 0.6, 0.7]}},
    "tw_rc_cu_030": {"type": "twosided", "bsdf": {"type": "roughconductor", "distribution": "ggx",
                                                   "alpha": 0.3, "material": "Cu"}},
    # Delta models: compared through their samples.
    "c_au": {"type": "conductor", "material": "Au"},
    "c_none": {"type": "conductor"},
    "d_15": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
    "d_water_glass": {"type": "dielectric", "int_ior": 1.33, "ext_ior": 1.5},
    "td_15": {"type": "thindielectric", "int_ior": 1.5, "ext_ior": 1.0},
    "rcb_au_010": {"type": "roughconductor", "distribution": "beckmann", "alpha": 0.1,
                   "sample_visible": False, "material": "Au"},
    "rcb_aniso": {"type": "roughconductor", "distribution": "beckmann", "alpha_u": 0.05,
                  "alpha_v": 0.3, "sample_visible": False,
                  "eta": {"type": "rgb", "value": ANISO_ETA}, "k": {"type": "rgb", "value": ANISO_K}},
    # Visible normals here: Mitsuba's roughdielectric without them samples a widened alpha and
    # its sample weights then disagree with its own eval (wo at 80 deg: mean weight 0.989, the
    # integral of eval 0.949). Its pdfs are then not ppm's, only its values are compared.
    "rdb_030": {"type": "roughdielectric", "distribution": "beckmann", "alpha": 0.3,
                "int_ior": 1.5, "ext_ior": 1.0},
    "rpb_020": {"type": "roughplastic", "distribution": "beckmann", "alpha": 0.2,
                "sample_visible": False,
                "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.8]}},
}
TRANSMISSIVE = {"rd_010", "rd_050", "rd_water_glass", "rd_aniso", "rdb_030"}
BECKMANN = {"rcb_au_010", "rcb_aniso", "rdb_030", "rpb_020"}
DELTA = {"c_au", "c_none", "d_15", "d_water_glass", "td_15"}
ALBEDO_CASES = ["rc_au_010", "rc_al_100", "rc_aniso", "rd_010", "rd_050", "rd_water_glass",
                "rp_010", "rp_040", "pl", "c_au", "d_15", "td_15",
                "rcb_au_010", "rcb_aniso", "rdb_030", "rpb_020"]
ALBEDO_THETAS = [0.0, 45.0, 80.0]
ALBEDO_N = 100_000


def direction(theta_deg, phi):
    t = math.radians(theta_deg)
    return [math.sin(t) * math.cos(phi), math.sin(t) * math.sin(phi), math.cos(t)]


def context(mode):
    m = mi.TransportMode.Radiance if mode == "radiance" else mi.TransportMode.Importance
    return mi.BSDFContext(m)


def interaction(wo):
    si = mi.SurfaceInteraction3f()
    si.p = mi.Point3f(0, 0, 0)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    si.wi = mi.Vector3f(*wo)
    return si


def pairs(rng, transmissive):
    """Fixed (wo, wi) pairs: wo at several angles (and below for a transmissive case), wi
    random on the sphere, near the mirror direction and near the refracted one."""
    out = []
    thetas = [0.0, 20.0, 45.0, 70.0, 85.0]
    sides = [1, -1] if transmissive else [1, -1]
    for side in sides:
        for th in thetas:
            wo = direction(th, 0.7)
            wo[2] *= side
            wis = []
            for _ in range(4):
                v = rng.normal(size=3)
                wis.append(list(v / np.linalg.norm(v)))
            r = np.array([-wo[0], -wo[1], wo[2]])
            for s in [0.02, 0.1, 0.3]:
                v = r + rng.normal(size=3) * s
                wis.append(list(v / np.linalg.norm(v)))
            if transmissive:
                t = -np.array(wo)
                for s in [0.05, 0.2]:
                    v = t + rng.normal(size=3) * s
                    wis.append(list(v / np.linalg.norm(v)))
            for wi in wis:
                out.append((wo, [float(x) for x in wi]))
    return out


def f32(x):
    """The shortest decimal that reads back as the same f32."""
    return str(np.float32(x))


def fmt(x):
    """Nine significant digits: every f32 reads back exactly."""
    return f"{float(x):.9g}"


def main():
    rng = np.random.default_rng(20261204)
    # The Beckmann cases draw from their own stream: the earlier rows stay as they were.
    rng_beckmann = np.random.default_rng(20261206)
    rows = []
    header = "kind,case,mode,wo_x,wo_y,wo_z,wi_x,wi_y,wi_z,v_r,v_g,v_b,pdf,u_lobe,u1,u2,se_r,se_g,se_b"

    def row(kind, case, mode, wo, wi, v, pdf, u=(0, 0, 0), se=(0, 0, 0)):
        rows.append(",".join([kind, case, mode] + [fmt(x) for x in
                                                   list(wo) + list(wi) + list(v) + [pdf] + list(u) + list(se)]))

    for case, desc in CASES.items():
        bsdf = mi.load_dict(desc)
        modes = ["radiance", "importance"] if case in TRANSMISSIVE or case.startswith("d_") else ["radiance"]
        if case not in DELTA:
            for wo, wi in pairs(rng_beckmann if case in BECKMANN else rng, case in TRANSMISSIVE):
                for mode in modes:
                    ctx = context(mode)
                    si = interaction(wo)
                    v = bsdf.eval(ctx, si, mi.Vector3f(*wi))
                    p = bsdf.pdf(ctx, si, mi.Vector3f(*wi))
                    row("eval", case, mode, wo, wi, [v[0], v[1], v[2]], p)
        else:
            for th in [0.0, 30.0, 60.0, 85.0, 89.0]:
                for side in [1, -1]:
                    wo = direction(th, 0.4)
                    wo[2] *= side
                    for u_lobe in [0.0, 0.999]:
                        for mode in modes:
                            ctx = context(mode)
                            si = interaction(wo)
                            bs, w = bsdf.sample(ctx, si, u_lobe, mi.Point2f(0.3, 0.6))
                            if bs.pdf > 0 and max(w[0], w[1], w[2]) > 0:
                                row("sample", case, mode, wo, [bs.wo[0], bs.wo[1], bs.wo[2]],
                                    [w[0], w[1], w[2]], bs.pdf, (u_lobe, 0.3, 0.6))
    # Directional albedo by Mitsuba's own sampling (flux: importance mode for refraction).
    for case in ALBEDO_CASES:
        bsdf = mi.load_dict(CASES[case])
        mode = "importance" if case in TRANSMISSIVE or case.startswith("d_") else "radiance"
        ctx = context(mode)
        for th in ALBEDO_THETAS:
            wo = direction(th, 0.4)
            si = interaction(wo)
            u = (rng_beckmann if case in BECKMANN else rng).random(size=(ALBEDO_N, 3))
            s = np.zeros(3)
            s2 = np.zeros(3)
            for k in range(ALBEDO_N):
                bs, w = bsdf.sample(ctx, si, float(u[k, 0]), mi.Point2f(float(u[k, 1]), float(u[k, 2])))
                w = np.array([w[0], w[1], w[2]]) if bs.pdf > 0 or case in DELTA else np.zeros(3)
                s += w
                s2 += w * w
            mean = s / ALBEDO_N
            se = np.sqrt(np.maximum(s2 / ALBEDO_N - mean * mean, 0) / ALBEDO_N)
            row("albedo", case, mode, wo, [0, 0, 0], mean, ALBEDO_N, se=se)
            print(case, th, mean, se, file=sys.stderr)
    with open(CSV, "w") as f:
        f.write("# Generated by scripts/mitsuba/bsdf_values.py with Mitsuba " + mi.__version__ + " (scalar_rgb).\n")
        f.write(header + "\n")
        f.write("\n".join(rows) + "\n")
    print(f"{len(rows)} rows -> {CSV}", file=sys.stderr)

    metals = []
    for name in METAL_NAMES:
        try:
            p = mi.traverse(mi.load_dict({"type": "conductor", "material": name}))
        except Exception:
            print(f"skipped {name}: not a Mitsuba preset", file=sys.stderr)
            continue
        eta, k = p["eta.value"], p["k.value"]
        metals.append((name, [eta[0], eta[1], eta[2]], [k[0], k[1], k[2]]))
    with open(METALS_RS, "w") as f:
        f.write("//! Named conductors: the RGB complex index of refraction Mitsuba 3 uses for its\n")
        f.write("//! `material` presets in the `scalar_rgb` variant (its measured spectra of eta and k\n")
        f.write(f"//! reduced to RGB by Mitsuba {mi.__version__} itself).\n")
        f.write("//!\n//! Generated by `scripts/mitsuba/bsdf_values.py`; do not edit.\n\n")
        f.write("use glam::Vec3;\n\n")
        f.write("/// A named conductor: (Mitsuba's preset name, eta, k) per RGB channel.\n")
        f.write("pub struct Metal {\n    /// Mitsuba's preset name.\n    pub name: &'static str,\n")
        f.write("    /// Real part of the index of refraction.\n    pub eta: Vec3,\n")
        f.write("    /// Extinction coefficient.\n    pub k: Vec3,\n}\n\n")
        f.write("/// Every preset, in Mitsuba's order; `none` (eta 0, k 1) is a perfect mirror.\n")
        f.write("pub const METALS: &[Metal] = &[\n")
        for name, eta, k in metals + [("none", [0.0, 0.0, 0.0], [1.0, 1.0, 1.0])]:
            f.write(f"    Metal {{\n        name: {name!r},\n".replace("'", '"'))
            f.write(f"        eta: Vec3::new({f32(eta[0])}, {f32(eta[1])}, {f32(eta[2])}),\n")
            f.write(f"        k: Vec3::new({f32(k[0])}, {f32(k[1])}, {f32(k[2])}),\n    }},\n")
        f.write("];\n\n")
        f.write("/// The preset called `name` (case-sensitive, as in Mitsuba).\n")
        f.write("pub fn metal(name: &str) -> Option<&'static Metal> {\n")
        f.write("    METALS.iter().find(|m| m.name == name)\n}\n")
    print(f"{len(metals)} metals -> {METALS_RS}", file=sys.stderr)


if __name__ == "__main__":
    main()
