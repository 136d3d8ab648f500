#!/usr/bin/env bash
# ppm beside SmallVCM (a C++ teaching renderer with progressive photon mapping) on SmallVCM's
# scene 1, which scenes/compare/smallvcm_mirror_ceiling.yml transcribes. SmallVCM is not part of
# ppm: build it yourself (docs/performance.md, "against SmallVCM") and pass its binary. Writes
# into OUT (default compare_smallvcm/): the alternating speed runs (speed.tsv; each round also
# times the speed benchmark pair of scenes) and relMSE against seconds for SmallVCM's PPM, ppm
# and ppm --direct photons (smallvcm_mirror_ceiling.csv), then prints the tables.
# Needs the reference refs/smallvcm_mirror_ceiling.exr (512x512 path tracing, see docs/performance.md).
# Usage: scripts/against_smallvcm.sh SMALLVCM_BINARY [RUNS] [MAX_SMALLVCM_ITERATIONS] [OUT]
set -euo pipefail
cd "$(dirname "$0")/.."
smallvcm=$(realpath "$1")
runs=${2:-7}
max_iterations=${3:-512}
out=${4:-compare_smallvcm}
scene=scenes/compare/smallvcm_mirror_ceiling.yml
ref=refs/smallvcm_mirror_ceiling.exr
ppm=target/release/ppm
cargo build --release --quiet
mkdir -p "$out"
now() { date +%s.%N; }

# Speed: 12 iterations each at 2 threads (SmallVCM takes all cores; this machine has 2),
# alternating so that all see the same load. Wall seconds, start-up and image output included.
# Each round also runs the speed benchmark pair (SmallVCM's scene 0 and ppm's specular box).
echo -e "run\trenderer\tseconds" > "$out/speed.tsv"
# timed RUN NAME COMMAND...: runs COMMAND (its output dropped) and logs its wall seconds.
timed() {
  local run=$1 name=$2 t0 t1
  shift 2
  t0=$(now); "$@" > /dev/null 2>&1; t1=$(now)
  echo -e "$run\t$name\t$(echo "$t1 - $t0" | bc -l)" >> "$out/speed.tsv"
}
for run in $(seq 1 "$runs"); do
  timed "$run" smallvcm "$smallvcm" -a ppm -s 1 -i 12 -o "$out/smallvcm_12.hdr"
  for direct in sampled photons; do
    timed "$run" "ppm-direct-$direct" "$ppm" "$scene" -n 12 --threads 2 --direct "$direct" \
      -o "$out/ppm_12.exr"
  done
  # The speed benchmark pair (different scenes): SmallVCM's default sun scene, ppm's specular box.
  timed "$run" smallvcm-sun "$smallvcm" -a ppm -s 0 -i 12 -o "$out/smallvcm_sun_12.hdr"
  timed "$run" ppm-specular "$ppm" scenes/cornell_box_specular.yml --photons 262144 \
    --width 512 --height 512 -n 12 --threads 2 -o "$out/ppm_specular_12.exr"
done

# Error against time: SmallVCM at 1, 2, 4, ... iterations (one run each, seconds measured
# here), ppm from its own error log (seconds exclude computing the error).
echo "algorithm,seed,iteration,seconds,relmse,rmse" > "$out/smallvcm_mirror_ceiling.csv"
iterations=1
while [ "$iterations" -le "$max_iterations" ]; do
  t0=$(now); "$smallvcm" -a ppm -s 1 -i "$iterations" -o "$out/smallvcm.hdr" > /dev/null; t1=$(now)
  metrics=$("$ppm" compare "$out/smallvcm.hdr" "$ref")
  relmse=$(echo "$metrics" | awk '/^relMSE \(B/ {print $NF}')
  rmse=$(echo "$metrics" | awk '/^RMSE/ {print $NF}')
  echo "smallvcm,1234,$iterations,$(echo "$t1 - $t0" | bc -l),$relmse,$rmse" >> "$out/smallvcm_mirror_ceiling.csv"
  iterations=$((iterations * 2))
done
seconds=$(tail -n 1 "$out/smallvcm_mirror_ceiling.csv" | cut -d, -f4)
limit=$(python3 -c "print(min(120, max(10, round($seconds / 4))))")
for direct in sampled photons; do
  "$ppm" "$scene" --direct "$direct" --threads 2 --time-limit "$limit" --seed 0 \
    --reference "$ref" --error-log "$out/ppm_$direct.csv" -o "$out/ppm_$direct.exr" 2> /dev/null
  tail -n +2 "$out/ppm_$direct.csv" | sed "s/^/ppm-direct-$direct,0,/" >> "$out/smallvcm_mirror_ceiling.csv"
done

python3 - "$out/speed.tsv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
seconds = {}
for r in rows:
    seconds.setdefault(r["renderer"], {})[r["run"]] = float(r["seconds"])
print("| renderer | seconds for 12 iterations (min / median / max) | SmallVCM / this, per run (min / median / max) |")
print("|---|---|---|")
for name, runs in seconds.items():
    s = sorted(runs.values())
    # Each ppm run against the SmallVCM run of its pair of scenes in the same round.
    smallvcm = seconds["smallvcm-sun" if name.endswith(("sun", "specular")) else "smallvcm"]
    ratios = sorted(smallvcm[k] / v for k, v in runs.items())
    print(f"| {name} | {s[0]:.2f} / {statistics.median(s):.2f} / {s[-1]:.2f} | "
          f"{ratios[0]:.2f} / {statistics.median(ratios):.2f} / {ratios[-1]:.2f} |")
PY
python3 scripts/time_to_error.py --interpolate "$out/smallvcm_mirror_ceiling.csv"
