#!/usr/bin/env bash
# ppm against SmallVCM (Davidovič's C++ implementation of vertex connection and merging) on
# SmallVCM's own Cornell box, in the variants its scene mask selects. Each mask has its
# transcription in scenes/compare/:
#   289 glossy Phong floor, large glass sphere, ceiling light  smallvcm_glass_ceiling.yml
#    33 white floor, large glass sphere, ceiling light         smallvcm_glass_box.yml
#   257 glossy Phong floor, ceiling light (no sphere)          smallvcm_glossy_box.yml
# Two parts per mask, written as Markdown tables to OUT/table.md (see docs/vcm.md, "Against
# SmallVCM", and docs/performance.md):
#
# 1. Per iteration, at ITER_SIZE: SEEDS renders of ITERATIONS iterations of each technique set
#    (vcm, bpt, bpm, lt; the same names in both renderers), their relMSE and relVar. Both are
#    measured against SmallVCM's long vcm render (REF_ITERATIONS iterations, another seed):
#    a reference independent of the images measured. (A reference made of the measured images
#    themselves, such as their mean, bounds each firefly's relative error by its own square
#    and so hides exactly the outliers being compared.)
# 2. Equal time, at each of SIZES: each renderer's algorithms for RUN_SECONDS of wall clock on
#    2 threads, ROUNDS rounds alternating the renderers (the machine may be shared), relMSE
#    against SmallVCM's long vcm render at that size; the best of each renderer and their ratio.
#
# SmallVCM is not part of ppm and none of its code is committed: the script clones it (from
# SMALLVCM_GIT: the local mirror when there is one, else GitHub) into SMALLVCM_DIR/src_repo if
# absent, copies its sources to SMALLVCM_DIR/build_masks and edits that copy only to read (a)
# the scene mask from SMALLVCM_MASK and (b) its seed, resolution, thread count and maximum path
# length from environment variables, then compiles it (g++ -O3 -fopenmp). Statistics:
# scripts/smallvcm_stats.py, run with Mitsuba's python (it reads EXR and HDR).
#
# Both renderers render SIZE x SIZE (one light subpath per pixel in both), SmallVCM's merge
# radius 0.003 x the scene's bounding-sphere radius = 0.0066512 and alpha 0.75 for vcm and bpm,
# at most 10 edges per path (SmallVCM's default; ppm's max_depth 9). ppm's ppm and sppm run at
# their default radius (`photons`), which the scene files' radius (SmallVCM's, for vcm) would
# override.
#
# Usage: scripts/smallvcm_compare.sh [OUT]
#   env: MASKS ("289"), ITER_SIZE (256), ITERATIONS (24), SEEDS (4), TECHNIQUES ("vcm bpt bpm lt"),
#        REF_ITERATIONS (800 at 256 px, scaled by (256/size)^2 above), SIZES ("256"),
#        RUN_SECONDS (20), ROUNDS (2), SVCM_ALGS ("vcm bpt pt ppm"), PPM_ALGS ("vcm pt sppm"),
#        SMALLVCM_DIR (/work/smallvcm), SMALLVCM_GIT, PYTHON (/work/venv-mitsuba/bin/python)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-compare_smallvcm_glass}
iter_size=${ITER_SIZE:-256}
iterations=${ITERATIONS:-24}
seeds=${SEEDS:-4}
techniques=${TECHNIQUES:-vcm bpt bpm lt}
sizes=${SIZES:-256}
seconds=${RUN_SECONDS:-20}
rounds=${ROUNDS:-2}
svcm_algs=${SVCM_ALGS:-vcm bpt pt ppm}
ppm_algs=${PPM_ALGS:-vcm pt sppm}
smallvcm_dir=${SMALLVCM_DIR:-/work/smallvcm}
mirror=/work/.mirror/SmallVCM+SmallVCM/repo
if [ -d "$mirror" ]; then default_git=$mirror; else default_git=https://github.com/SmallVCM/SmallVCM; fi
smallvcm_git=${SMALLVCM_GIT:-$default_git}
python=${PYTHON:-/work/venv-mitsuba/bin/python}
masks=${MASKS:-289}
ppm=target/release/ppm
smallvcm=$smallvcm_dir/smallvcm_masks
mkdir -p "$out"

# SmallVCM, built beside ppm (never inside this repository).
if [ ! -x "$smallvcm" ]; then
  if [ ! -d "$smallvcm_dir/src_repo" ]; then
    git clone --quiet "$smallvcm_git" "$smallvcm_dir/src_repo"
  fi
  rm -rf "$smallvcm_dir/build_masks"
  cp -r "$smallvcm_dir/src_repo/src" "$smallvcm_dir/build_masks"
  config=$smallvcm_dir/build_masks/config.hxx
  # The scene mask from SMALLVCM_MASK when it is set (the -s scene number otherwise).
  perl -0pi -e 's/LoadCornellBox\(oConfig.mResolution, g_SceneConfigs\[sceneID\]\)/LoadCornellBox(oConfig.mResolution, getenv("SMALLVCM_MASK") ? uint(atoi(getenv("SMALLVCM_MASK"))) : g_SceneConfigs[sceneID])/' "$config"
  # Seed, maximum path length, resolution and threads from the environment.
  perl -0pi -e 's/(oConfig.mRadiusAlpha   = 0.75f;\n)/$1    if(getenv("SMALLVCM_SEED")) oConfig.mBaseSeed = atoi(getenv("SMALLVCM_SEED"));\n    if(getenv("SMALLVCM_MAX_PATH_LENGTH")) oConfig.mMaxPathLength = atoi(getenv("SMALLVCM_MAX_PATH_LENGTH"));\n    if(getenv("SMALLVCM_RESOLUTION")) oConfig.mResolution = Vec2i(atoi(getenv("SMALLVCM_RESOLUTION")), atoi(getenv("SMALLVCM_RESOLUTION")));\n    if(getenv("SMALLVCM_THREADS")) oConfig.mNumThreads = atoi(getenv("SMALLVCM_THREADS"));\n/' "$config"
  grep -q SMALLVCM_MASK "$config" && grep -q SMALLVCM_SEED "$config" \
    || { echo "could not patch $config" >&2; exit 1; }
  g++ -O3 -march=native -fopenmp -std=c++11 -o "$smallvcm" "$smallvcm_dir/build_masks/smallvcm.cxx"
fi
CARGO_INCREMENTAL=0 cargo build --release --quiet -p ppm-cli

# svcm SIZE ALG SEED FILE [SmallVCM's options]: SmallVCM on scene $mask, 2 threads (seeds SEED,
# SEED + 1).
svcm() {
  local size=$1 alg=$2 seed=$3 file=$4
  shift 4
  SMALLVCM_MASK=$mask SMALLVCM_RESOLUTION=$size SMALLVCM_SEED=$seed SMALLVCM_THREADS=2 \
    "$smallvcm" -a "$alg" -o "$file" "$@" > /dev/null
}
# ppmr SIZE ALG SEED FILE_STEM [ppm's options]: ppm on $scene.
ppmr() {
  local size=$1 alg=$2 seed=$3 file=$4
  shift 4
  "$ppm" "$scene" -a "$alg" --seed "$seed" --width "$size" --height "$size" --threads 2 \
    -o "$file" -q "$@"
}
# stats REFERENCE IMAGE...: K, reference mean, images' mean, relMSE, its standard error, relVar.
stats() { "$python" scripts/smallvcm_stats.py "$@"; }
# reference SIZE: SmallVCM's long vcm render of scene $mask at SIZE (kept between runs).
reference() {
  local size=$1 n=${REF_ITERATIONS:-$((800 * 256 * 256 / ($1 * $1)))}
  local file=$out/ref_smallvcm_m${mask}_$size.hdr
  [ -f "$file" ] || svcm "$size" vcm 100000 "$file" -i "$n"
  echo "$file"
}

table=$out/table.md
: > "$table"

for mask in $masks; do
  case $mask in
    289) scene=scenes/compare/smallvcm_glass_ceiling.yml ;;
    33) scene=scenes/compare/smallvcm_glass_box.yml ;;
    257) scene=scenes/compare/smallvcm_glossy_box.yml ;;
    *) echo "no transcription of SmallVCM's scene mask $mask in scenes/compare/" >&2; exit 1 ;;
  esac
  echo "## SmallVCM's scene mask $mask ($scene)" >> "$table"
  m=$out/m$mask
  mkdir -p "$m"

  # 1. Per iteration.
  if [ -n "$techniques" ]; then
    ref=$(reference "$iter_size")
    {
      echo
      echo "Per iteration: $iter_size x $iter_size, $iterations iterations, $seeds seeds, against" \
        "SmallVCM's vcm of ${REF_ITERATIONS:-$((800 * 256 * 256 / (iter_size * iter_size)))} iterations (mean $(stats "$ref" "$ref" | cut -f2))."
      echo
      echo "| technique | SmallVCM relMSE | ppm relMSE | SmallVCM relVar | ppm relVar | ppm / SmallVCM (relVar) |"
      echo "|---|---|---|---|---|---|"
    } >> "$table"
    for alg in $techniques; do
      svcm_images=() ppm_images=()
      for s in $(seq 1 "$seeds"); do
        svcm "$iter_size" "$alg" $((s * 10)) "$m/smallvcm_${alg}_s$s.hdr" -i "$iterations"
        ppmr "$iter_size" "$alg" "$s" "$m/ppm_${alg}_s$s" -n "$iterations"
        svcm_images+=("$m/smallvcm_${alg}_s$s.hdr")
        ppm_images+=("$m/ppm_${alg}_s$s.exr")
      done
      read -r _ _ _ s_rel s_err s_var < <(stats "$ref" "${svcm_images[@]}")
      read -r _ _ _ p_rel p_err p_var < <(stats "$ref" "${ppm_images[@]}")
      ratio=$(python3 -c "print(f'{$p_var / $s_var:.2f}')")
      echo "| $alg | $s_rel ± $s_err | $p_rel ± $p_err | $s_var | $p_var | $ratio |" >> "$table"
    done
  fi

  # 2. Equal time.
  for size in $sizes; do
    ref=$(reference "$size")
    {
      echo
      echo "Equal time: $size x $size, $seconds s of wall clock on 2 threads per run, $rounds" \
        "rounds alternating the renderers; relMSE against SmallVCM's long vcm render (mean" \
        "over the rounds; min-max); image means against the reference's mean $(stats "$ref" "$ref" | cut -f2)."
      echo
      echo "| renderer | algorithm | relMSE | min | max | mean ÷ reference's |"
      echo "|---|---|---|---|---|---|"
    } >> "$table"
    for r in $(seq 1 "$rounds"); do
      for alg in $svcm_algs; do
        svcm "$size" "$alg" $((1000 + r * 10)) "$m/time_smallvcm_${size}_${alg}_r$r.hdr" \
          -t "$seconds"
      done
      for alg in $ppm_algs; do
        extra=()
        # ppm's photon mappers choose their own radius (the default rule, which the scene
        # file's radius would override); vcm keeps SmallVCM's.
        if [ "$alg" = sppm ] || [ "$alg" = ppm ]; then extra=(--radius photons); fi
        ppmr "$size" "$alg" $((1000 + r)) "$m/time_ppm_${size}_${alg}_r$r" \
          --time-limit "$seconds" "${extra[@]}"
      done
    done
    best_s=1e9 best_p=1e9
    for who in smallvcm ppm; do
      if [ $who = smallvcm ]; then algs=$svcm_algs ext=hdr; else algs=$ppm_algs ext=exr; fi
      for alg in $algs; do
        values=() means=()
        for r in $(seq 1 "$rounds"); do
          read -r _ ref_mean mean rel _ < <(stats "$ref" "$m/time_${who}_${size}_${alg}_r$r.$ext")
          values+=("$rel")
          means+=("$(python3 -c "print($mean / $ref_mean)")")
        done
        read -r mean lo hi bias < <(python3 -c "v=[float(x) for x in '${values[*]}'.split()]; b=[float(x) for x in '${means[*]}'.split()]; print(f'{sum(v)/len(v):.5f} {min(v):.5f} {max(v):.5f} {sum(b)/len(b):.4f}')")
        echo "| $who | $alg | $mean | $lo | $hi | $bias |" >> "$table"
        if [ $who = smallvcm ]; then
          best_s=$(python3 -c "print(min($best_s, $mean))")
        else
          best_p=$(python3 -c "print(min($best_p, $mean))")
        fi
      done
    done
    echo >> "$table"
    echo "Best at $size px: ppm $best_p, SmallVCM $best_s, ratio $(python3 -c "print(f'{$best_p / $best_s:.2f}')")." >> "$table"
    echo >> "$table"
  done
done
cat "$table"
