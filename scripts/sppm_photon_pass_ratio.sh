#!/bin/bash
# SPPM's photon pass against ppm's, alternated on one busy machine (only ratios mean anything).
#
#   scripts/sppm_photon_pass_ratio.sh SIZE ROUNDS ITERATIONS BINARY...
#   e.g. scripts/sppm_photon_pass_ratio.sh 512 5 4 target/release/ppm
#
# For each round and each binary, renders scenes/cornell_box.yml at SIZE x SIZE with one light
# path per pixel (--photons SIZE^2, --radius auto, 1 thread, seed 1), `-a ppm` then `-a sppm`,
# and prints each run's pass times and its photon pass's rays/s from the `passes:` line.
# The ratio of a round is ppm's photon rays/s over sppm's. Images go to a temporary folder.
set -euo pipefail
size=$1; rounds=$2; iterations=$3; shift 3
scene="$(dirname "$0")/../scenes/cornell_box.yml"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for r in $(seq 1 "$rounds"); do
  for bin in "$@"; do
    for alg in ppm sppm; do
      line=$("$bin" "$scene" -a $alg --width "$size" --height "$size" --seed 1 --threads 1 \
        --radius auto --photons $((size * size)) -n "$iterations" -o "$out/$alg.png" 2>&1 |
        grep '^passes:')
      echo "$size $r $(basename "$bin") $alg $line"
    done
  done
done
