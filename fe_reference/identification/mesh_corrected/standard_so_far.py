#!/usr/bin/env python3
"""The standard-mesh ramps at the mesh-corrected optimum (sweep 6) committed so far, against the
corrected coarse estimate of the identification (report.json) and the recordings: how well the
correction taken at the wall-law point predicts the standard mesh at the new point.

    python3 fe_reference/identification/mesh_corrected/standard_so_far.py
"""
import glob
import json
import math
import os

here = os.path.dirname(os.path.abspath(__file__))
rows = {(r["n_bellows"], r["wall_thickness_mm"], r["pressure_bar"]): r
        for r in json.load(open(os.path.join(here, "report.json")))["rows"]}
for f in sorted(glob.glob(os.path.join(here, "standard_ramps", "*.json"))):
    name = os.path.basename(f)[:-5].split("_")
    n, t, mode = int(name[0][1:]), float(name[1][1:]), name[2]
    for s in json.load(open(f))["steps"][1:]:
        r = rows[(n, t, s["pressure_bar"])]
        if mode == "bending":
            std = (s["tip_uz_mm"], s["tip_uy_mm"])
            be = math.hypot(std[0] - r["uz_mm"][0], std[1] - r["uy_mm"][0])
            print(f"N {n} T {t} P {s['pressure_bar']:.0f} bending: tip rec ({r['uz_mm'][0]:.1f}, {r['uy_mm'][0]:.1f}) "
                  f"estimate ({r['uz_mm'][1]:.1f}, {r['uy_mm'][1]:.1f}) standard ({std[0]:.1f}, {std[1]:.1f}); "
                  f"BE estimate {r['be_mm']:.2f} standard {be:.2f} mm")
        else:
            print(f"N {n} T {t} P {s['pressure_bar']:.0f} force: rec {r['force_n'][0]:.3f} "
                  f"estimate {r['force_n'][1]:.3f} standard {s['force_n']:.3f} N")
