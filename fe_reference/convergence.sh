#!/usr/bin/env bash
# Mesh convergence of the actuator, N=11, T=2.0 mm, Ogden 002, gravity on, P = 0,1,2,3 bar,
# on the three levels of one refinement family (coarse h=6 mm / 1 element through a wall,
# standard h=3 / 2, fine h=2 / 3):
#   - bending, no contact (issue 2, verification 7)
#   - blocked force, contact on (issue 3, verification 5)
#   - bending, contact on (the configuration of the snapshots and of the baseline)
# Regenerate: bash fe_reference/convergence.sh
#   (writes fe_reference/convergence/*.json and table.md; two runs at a time, one thread
#    each; about 1.5 h on 2 cores. Existing JSON files are kept: delete them to rerun.)
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin="${CARGO_TARGET_DIR:-target}/release/surrogate"
out=fe_reference/convergence
mkdir -p "$out"
run() { # mode level [flags]
  local mode=$1 level=$2; shift 2
  local f="$out/n11_t2.0_${mode}_${level}.json"
  if [ "$mode" = bending ] && [[ " $* " != *" --no-contact "* ]]; then
    f="$out/n11_t2.0_bending_contact_${level}.json"
  fi
  if [ ! -s "$f" ]; then
    RAYON_NUM_THREADS=1 "$bin" simulate --n 11 --t 2.0 --pressures 0,1,2,3 \
      --material ogden_002 --mesh "$level" --mode "$mode" "$@" --out "$f.tmp" 2>/dev/null
    mv "$f.tmp" "$f"
  fi
}
( run bending coarse --no-contact; run bending standard --no-contact; run bending fine --no-contact ) &
( run force coarse; run force standard; run force fine ) &
wait
( run bending coarse; run bending standard ) &
( run bending fine ) &
wait
python3 fe_reference/convergence_table.py "$out"
