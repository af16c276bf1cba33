#!/usr/bin/env python3
"""Each cached sweep of the mesh-corrected identification against the recordings, read straight
from its coarse ramps plus the mesh correction (standard − coarse at the wall-law optimum,
`../wall_law/standard.csv` − `../wall_law/coarse.csv`): mean tip BE over the configurations
fitted (N = 11, T = 1.6 left out, as the data checks flag its rows), over all 27 and over the
study's nine, the mean |force error|, and the N = 13 / N = 11 angle ratio at 3 bar for each T
(recorded: 0.99, 0.89, 0.82). These are estimates of the standard mesh; `standard.csv` here is
the standard mesh itself at the optimum.

    python3 fe_reference/identification/mesh_corrected/sweeps.py
"""
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, ".."))
from sweep_scores import score, sweeps, table  # noqa: E402

fine = table(os.path.join(here, "..", "wall_law", "standard.csv"))
coarse = table(os.path.join(here, "..", "wall_law", "coarse.csv"))
corr = {
    k: {q: float(fine[k][q + "_sim_" + u]) - float(coarse[k][q + "_sim_" + u])
        for q, u in (("uz", "mm"), ("uy", "mm"), ("angle", "deg"), ("force", "n"))}
    for k in fine
}

for sw in sweeps(here):
    s = score(sw, corr)
    if "ramps" in s:
        print(f"{os.path.basename(sw)}: {s['ramps']} of 18 ramps")
        continue
    print(f"{os.path.basename(sw)}: tip BE {s['fitted']:.2f} mm ({s['n_fitted']} fitted), all 27 "
          f"{s['all27']:.2f} mm, the nine {s['nine']:.2f} mm, |F error| {s['force']:.3f} N, "
          f"N13/N11 at 3 bar (T 1.6 / 2.0 / 2.4) {s['ratios']}")
