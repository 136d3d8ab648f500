#!/bin/bash
# Renders a scene on a Slurm cluster: a job array of K shards, then a merge job that starts
# when all of them succeeded. Prints the two job ids.
#
#   scripts/slurm/submit.sh SCENE ITERATIONS SHARDS OUT_DIR [ppm render flags...]
#
# e.g. scripts/slurm/submit.sh scenes/cornell_box.yml 4096 64 /shared/box --width 1024
# renders 64 shards of 64 iterations each and writes /shared/box/merged.png and .exr.
# OUT_DIR must be on a file system every node sees. Extra sbatch options (partition, time
# limit, account) can be given in SBATCH_ARGS, e.g. SBATCH_ARGS="-p long -t 2:00:00".
# PPM names the ppm binary (default: ppm on PATH; give an absolute path).
set -euo pipefail

if (($# < 4)); then
    sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
scene=$1 iterations=$2 shards=$3 out_dir=$4
shift 4
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out_dir"
out_dir=$(cd "$out_dir" && pwd)
scene=$(realpath "$scene")

# Each flag single-quoted (a ' inside written '\''), so render_shard.sbatch gets back exactly
# these words: spaces, quotes and glob characters in them survive.
ppm_args=""
for arg in "$@"; do
    ppm_args+="'${arg//\'/\'\\\'\'}' "
done
export PPM=${PPM:-ppm} SCENE=$scene ITERATIONS=$iterations OUT_DIR=$out_dir PPM_ARGS=$ppm_args
# shellcheck disable=SC2086 # SBATCH_ARGS is a list of options
array=$(sbatch --parsable ${SBATCH_ARGS:-} --array="0-$((shards - 1))" \
    --output="$out_dir/shard_%a.log" --export=ALL "$here/render_shard.sbatch")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency="afterok:$array" --kill-on-invalid-dep=yes \
    --output="$out_dir/merge.log" --export=ALL "$here/merge.sbatch")
merge=${merge%%;*}
echo "shards: job $array (array 0-$((shards - 1))), merge: job $merge"
