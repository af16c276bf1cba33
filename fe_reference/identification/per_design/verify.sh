#!/bin/sh
# FE at each design's own wall offset (offsets_wall_bias.json from fit.py), bending and
# blocked force, coarse mesh, two runs at a time on the 2 cores. Resumable: a finished run's
# JSON is kept.
set -e
cd "$(dirname "$0")"
M=1.0781549017819898,8.297012362485463,-2.634,-0.5
G=../coarse_balanced/geometry.json
BIN=${BIN:-../../../target/release/surrogate}
python3 -c "
import json
for k, v in json.load(open('offsets_wall_bias.json')).items():
    n, t = k.split(',')
    for mode in ('bending', 'force'):
        print(n, t, mode, v)
" | xargs -P 2 -L 1 sh -c '
    out=verify/n$0_t$1_$2.json
    [ -f "$out" ] && exit 0
    RAYON_NUM_THREADS=1 nice $BIN simulate --n $0 --t $1 --mode $2 --mesh coarse --geometry '"$G"' \
        --material='"$M"' --effect wall_bias=$3 --effect plate_offset=-4.5 --out $out.tmp > /dev/null 2>&1 \
        && mv $out.tmp $out'
