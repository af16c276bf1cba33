#!/usr/bin/env bash
# Builds the shipped models from the shipped snapshot sets.
#
#   bash training_data/snapshots/ship.sh            # the shipped multi-fidelity model models/actuator.json
#   bash training_data/snapshots/ship.sh --coarse   # the coarse-value model models/actuator_coarse.json
#   bash training_data/snapshots/ship.sh --as-modelled [--coarse]
#       # the models on the geometry as modelled before the identification, N = 9, 11, 13
#       # (models/as_modelled/), which the blind study reads
#
# The shipped models are on the identified geometry (`--geometry identified`, the force rig's
# plate -4.5 mm, recorded in each model as `training.built_with`), every N from 7 to 15:
# the design-space coarse set with the box extension's two rounds appended (--add-data), N
# ordinal, a sparse GP on 150 inducing points; the multi-fidelity one is warped in pressure
# and corrected by the design-space standard subset.
#
# The sets are committed once each, as the merge of their campaign (`snapshots merge`, which
# is byte-identical to a single run of the plan, whatever the sharding or resume history),
# with the plan beside them:
#   training_data/snapshots_design_space_coarse.csv    plan 9d6561c9, 450 cases, coarse mesh
#   fe_reference/identification/design_space/extend/extend_{1,2}.csv   the box extension, 72 cases
#   training_data/snapshots_design_space_standard.csv  plan 6a0ffd14, 36 cases, standard mesh
#   training_data/snapshots_coarse.csv    plan bdd27aba, 300 cases, coarse mesh (as modelled)
#   training_data/snapshots_standard.csv  plan 35616428, 30 of those cases, standard mesh (as modelled)
# `tests/rom/shipped_model.rs` checks that each holds every case of its plan exactly once and
# that retraining reproduces the models.
#
# 1. trains models/actuator.json: the coarse set, each ramp warped in pressure and corrected by
#    the standard-minus-coarse discrepancy learnt on the subset (src/rom/fidelity.rs,
#    src/rom/warp.rs); the stored validation is 5-fold by case with 3 fold assignments pooled;
#    N = 8, 10, 14 are held out once more to measure the interpolation in N; the whole
#    pipeline is also checked against standard-mesh cases it never saw (--check-high-fidelity,
#    stored in the model); about 45 min on one core;
# 2. writes every held-out prediction (models/actuator_held_out.csv) and the plot of
#    the held-out errors (models/actuator_held_out.svg);
# 3. stores in models/actuator.json its model-form error, learned from the residuals of the
#    committed calibration through it (fe_reference/identification/shipped_surrogate/report.json;
#    `surrogate model-form` refuses a report whose predictions are not the model's: after a
#    retraining that moves them, calibrate again first).
#
# SURROGATE=path/to/surrogate overrides the binary (default: cargo run --release).
set -euo pipefail
cd "$(dirname "$0")/../.."

coarse_only=0
as_modelled=0
if [[ "${1:-}" == "--as-modelled" ]]; then
    as_modelled=1
    shift
fi
if [[ "${1:-}" == "--coarse" ]]; then
    coarse_only=1
elif [[ -n "${1:-}" ]]; then
    echo "usage: $0 [--as-modelled] [--coarse]" >&2
    exit 2
fi
if [[ -n "${SURROGATE:-}" ]]; then
    run() { "$SURROGATE" "$@"; }
else
    cargo build --release --quiet
    run() { target/release/surrogate "$@"; }
fi

if [[ $as_modelled == 0 ]]; then
    # 522 cases, a sparse GP on 150 inducing points, N ordinal, N = 8, 10, 14 held out once
    # more to measure the interpolation in N; about 13 min (coarse) and 45 min each on one core
    extend=fe_reference/identification/design_space/extend
    common=(--data training_data/snapshots_design_space_coarse.csv
        --add-data "$extend/extend_1.csv" --add-data "$extend/extend_2.csv"
        --ordinal-n --hold-out-n 8,10,14 --inducing 150 --folds 5 --repeats 3)
    if [[ $coarse_only == 1 ]]; then
        time run train "${common[@]}" \
            --held-out models/actuator_coarse_held_out.csv --plot models/actuator_coarse_held_out.svg \
            --out models/actuator_coarse.json --force
        exit 0
    fi
    time run train "${common[@]}" \
        --high-fidelity training_data/snapshots_design_space_standard.csv \
        --pressure-warp --check-high-fidelity \
        --held-out models/actuator_held_out.csv --plot models/actuator_held_out.svg \
        --out models/actuator.json --force
    run model-form --model models/actuator.json \
        --calibration fe_reference/identification/shipped_surrogate/report.json \
        --out models/actuator.json --force
    exit 0
fi

# the geometry as modelled: 300 coarse cases, 30 standard ones, N = 9, 11, 13
model=models/as_modelled/actuator
sets=training_data/snapshots

if [[ $coarse_only == 1 ]]; then
    time run train --data "${sets}_coarse.csv" \
        --folds 5 --repeats 3 \
        --held-out models/as_modelled/actuator_coarse_held_out.csv --plot models/as_modelled/actuator_coarse_held_out.svg \
        --out models/as_modelled/actuator_coarse.json --force
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
