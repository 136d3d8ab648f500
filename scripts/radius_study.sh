#!/usr/bin/env bash
# The default radius (`photons`) against a sweep of fixed world radii, at equal time
# (docs/radius.md, docs/performance.md "A radius from the photons"). For each scene and
# width, `ppm converge -a ALG` runs SECONDS with the default radius, with `footprint`, and
# with each world radius of the sweep (the scene's diagonal times 0.00125, 0.0025, 0.005,
# 0.01, 0.02); the error is against a path-traced reference of REF_SECONDS. A second,
# independent reference of the same length measures the reference's own noise:
# relMSE(ref_a, ref_b) / 2 is what ref_a adds to every run's relMSE, and is subtracted in
# the table ("floor"; a negative entry means the reference's noise hides that run's error).
# Prints one table row per scene and width, with default / best world radius after and
# before the subtraction; the images stay in OUT.
# Usage: scripts/radius_study.sh [SECONDS] [REF_SECONDS] [WIDTHS] [OUT] [ALG] [SCENES...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
ref_seconds=${2:-120}
widths=${3:-"128 512"}
out=${4:-radius_study}
alg=${5:-ppm}
shift $(( $# < 5 ? $# : 5 ))
scenes=${*:-"scenes/compare/smallvcm_glass_ceiling.yml scenes/cornell_box.yml"}
cargo build --release --quiet -p ppm-cli
ppm=target/release/ppm
mkdir -p "$out"

# relMSE of image $1 against reference $2 (the `relMSE` line of `ppm compare`).
relmse() { "$ppm" compare "$1" "$2" | awk '/relMSE/ { for (i = 1; i <= NF; i++) if ($i ~ /^[0-9.eE+-]+$/) { print $i; exit } }'; }
# The scene's bounding-box diagonal, from the extents its file states.
diagonal() {
  case $(basename "$1" .yml) in
    smallvcm_glass_ceiling | smallvcm_mirror_ceiling) echo 4.434 ;;  # about 2.56 on each side
    cornell_box*) echo 3.464 ;;  # [-1, 1] x [0, 2] x [-1, 1]
    *) echo "no diagonal known for $1" >&2; exit 1 ;;
  esac
}

printf '%-26s %5s %9s %9s %9s %9s %9s %9s %9s %9s %7s %7s\n' scene width floor photons footprint \
  r/800 r/400 r/200 r/100 r/50 ratio raw
for scene in $scenes; do
  stem=$(basename "$scene" .yml)
  d=$(diagonal "$scene")
  for width in $widths; do
    dir="$out/$stem-$width"
    mkdir -p "$dir"
    for seed in 1000003 2000003; do
      [ -f "$dir/ref-$seed.exr" ] || "$ppm" "$scene" -a pt --width "$width" \
        --time-limit "$ref_seconds" --seed "$seed" -q -o "$dir/ref-$seed.exr"
    done
    ref="$dir/ref-1000003.exr"
    floor=$(python3 -c "print($(relmse "$dir/ref-2000003.exr" "$ref") / 2)")
    row=()
    raw=()
    for radius in photons footprint 0.00125 0.0025 0.005 0.01 0.02; do
      case $radius in
        photons|footprint) r=$radius ;;
        *) r=$(python3 -c "print($radius * $d)") ;;
      esac
      [ -f "$dir/$radius.exr" ] || "$ppm" "$scene" -a "$alg" --width "$width" --radius "$r" \
        --time-limit "$seconds" --seed 1 -q -o "$dir/$radius.exr"
      e=$(relmse "$dir/$radius.exr" "$ref")
      raw+=("$e")
      row+=("$(python3 -c "print($e - $floor)")")
    done
    # default / best world radius, with the floor subtracted (n/a when the floor is larger
    # than an error: the reference is too noisy for the difference) and raw.
    ratio=$(python3 -c "v = [float(x) for x in '${row[*]}'.split()]; b = min(v[2:]); print(round(v[0] / b, 3) if b > 0 and v[0] > 0 else 'n/a')")
    raw_ratio=$(python3 -c "v = [float(x) for x in '${raw[*]}'.split()]; print(round(v[0] / min(v[2:]), 3))")
    printf '%-26s %5s %9.3g %9.3g %9.3g %9.3g %9.3g %9.3g %9.3g %9.3g %7s %7s\n' "$stem" "$width" \
      "$floor" "${row[@]}" "$ratio" "$raw_ratio"
  done
done
