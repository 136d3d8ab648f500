#!/usr/bin/env bash
# Renders the path-traced references of the speed-and-error study into refs/ (kept out of git:
# each is a float EXR; rerun this script to regenerate them).
# Usage: scripts/make_references.sh [SECONDS_PER_SCENE] [WIDTH]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
width=${2:-256}
cargo build --release --quiet
mkdir -p refs
for scene in cornell_box cornell_box_specular cornell_box_water cornell_box_glossy; do
  # A seed no converge run uses, so the reference's noise is independent of the runs'.
  target/release/ppm "$scene.yml" -a pt --width "$width" --time-limit "$seconds" \
    --seed 1000003 -o "refs/$scene.exr"
done
