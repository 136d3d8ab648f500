#!/usr/bin/env bash
# Speed against error of the radius and photon defaults (docs/sppm.md, docs/performance.md):
# on the four shipped scenes and on a large-plane scene written here (a glass sphere on a
# 200 x 200 floor, under a small lamp), `ppm converge` runs for SECONDS each:
#   old       -a ppm with the radius a user got before `auto`: the scene's own (the boxes),
#             or 0.5% of the bounding box's diagonal (the large plane, which sets none);
#   ppm-auto  -a ppm --radius auto;
#   sppm-auto -a sppm --radius auto --photons <one light path per pixel>.
# Then the photons-per-iteration sweep of sppm (1/4, 1, 4 and 16 light paths per pixel, and
# 200000) on cornell_box and cornell_box_water. References: path tracing for REF_SECONDS at
# seed 1000003 (no run uses it). Prints the tables; CSVs stay in OUT.
# Usage: scripts/defaults_study.sh [SECONDS] [REF_SECONDS] [WIDTH] [OUT] [THREADS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
ref_seconds=${2:-150}
width=${3:-128}
out=${4:-defaults_study}
threads=${5:-2}
cargo build --release --quiet
ppm=target/release/ppm
mkdir -p "$out/refs"

cat > "$out/large_plane.yml" <<'YAML'
# A glass sphere (radius 0.5) and nothing else on a 200 x 200 floor under a 0.3 x 0.3 lamp.
camera: { position: [0.0, 1.6, 2.6], look_at: [0.0, 0.35, 0.0], up: [0, 1, 0], fov: 38.0 }
resolution: [128, 128]
materials:
  white: { type: diffuse, color: [0.7, 0.7, 0.7] }
  glass: { type: glass, ior: 1.5 }
  lamp:  { type: diffuse, color: [0, 0, 0], emission: [60, 60, 60] }
objects:
  - { type: quad, corner: [-100, 0, -100], edge_u: [0, 0, 200], edge_v: [200, 0, 0], material: white }
  - { type: sphere, center: [0.25, 0.5, 0.0], radius: 0.5, material: glass }
  - { type: quad, corner: [0.55, 2.2, -0.45], edge_u: [0.3, 0, 0], edge_v: [0, 0, 0.3], material: lamp }
render: { max_depth: 32 }
YAML

scenes="scenes/cornell_box.yml scenes/cornell_box_specular.yml scenes/cornell_box_water.yml scenes/cornell_box_glossy.yml $out/large_plane.yml"
for scene in $scenes; do
  stem=$(basename "$scene" .yml)
  [ -f "$out/refs/$stem.exr" ] || "$ppm" "$scene" -a pt --width "$width" --time-limit "$ref_seconds" \
    --seed 1000003 --threads "$threads" -q -o "$out/refs/$stem.exr"
done

# Pixels of a reference (its size line in `ppm info`).
pixels() { "$ppm" info "$out/refs/$1.exr" | awk '/^size:/ { split($2, s, "x"); print s[1] * s[2] }'; }

for scene in $scenes; do
  stem=$(basename "$scene" .yml)
  ref="$out/refs/$stem.exr"
  n=$(pixels "$stem")
  if [ "$stem" = large_plane ]; then
    old_radius=$(python3 -c "import math; print(0.005 * math.sqrt(200**2 + 200**2 + 2.2**2))")
    old=(--radius "$old_radius")
  else
    old=()
  fi
  common=(--reference "$ref" --time-limit "$seconds" --threads "$threads" --seed 1)
  "$ppm" converge "$scene" "${common[@]}" -a ppm "${old[@]}" --out "$out/old"
  "$ppm" converge "$scene" "${common[@]}" -a ppm --radius auto --out "$out/ppm-auto"
  "$ppm" converge "$scene" "${common[@]}" -a sppm --radius auto --photons "$n" --out "$out/sppm-auto"
done

for stem in cornell_box cornell_box_water; do
  n=$(pixels "$stem")
  for photons in $((n / 4)) "$n" $((4 * n)) $((16 * n)) 200000; do
    "$ppm" converge "scenes/$stem.yml" --reference "$out/refs/$stem.exr" --time-limit "$seconds" \
      --threads "$threads" --seed 1 -a sppm --radius auto --photons "$photons" \
      --out "$out/photons-$photons"
  done
done
python3 scripts/defaults_table.py "$out"
