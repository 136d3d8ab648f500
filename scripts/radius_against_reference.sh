#!/usr/bin/env bash
# The default `photons` radius against fixed world radii at equal time, on SmallVCM's glass
# sphere over a glossy floor (scenes/compare/smallvcm_glass_ceiling.yml): `ppm -a ppm` for
# RUN_SECONDS of wall clock on 2 threads at SIZE x SIZE, ROUNDS rounds alternating the radii, relMSE
# against REFERENCE (an independent long render of the same scene at that size, e.g. the
# SmallVCM `vcm` reference scripts/smallvcm_compare.sh leaves in its output folder).
# Statistics by scripts/smallvcm_stats.py (Mitsuba's python reads the images).
#
# Usage: scripts/radius_against_reference.sh REFERENCE [OUT]
#   env: SIZE (512), RUN_SECONDS (20), ROUNDS (2), RADII ("photons 0.01 0.02 0.04 0.08"),
#        PYTHON (/work/venv-mitsuba/bin/python)
set -euo pipefail
cd "$(dirname "$0")/.."
ref=$1
out=${2:-radius_against_reference}
size=${SIZE:-512}
seconds=${RUN_SECONDS:-20}
rounds=${ROUNDS:-2}
radii=${RADII:-photons 0.01 0.02 0.04 0.08}
python=${PYTHON:-/work/venv-mitsuba/bin/python}
mkdir -p "$out"
CARGO_INCREMENTAL=0 cargo build --release --quiet -p ppm-cli
for r in $(seq 1 "$rounds"); do
  for radius in $radii; do
    target/release/ppm scenes/compare/smallvcm_glass_ceiling.yml -a ppm --seed $((2000 + r)) \
      --width "$size" --height "$size" --threads 2 --time-limit "$seconds" --radius "$radius" \
      -q -o "$out/ppm_${radius}_r$r.exr"
  done
done
echo "| radius | relMSE per round |"
echo "|---|---|"
for radius in $radii; do
  values=()
  for r in $(seq 1 "$rounds"); do
    values+=("$("$python" scripts/smallvcm_stats.py "$ref" "$out/ppm_${radius}_r$r.exr" | cut -f4)")
  done
  echo "| $radius | ${values[*]} |"
done
