#!/usr/bin/env bash
# The rough-lobe study of docs/rough-lobes.md: for each scene (a rough gold sphere casting a
# reflection caustic, a frosted glass sphere casting a refraction caustic, a glass sphere's
# caustic landing on a rough gold floor) and each roughness, pt, ppm, sppm and vcm render
# ITERATIONS iterations at 32 x 32 for SEEDS seeds (relMSE and render time from --error-log),
# against a long vcm reference of REF_ITERATIONS iterations. The four algorithms run
# alternated (pt ppm sppm vcm pt ppm ...), so that the busy machine's load falls on all of
# them alike; the table gives each algorithm's mean relMSE at equal iterations, its median
# time per run relative to pt's, and their product relative to pt's (relMSE at equal time,
# as relMSE falls as 1/time).
# Writes docs/rough-lobes.csv (one row per scene, roughness and algorithm).
# Usage: scripts/rough_lobes.sh [ITERATIONS] [SEEDS] [REF_ITERATIONS]
set -euo pipefail
cd "$(dirname "$0")/.."
iterations=${1:-64}
seeds=${2:-4}
ref_iterations=${3:-4096}
cargo build --release --quiet -p ppm-cli
ppm=target/release/ppm
data=crates/ppm-scene/tests/data/mitsuba/renders
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
csv=docs/rough-lobes.csv
echo "scene,alpha,algorithm,relmse,relmse_se,time_ratio,equal_time_relmse_ratio" > "$csv"
# ppm and sppm trace 8192 photons an iteration (the image has 1024 pixels).
flags() {
  case $1 in
    ppm|sppm) echo "--photons 8192" ;;
    *) echo "" ;;
  esac
}
for scene in metal glass receiver; do
  for alpha in 0.001 0.01 0.05 0.1 0.23 0.5; do
    xml=$data/rough_lobe_$scene.xml
    $ppm "$xml" -D alpha=$alpha -a vcm -n "$ref_iterations" --seed 999 -q -o "$tmp/ref.exr"
    for alg in pt ppm sppm vcm; do : > "$tmp/$alg.err"; : > "$tmp/$alg.time"; done
    for seed in $(seq 1 "$seeds"); do
      for alg in pt ppm sppm vcm; do
        # shellcheck disable=SC2046
        $ppm "$xml" -D alpha=$alpha -a $alg -n "$iterations" --seed "$seed" -q \
          $(flags $alg) -o "$tmp/$alg.exr" --reference "$tmp/ref.exr" --error-log "$tmp/log.csv"
        # The last row: iteration,seconds (render time, without loading),relmse,rmse.
        tail -n 1 "$tmp/log.csv" | cut -d, -f2 >> "$tmp/$alg.time"
        tail -n 1 "$tmp/log.csv" | cut -d, -f3 >> "$tmp/$alg.err"
      done
    done
    python3 - "$tmp" "$scene" "$alpha" >> "$csv" <<'EOF'
import statistics, sys
tmp, scene, alpha = sys.argv[1:]
def read(alg, kind):
    return [float(x) for x in open(f"{tmp}/{alg}.{kind}").read().split()]
t_pt = statistics.median(read("pt", "time"))
e_pt = statistics.mean(read("pt", "err"))
for alg in ["pt", "ppm", "sppm", "vcm"]:
    e = read(alg, "err")
    m = statistics.mean(e)
    se = statistics.stdev(e) / len(e) ** 0.5 if len(e) > 1 else float("nan")
    ratio = statistics.median(read(alg, "time")) / t_pt
    print(f"{scene},{alpha},{alg},{m:.4g},{se:.2g},{ratio:.3g},{m * ratio / e_pt:.3g}")
EOF
    tail -n 4 "$csv"
  done
done
