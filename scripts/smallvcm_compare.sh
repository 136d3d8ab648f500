#!/usr/bin/env bash
# ppm against SmallVCM (Davidovič's C++ implementation of vertex connection and merging) on
# SmallVCM's own Cornell box with a glossy Phong floor, a large glass sphere and the ceiling
# light (its box mask 289), which scenes/compare/smallvcm_glass_ceiling.yml transcribes:
# relMSE per iteration of each technique set (vcm, bpt, bpm, lt; the same names in both
# renderers) and a short equal-CPU-time check of vcm. See docs/vcm.md ("Against SmallVCM")
# and docs/performance.md.
#
# SmallVCM is not part of ppm and none of its code is committed: the script clones it into
# SMALLVCM_DIR if it is not there, copies its sources to SMALLVCM_DIR/build and edits that
# copy only to add (a) scene 4 = mask 289 and (b) environment variables for its seed,
# resolution, thread count and maximum path length, then compiles it (g++ -O3 -fopenmp).
# Statistics: scripts/smallvcm_stats.py, run with Mitsuba's python (it reads EXR and HDR).
#
# Both renderers render SIZE x SIZE (SmallVCM's light paths are one per pixel in both),
# SmallVCM's merge radius 0.003 x the scene's bounding-sphere radius = 0.0066512 and
# alpha 0.75, at most 10 edges per path (SmallVCM's default; ppm's max_depth 9). Each
# renderer's relMSE is against its own long vcm render (REF_ITERATIONS iterations); the
# two references' means are printed as a check that both render the same scene.
#
# Usage: scripts/smallvcm_compare.sh [OUT]
#   env: SIZE (256), ITERATIONS (24), SEEDS (4), REF_ITERATIONS (800), TECHNIQUES
#   ("vcm bpt bpm lt"), SMALLVCM_DIR (/work/smallvcm), PYTHON (/work/venv-mitsuba/bin/python)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-compare_smallvcm_glass}
size=${SIZE:-256}
iterations=${ITERATIONS:-24}
seeds=${SEEDS:-4}
ref_iterations=${REF_ITERATIONS:-800}
techniques=${TECHNIQUES:-vcm bpt bpm lt}
smallvcm_dir=${SMALLVCM_DIR:-/work/smallvcm}
python=${PYTHON:-/work/venv-mitsuba/bin/python}
scene=scenes/compare/smallvcm_glass_ceiling.yml
ppm=target/release/ppm
smallvcm=$smallvcm_dir/smallvcm_ppmcmp
mkdir -p "$out"

# SmallVCM, built beside ppm (never inside this repository).
if [ ! -x "$smallvcm" ]; then
  if [ ! -d "$smallvcm_dir/src_repo" ]; then
    git clone --quiet https://github.com/SmallVCM/SmallVCM "$smallvcm_dir/src_repo"
  fi
  rm -rf "$smallvcm_dir/build"
  cp -r "$smallvcm_dir/src_repo/src" "$smallvcm_dir/build"
  config=$smallvcm_dir/build/config.hxx
  # Scene 4: glossy floor, large glass sphere, ceiling light (mask 256 | 32 | 1 = 289).
  perl -0pi -e 's/(Scene::kLightBackground)\n\};/$1,\n    Scene::kGlossyFloor | Scene::kLargeGlassSphere | Scene::kLightCeiling\n};/' "$config"
  # Seed, maximum path length, resolution and threads from the environment.
  perl -0pi -e 's/(oConfig.mRadiusAlpha   = 0.75f;\n)/$1    if(getenv("SMALLVCM_SEED")) oConfig.mBaseSeed = atoi(getenv("SMALLVCM_SEED"));\n    if(getenv("SMALLVCM_MAX_PATH_LENGTH")) oConfig.mMaxPathLength = atoi(getenv("SMALLVCM_MAX_PATH_LENGTH"));\n    if(getenv("SMALLVCM_RESOLUTION")) oConfig.mResolution = Vec2i(atoi(getenv("SMALLVCM_RESOLUTION")), atoi(getenv("SMALLVCM_RESOLUTION")));\n    if(getenv("SMALLVCM_THREADS")) oConfig.mNumThreads = atoi(getenv("SMALLVCM_THREADS"));\n/' "$config"
  grep -q kLargeGlassSphere "$config" && grep -q SMALLVCM_SEED "$config" \
    || { echo "could not patch $config" >&2; exit 1; }
  g++ -O3 -march=native -fopenmp -std=c++11 -o "$smallvcm" "$smallvcm_dir/build/smallvcm.cxx"
fi
CARGO_INCREMENTAL=0 cargo build --release --quiet -p ppm-cli

# svcm ALG SEED ITERATIONS FILE: SmallVCM on 2 threads; its threads take seeds SEED and SEED + 1.
svcm() {
  SMALLVCM_RESOLUTION=$size SMALLVCM_SEED=$2 SMALLVCM_THREADS=2 \
    "$smallvcm" -s 4 -a "$1" -i "$3" -o "$4" > /dev/null
}
# ppmr ALG SEED ITERATIONS FILE_STEM
ppmr() {
  "$ppm" "$scene" -a "$1" --seed "$2" -n "$3" --width "$size" --height "$size" --threads 2 \
    -o "$4" 2> /dev/null
}

# The references (kept between runs).
[ -f "$out/ref_smallvcm.hdr" ] || svcm vcm 100000 "$ref_iterations" "$out/ref_smallvcm.hdr"
[ -f "$out/ref_ppm.exr" ] || ppmr vcm 100000 "$ref_iterations" "$out/ref_ppm"
echo "reference means (SmallVCM, ppm; each against the other as a check):"
"$python" scripts/smallvcm_stats.py "$out/ref_ppm.exr" "$out/ref_smallvcm.hdr"
"$python" scripts/smallvcm_stats.py "$out/ref_smallvcm.hdr" "$out/ref_ppm.exr"

# Per iteration: SEEDS renders of ITERATIONS iterations per technique set and renderer.
table=$out/table.md
{
  echo "| technique | SmallVCM relMSE | ppm relMSE | SmallVCM relVar | ppm relVar | ppm / SmallVCM (relMSE) |"
  echo "|---|---|---|---|---|---|"
} > "$table"
for alg in $techniques; do
  svcm_images=() ppm_images=()
  for s in $(seq 1 "$seeds"); do
    svcm "$alg" $((s * 10)) "$iterations" "$out/smallvcm_${alg}_s$s.hdr"
    ppmr "$alg" "$s" "$iterations" "$out/ppm_${alg}_s$s"
    svcm_images+=("$out/smallvcm_${alg}_s$s.hdr")
    ppm_images+=("$out/ppm_${alg}_s$s.exr")
  done
  # Fields: K, reference mean, images' mean, relMSE, its standard error, relVar.
  # relMSE against each renderer's own reference; relVar over the same denominators (SmallVCM's).
  read -r _ _ _ s_rel s_err s_var < <("$python" scripts/smallvcm_stats.py "$out/ref_smallvcm.hdr" "${svcm_images[@]}")
  read -r _ _ _ p_rel p_err _ < <("$python" scripts/smallvcm_stats.py "$out/ref_ppm.exr" "${ppm_images[@]}")
  read -r _ _ _ _ _ p_var < <("$python" scripts/smallvcm_stats.py "$out/ref_smallvcm.hdr" "${ppm_images[@]}")
  ratio=$(python3 -c "print(f'{$p_rel / $s_rel:.2f}')")
  echo "| $alg | $s_rel ± $s_err | $p_rel ± $p_err | $s_var | $p_var | $ratio |" >> "$table"
done

# Equal CPU time, vcm (measured on whatever load the machine has): SmallVCM's ITERATIONS
# iterations and as many ppm iterations as fit in the same CPU seconds (user + sys).
cpu() { /usr/bin/time -f "%U %S" "$@" 2>&1 >/dev/null | tail -n 1 | awk '{print $1 + $2}'; }
svcm_cpu=$(cpu env SMALLVCM_RESOLUTION="$size" SMALLVCM_SEED=7 SMALLVCM_THREADS=2 \
  "$smallvcm" -s 4 -a vcm -i "$iterations" -o "$out/smallvcm_time.hdr")
ppm_cpu=$(cpu "$ppm" "$scene" -a vcm --seed 7 -n "$iterations" --width "$size" --height "$size" \
  --threads 2 -o "$out/ppm_time_probe")
ppm_iterations=$(python3 -c "print(max(1, round($iterations * $svcm_cpu / $ppm_cpu)))")
ppm_equal_cpu=$(cpu "$ppm" "$scene" -a vcm --seed 7 -n "$ppm_iterations" --width "$size" \
  --height "$size" --threads 2 -o "$out/ppm_time")
read -r _ _ _ s_time _ _ < <("$python" scripts/smallvcm_stats.py "$out/ref_smallvcm.hdr" "$out/smallvcm_time.hdr")
read -r _ _ _ p_time _ _ < <("$python" scripts/smallvcm_stats.py "$out/ref_ppm.exr" "$out/ppm_time.exr")
{
  echo
  echo "Equal CPU time, vcm (measured on a loaded machine): SmallVCM $iterations iterations in" \
    "$svcm_cpu CPU s, relMSE $s_time; ppm $ppm_iterations iterations in $ppm_equal_cpu CPU s," \
    "relMSE $p_time."
} >> "$table"
cat "$table"
