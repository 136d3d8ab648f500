#!/usr/bin/env python3
"""Scene-loading scaling: writes large scenes and times `ppm` loading them at N, 2N and 4N.

Three kinds of scene, each made of one kind of repetition:

- `yaml`:    N YAML materials, each used by one sphere.
- `mtl`:     one OBJ of N triangles, each with its own MTL material (`usemtl`).
- `aliases`: one small OBJ named by N mesh objects (a YAML anchor and N aliases).

Each scene renders one 8 x 8 path-tracing iteration, so the time is the load (parsing,
materials, meshes, fingerprint, BVH). The time is the process's CPU time (user + system,
from the kernel's accounting of the child), which other work on a shared machine disturbs
far less than the wall clock. Runs of the sizes alternate (N, 2N, 4N, N, 2N, ...); the
table gives min / median / max CPU seconds and the ratio of medians to the previous size
(2 for linear, 4 for quadratic).

Usage (from the repository root, after `cargo build --release -p ppm-cli`):

    python3 scripts/load_scaling.py yaml 50000 [--runs 3] [--ppm target/release/ppm]
    python3 scripts/load_scaling.py mtl 20000
    python3 scripts/load_scaling.py aliases 25000
"""

import argparse
import os
import resource
import statistics
import subprocess
import tempfile

HEADER = """camera: {{ position: [0, 1, 4], look_at: [0, 1, 0], up: [0, 1, 0], fov: 40 }}
resolution: [8, 8]
materials:
  lamp: {{ type: diffuse, color: [0.5, 0.5, 0.5], emission: [5, 5, 5] }}
{materials}objects:
  - {{ type: quad, corner: [-0.5, 2, -0.5], edge_u: [1, 0, 0], edge_v: [0, 0, 1], material: lamp }}
{objects}"""


def yaml_scene(n, folder):
    """N materials, one sphere each, on a grid."""
    side = int(n**0.5) + 1
    mats = "".join(
        f"  m{i}: {{ type: diffuse, color: [{(i % 97) / 100:.2f}, 0.5, 0.5] }}\n" for i in range(n)
    )
    objs = "".join(
        f"  - {{ type: sphere, center: [{i % side * 0.01:.2f}, {i // side * 0.01:.2f}, -1], radius: 0.004, material: m{i} }}\n"
        for i in range(n)
    )
    return HEADER.format(materials=mats, objects=objs)


def mtl_scene(n, folder):
    """One OBJ with N triangles, each in its own MTL material."""
    with open(os.path.join(folder, "many.mtl"), "w") as f:
        for i in range(n):
            f.write(f"newmtl m{i}\nKd {(i % 97) / 100:.2f} 0.5 0.5\n")
    side = int(n**0.5) + 1
    with open(os.path.join(folder, "many.obj"), "w") as f:
        f.write("mtllib many.mtl\n")
        for i in range(n):
            x, y = i % side * 0.01, i // side * 0.01
            f.write(f"v {x:.2f} {y:.2f} -1\nv {x + 0.008:.3f} {y:.2f} -1\nv {x:.2f} {y + 0.008:.3f} -1\n")
        for i in range(n):
            f.write(f"usemtl m{i}\nf {3 * i + 1} {3 * i + 2} {3 * i + 3}\n")
    return HEADER.format(materials="", objects="  - { type: mesh, file: many.obj }\n")


def aliases_scene(n, folder):
    """One small OBJ named by N objects through a YAML alias."""
    with open(os.path.join(folder, "tri.obj"), "w") as f:
        f.write("v 0 0 -1\nv 1 0 -1\nv 0 1 -1\nf 1 2 3\n")
    mats = "  white: { type: diffuse, color: [0.5, 0.5, 0.5] }\n"
    objs = "  - &tri { type: mesh, file: tri.obj, material: white }\n" + "  - *tri\n" * (n - 1)
    return HEADER.format(materials=mats, objects=objs)


KINDS = {"yaml": yaml_scene, "mtl": mtl_scene, "aliases": aliases_scene}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("kind", choices=KINDS)
    parser.add_argument("n", type=int)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--ppm", default="target/release/ppm")
    args = parser.parse_args()
    ppm = os.path.abspath(args.ppm)
    sizes = [args.n, 2 * args.n, 4 * args.n]
    with tempfile.TemporaryDirectory() as tmp:
        scenes = []
        for n in sizes:
            folder = os.path.join(tmp, str(n))
            os.mkdir(folder)
            scene = os.path.join(folder, "scene.yml")
            with open(scene, "w") as f:
                f.write(KINDS[args.kind](n, folder))
            scenes.append(scene)
        times = {n: [] for n in sizes}
        for _ in range(args.runs):
            for n, scene in zip(sizes, scenes):
                out = os.path.join(tmp, "out.exr")
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                subprocess.run(
                    [ppm, scene, "-a", "pt", "-n", "1", "-q", "-o", out, "--seed", "1"],
                    check=True,
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                )
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                times[n].append(
                    after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
                )
    print(f"| {args.kind} N | min CPU s | median CPU s | max CPU s | median / previous |")
    print("| ---: | ---: | ---: | ---: | ---: |")
    previous = None
    for n in sizes:
        t = times[n]
        median = statistics.median(t)
        ratio = f"{median / previous:.2f}" if previous else ""
        print(f"| {n} | {min(t):.2f} | {median:.2f} | {max(t):.2f} | {ratio} |")
        previous = median


if __name__ == "__main__":
    main()
