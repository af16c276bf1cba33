#!/usr/bin/env bash
# Submits the snapshots of a plan to Slurm: a job array with one task per shard, then the merge
# (a dependent job that starts when every task succeeded). Prints both job ids.
#
#   bash slurm/submit.sh PLAN N_SHARDS OUT MERGED [extra `snapshots run` arguments]
#   e.g. bash slurm/submit.sh plan.json 16 /scratch/$USER/snap training_data/snapshots.csv
#
# Environment: SURROGATE (binary; default: built here with cargo build --release, with
# SURROGATE_GIT_DESCRIBE from git describe for the code_version column), CPUS_PER_TASK
# (default 1: cases of a shard run in parallel on them), SBATCH_ARGS (extra sbatch options,
# e.g. "--partition=long --time=24:00:00"). The paths must be visible from the compute nodes.
set -euo pipefail

if [[ $# -lt 4 ]]; then
    sed -n '2,12p' "$0" >&2
    exit 2
fi
PLAN=$(realpath "$1"); N=$2; OUT=$(realpath -m "$3"); MERGED=$(realpath -m "$4"); shift 4
RUN_ARGS="$*"
[[ $N =~ ^[1-9][0-9]*$ ]] || { echo "error: N_SHARDS '$N': expected an integer ≥ 1" >&2; exit 2; }
HERE=$(cd "$(dirname "$0")" && pwd)
REPO=$(dirname "$HERE")

if [[ -z ${SURROGATE:-} ]]; then
    describe=$(git -C "$REPO" describe --always --dirty 2>/dev/null || true)
    (cd "$REPO" && SURROGATE_GIT_DESCRIBE=$describe cargo build --release --quiet)
    SURROGATE=${CARGO_TARGET_DIR:-$REPO/target}/release/surrogate
fi
SURROGATE=$(realpath "$SURROGATE")
# fail here, not in N tasks, on a bad plan or a directory of another plan
"$SURROGATE" snapshots run --plan "$PLAN" --shard "1/$N" --out "$OUT/shard_1" --dry-run

mkdir -p "$OUT/logs"
export PLAN OUT MERGED SURROGATE RUN_ARGS
# shellcheck disable=SC2086 # SBATCH_ARGS is a list of options
array=$(sbatch --parsable --array="0-$((N - 1))" --cpus-per-task="${CPUS_PER_TASK:-1}" \
    --output="$OUT/logs/shard_%a.log" --export=ALL ${SBATCH_ARGS:-} "$HERE/snapshots.sbatch")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes \
    --job-name=snapshots-merge --output="$OUT/logs/merge.log" --export=ALL ${SBATCH_ARGS:-} \
    "$HERE/snapshots.sbatch")
merge=${merge%%;*}
echo "submitted: array job $array ($N shards of $PLAN into $OUT), merge job $merge -> $MERGED"
echo "array=$array merge=$merge"
