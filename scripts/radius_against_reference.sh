#!/usr/bin/env bash
# The default `photons` radius against fixed world radii at equal time, on SCENE (by default
# SmallVCM's glass sphere over a glossy floor, scenes/compare/smallvcm_glass_ceiling.yml):
# `ppm -a ALGORITHM` for RUN_SECONDS of wall clock on 2 threads at SIZE x SIZE, ROUNDS rounds alternating the radii, relMSE
# against REFERENCE (an independent long render of the same scene at that size, e.g. the
# SmallVCM `vcm` reference scripts/smallvcm_compare.sh leaves in its output folder).
# Statistics by scripts/smallvcm_stats.py (Mitsuba's python reads the images). REF_NOISE is
# the reference's own relMSE (scripts/reference_pair.py estimates it from two independent
# halves); it is subtracted from each mean, since it adds the same to every radius and would
# pull their ratios toward 1. The last line is the first radius's (the default's) corrected
# relMSE over the best corrected relMSE of the others.
#
# Usage: scripts/radius_against_reference.sh REFERENCE [OUT]
#   env: SCENE (scenes/compare/smallvcm_glass_ceiling.yml), ALGORITHM (ppm), SIZE (512),
#        RUN_SECONDS (20), ROUNDS (2), RADII ("photons 0.01 0.02 0.04 0.08"), REF_NOISE (0),
#        SEED_BASE (2000: round r renders with seed SEED_BASE + r),
#        PYTHON (/work/venv-mitsuba/bin/python)
set -euo pipefail
cd "$(dirname "$0")/.."
ref=$1
out=${2:-radius_against_reference}
scene=${SCENE:-scenes/compare/smallvcm_glass_ceiling.yml}
algorithm=${ALGORITHM:-ppm}
size=${SIZE:-512}
seconds=${RUN_SECONDS:-20}
rounds=${ROUNDS:-2}
radii=${RADII:-photons 0.01 0.02 0.04 0.08}
python=${PYTHON:-/work/venv-mitsuba/bin/python}
ref_noise=${REF_NOISE:-0}
seed_base=${SEED_BASE:-2000}
mkdir -p "$out"
CARGO_INCREMENTAL=0 cargo build --release --quiet -p ppm-cli
for r in $(seq 1 "$rounds"); do
  for radius in $radii; do
    target/release/ppm "$scene" -a "$algorithm" --seed $((seed_base + r)) \
      --width "$size" --height "$size" --threads 2 --time-limit "$seconds" --radius "$radius" \
      -q -o "$out/ppm_${radius}_r$r.exr"
  done
done
echo "| radius | relMSE per round | mean | mean - reference's own ($ref_noise) |"
echo "|---|---|---|---|"
corrected=()
for radius in $radii; do
  values=()
  for r in $(seq 1 "$rounds"); do
    values+=("$("$python" scripts/smallvcm_stats.py "$ref" "$out/ppm_${radius}_r$r.exr" | cut -f4)")
  done
  read -r mean own < <(python3 -c "v=[float(x) for x in '${values[*]}'.split()]; m=sum(v)/len(v); print(f'{m:.6f} {m - $ref_noise:.6f}')")
  corrected+=("$own")
  echo "| $radius | ${values[*]} | $mean | $own |"
done
python3 -c "c=[float(x) for x in '${corrected[*]}'.split()]; print(f'first radius / best of the others: {c[0] / min(c[1:]):.3f}')"
