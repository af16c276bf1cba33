#!/usr/bin/env python3
"""Each cached sweep of the wall-law identification against the recordings, read straight
from its ramps: mean tip BE over the configurations fitted (N = 11, T = 1.6 left out, as the
data checks flag its rows), over the study's nine (all), the mean |force error|, and the
N = 13 / N = 11 angle ratio at 3 bar for each T (recorded: 0.99, 0.89, 0.82).

    python3 fe_reference/identification/wall_law/sweeps.py
"""
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, ".."))
from sweep_scores import score, sweeps  # noqa: E402

for sw in sweeps(here):
    s = score(sw)
    if "ramps" in s:
        print(f"{os.path.basename(sw)}: {s['ramps']} of 18 ramps")
        continue
    print(f"{os.path.basename(sw)}: tip BE {s['fitted']:.2f} mm ({s['n_fitted']} fitted), the nine "
          f"{s['nine']:.2f} mm, |F error| {s['force']:.3f} N, N13/N11 at 3 bar (T 1.6 / 2.0 / 2.4) "
          f"{s['ratios']}")
