#!/usr/bin/env bash
# The speed-and-error study of the README: for each scene, the four algorithms (pt, ppm, sppm,
# vcm) run for the same time at 1 and 2 threads against the references of
# scripts/make_references.sh; writes CSVs and log-log plots into docs/speed_error/ and prints
# the time each run took to reach relMSE 0.05, 0.02 and 0.01.
# Usage: scripts/speed_error.sh [SECONDS_PER_RUN]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-40}
cargo build --release --quiet
out=docs/speed_error
mkdir -p "$out"
for threads in 1 2; do
  for scene in cornell_box cornell_box_specular cornell_box_water cornell_box_glossy; do
    target/release/ppm converge "$scene.yml" --reference "refs/$scene.exr" \
      --time-limit "$seconds" -a pt,ppm,sppm,vcm --threads "$threads" --out "$out/threads$threads"
  done
done
python3 scripts/time_to_error.py "$out"/threads*/*_convergence.csv
