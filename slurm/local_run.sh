#!/usr/bin/env bash
# Proves the Slurm path on a single-node cluster and writes slurm/local_run.log:
# starts the cluster (local_cluster.sh), writes a tiny real-FE plan (4 cases, N = 7, coarse
# mesh with 20 mm elements, gravity, 0 and 0.5 bar), submits it as a 2-task job array plus the
# dependent merge (submit.sh), waits for both, runs the same plan on this machine without Slurm,
# compares the two merged files byte for byte, and re-simulates 3 random cases.
#
#   bash slurm/local_run.sh [WORKDIR]      (as root; WORKDIR default /tmp/surrogate-slurm-run)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
REPO=$(dirname "$HERE")
WORK=${1:-/tmp/surrogate-slurm-run}
# before the log is (re)written: the log itself would make the tree dirty
describe=$(git -C "$REPO" describe --always --dirty)
exec > >(tee "$HERE/local_run.log") 2>&1

echo "# slurm/local_run.sh: $(date -u +%FT%TZ) on $(hostname), commit $describe"
echo "## start the single-node cluster"
bash "$HERE/local_cluster.sh"
sbatch --version

echo "## build"
(cd "$REPO" && SURROGATE_GIT_DESCRIBE=$describe cargo build --release --quiet)
export SURROGATE=${CARGO_TARGET_DIR:-$REPO/target}/release/surrogate
"$SURROGATE" --version

echo "## plan"
rm -rf "$WORK"
mkdir -p "$WORK"
"$SURROGATE" snapshots plan --cases 4 --seed 7 --n-values 7 --pressures 0,0.5 \
    --mesh coarse --element-size 20 --out "$WORK/plan.json"

echo "## submit: job array of 2 shards, then the merge"
ids=$(bash "$HERE/submit.sh" "$WORK/plan.json" 2 "$WORK/slurm" "$WORK/slurm_merged.csv" | tee /dev/stderr | tail -1)
array=$(sed 's/.*array=\([0-9]*\).*/\1/' <<<"$ids")
merge=$(sed 's/.*merge=\([0-9]*\).*/\1/' <<<"$ids")
start=$(date +%s)
while [[ -n $(squeue -h -j "$array,$merge" 2>/dev/null) ]]; do
    echo "--- t = $(($(date +%s) - start)) s"
    squeue -j "$array,$merge" -o "%.12i %.16j %.9T %.10M %R"
    sleep 15
done
echo "## job states (t = $(($(date +%s) - start)) s)"
for j in "${array}_0" "${array}_1" "$merge"; do
    scontrol show job "$j" | grep -oE "(JobId|ArrayJobId|ArrayTaskId|JobName|JobState|ExitCode|RunTime)=[^ ]+" | paste -sd' '
done
for f in "$WORK"/slurm/logs/*.log; do
    echo "## $f"
    cat "$f"
done

echo "## the same plan on this machine, without Slurm"
"$SURROGATE" snapshots --plan "$WORK/plan.json" --out "$WORK/single" --threads 2 --quiet
"$SURROGATE" snapshots merge --from "$WORK/single" --out "$WORK/single_merged.csv"

echo "## compare"
sha256sum "$WORK/slurm_merged.csv" "$WORK/single_merged.csv"
if cmp "$WORK/slurm_merged.csv" "$WORK/single_merged.csv"; then
    echo "IDENTICAL: the Slurm job array + merge equals the single-machine run"
else
    echo "DIFFERENT"
    exit 1
fi
echo "## re-simulate 3 random cases of the merged file and compare (tolerance 1e-9)"
"$SURROGATE" snapshots verify --data "$WORK/slurm_merged.csv" --cases 3 --seed 1

echo "## merged file (first 12 columns)"
cut -d, -f1-12 "$WORK/slurm_merged.csv"
