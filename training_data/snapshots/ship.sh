#!/usr/bin/env bash
# Builds the shipped models from the shipped snapshot sets.
#
#   bash training_data/snapshots/ship.sh            # the shipped multi-fidelity model
#   bash training_data/snapshots/ship.sh --coarse   # the coarse-value model models/actuator_coarse.json
#   bash training_data/snapshots/ship.sh --identified [--coarse]
#       # the models on the identified geometry, every N from 7 to 15 (models/identified/):
#       # the design-space coarse set with the box extension's two rounds appended
#       # (--add-data), the multi-fidelity one corrected by the design-space standard subset
#
# The sets are committed once each, as the merge of their campaign (`snapshots merge`, which
# is byte-identical to a single run of the plan, whatever the sharding or resume history),
# with the plan beside them:
#   training_data/snapshots_coarse.csv    plan bdd27aba, 300 cases, coarse mesh
#   training_data/snapshots_standard.csv  plan 35616428, 30 of those cases, standard mesh
# `tests/rom/shipped_model.rs` checks that each holds every case of its plan exactly once and
# that retraining reproduces the models.
#
# 1. trains models/actuator.json: the coarse set, each ramp warped in pressure and corrected by
#    the standard-minus-coarse discrepancy learnt on the subset (src/rom/fidelity.rs,
#    src/rom/warp.rs); the stored validation is 5-fold by case with 3 fold assignments pooled;
#    the whole pipeline is also checked against standard-mesh cases it never saw
#    (--check-high-fidelity, stored in the model);
# 2. writes every held-out prediction (models/actuator_held_out.csv) and the plot of
#    the held-out errors (models/actuator_held_out.svg);
# 3. stores in models/actuator.json its model-form error, learned from the residuals of the
#    committed calibration through it (fe_reference/calibration/surrogate/report.json;
#    `surrogate model-form` refuses a report whose predictions are not the model's: after a
#    retraining that moves them, calibrate again first).
#
# SURROGATE=path/to/surrogate overrides the binary (default: cargo run --release).
set -euo pipefail
cd "$(dirname "$0")/../.."

coarse_only=0
identified=0
model=models/actuator
sets=training_data/snapshots
if [[ "${1:-}" == "--identified" ]]; then
    identified=1
    shift
fi
if [[ "${1:-}" == "--coarse" ]]; then
    coarse_only=1
elif [[ -n "${1:-}" ]]; then
    echo "usage: $0 [--identified] [--coarse]" >&2
    exit 2
fi
if [[ -n "${SURROGATE:-}" ]]; then
    run() { "$SURROGATE" "$@"; }
else
    cargo build --release --quiet
    run() { target/release/surrogate "$@"; }
fi

if [[ $identified == 1 ]]; then
    # 522 cases, a sparse GP on 150 inducing points, N ordinal, N = 8, 10, 14 held out once
    # more to measure the interpolation in N; about 13 min each on one core
    out=models/identified
    extend=fe_reference/identification/design_space/extend
    common=(--data training_data/snapshots_design_space_coarse.csv
        --add-data "$extend/extend_1.csv" --add-data "$extend/extend_2.csv"
        --ordinal-n --hold-out-n 8,10,14 --inducing 150 --folds 5 --repeats 3)
    mkdir -p "$out"
    if [[ $coarse_only == 1 ]]; then
        time run train "${common[@]}" \
            --held-out "$out/actuator_coarse_held_out.csv" --plot "$out/actuator_coarse_held_out.svg" \
            --out "$out/actuator_coarse.json" --force
    else
        time run train "${common[@]}" \
            --high-fidelity training_data/snapshots_design_space_standard.csv \
            --pressure-warp --check-high-fidelity \
            --held-out "$out/actuator_held_out.csv" --plot "$out/actuator_held_out.svg" \
            --out "$out/actuator.json" --force
    fi
    exit 0
fi

if [[ $coarse_only == 1 ]]; then
    time run train --data "${sets}_coarse.csv" \
        --folds 5 --repeats 3 \
        --held-out models/actuator_coarse_held_out.csv --plot models/actuator_coarse_held_out.svg \
        --out models/actuator_coarse.json --force
    exit 0
fi
time run train --data "${sets}_coarse.csv" \
    --high-fidelity "${sets}_standard.csv" \
    --pressure-warp --check-high-fidelity \
    --folds 5 --repeats 3 \
    --held-out "${model}_held_out.csv" --plot "${model}_held_out.svg" \
    --out "${model}.json" --force
run model-form --model "${model}.json" \
    --calibration fe_reference/calibration/surrogate/report.json \
    --out "${model}.json" --force
