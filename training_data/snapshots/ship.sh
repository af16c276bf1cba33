#!/usr/bin/env bash
# Builds the shipped snapshot sets and the shipped models from the case files in this folder.
#
#   bash training_data/snapshots/ship.sh            # both sets complete (the shipped model)
#   bash training_data/snapshots/ship.sh --coarse   # the coarse set complete: the coarse-value
#        model models/actuator_coarse.json (the `demo` default) and training_data/snapshots_coarse.csv
#   bash training_data/snapshots/ship.sh --partial  # an interim model from the finished cases
#        (training_data/snapshots_interim_*.csv, models/actuator_interim*: not the shipped names)
#
# 1. merges the coarse plan (300 cases) and the standard-mesh subset (30 cases of the same plan)
#    into training_data/snapshots_coarse.csv and training_data/snapshots_standard.csv (each
#    with its plan beside it; byte-identical to a single run);
# 2. trains models/actuator.json: the coarse set, each ramp warped in pressure and corrected by
#    the standard-minus-coarse discrepancy learnt on the subset (src/rom/fidelity.rs,
#    src/rom/warp.rs); the stored validation is 5-fold by case with 3 fold assignments pooled;
#    the whole pipeline is also checked against standard-mesh cases it never saw
#    (--check-high-fidelity, stored in the model);
# 3. writes every held-out prediction (models/actuator_held_out.csv) and the plot of
#    the held-out errors (models/actuator_held_out.svg);
# 4. stores in models/actuator.json its model-form error, learned from the residuals of the
#    committed calibration through it (fe_reference/calibration/surrogate/report.json;
#    `surrogate model-form` refuses a report whose predictions are not the model's: after a
#    retraining that moves them, calibrate again first).
#
# SURROGATE=path/to/surrogate overrides the binary (default: cargo run --release).
set -euo pipefail
cd "$(dirname "$0")/../.."

partial=()
coarse_only=0
model=models/actuator
sets=training_data/snapshots
if [[ "${1:-}" == "--partial" ]]; then
    partial=(--partial)
    model=models/actuator_interim
    sets=training_data/snapshots_interim
elif [[ "${1:-}" == "--coarse" ]]; then
    coarse_only=1
elif [[ -n "${1:-}" ]]; then
    echo "usage: $0 [--partial | --coarse]" >&2
    exit 2
fi
if [[ -n "${SURROGATE:-}" ]]; then
    run() { "$SURROGATE" "$@"; }
else
    cargo build --release --quiet
    run() { target/release/surrogate "$@"; }
fi

run snapshots merge --from training_data/snapshots/coarse \
    --out "${sets}_coarse.csv" "${partial[@]}"
if [[ $coarse_only == 1 ]]; then
    time run train --data "${sets}_coarse.csv" \
        --folds 5 --repeats 3 \
        --held-out models/actuator_coarse_held_out.csv --plot models/actuator_coarse_held_out.svg \
        --out models/actuator_coarse.json --force
    exit 0
fi
run snapshots merge --from training_data/snapshots/standard \
    --out "${sets}_standard.csv" "${partial[@]}"
time run train --data "${sets}_coarse.csv" \
    --high-fidelity "${sets}_standard.csv" \
    --pressure-warp --check-high-fidelity \
    --folds 5 --repeats 3 \
    --held-out "${model}_held_out.csv" --plot "${model}_held_out.svg" \
    --out "${model}.json" --force
if [[ ${#partial[@]} == 0 ]]; then
    run model-form --model "${model}.json" \
        --calibration fe_reference/calibration/surrogate/report.json \
        --out "${model}.json" --force
fi
