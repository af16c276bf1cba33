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
import csv
import glob
import json
import math
import os

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.join(here, "..", "..", "..")
key = lambda r: (int(r["n_bellows"]), float(r["wall_thickness_mm"]), float(r["pressure_bar"]))
bend = {key(r): r for r in csv.DictReader(open(os.path.join(root, "training_data/bending_experiments.csv")))}
force = {key(r): r for r in csv.DictReader(open(os.path.join(root, "training_data/blocked_force_experiments.csv")))}
fine = {key(r): r for r in csv.DictReader(open(os.path.join(here, "..", "wall_law", "standard.csv")))}
coarse = {key(r): r for r in csv.DictReader(open(os.path.join(here, "..", "wall_law", "coarse.csv")))}
corr = {
    k: {q: float(fine[k][q + "_sim_" + u]) - float(coarse[k][q + "_sim_" + u])
        for q, u in (("uz", "mm"), ("uy", "mm"), ("angle", "deg"), ("force", "n"))}
    for k in fine
}


def steps(path):
    d = json.load(open(path))
    s = d.get("sensitivities")
    return s["steps"] if isinstance(s, dict) else d["steps"]


def design(path):
    name = os.path.basename(path).split("_")
    return int(name[0][1:]), float(name[1][1:])


for sw in sorted(glob.glob(os.path.join(here, "fe_ramps", "sweep_*"))):
    be, all27, nine, fe, ang = [], [], [], [], {}
    files = glob.glob(os.path.join(sw, "*_sensitivities.json"))
    if len(files) < 18:
        print(f"{os.path.basename(sw)}: {len(files)} of 18 ramps")
        continue
    for f in files:
        n, t = design(f)
        for st in steps(f):
            v = st.get("values", st)
            k = (n, t, st["pressure_bar"])
            if "_bending_" in f and k in bend:
                r, c = bend[k], corr[k]
                e = math.hypot(v["tip_uz_mm"] + c["uz"] - float(r["tip_uz_mm"]),
                               v["tip_uy_mm"] + c["uy"] - float(r["tip_uy_mm"]))
                all27.append(e)
                if not (n == 11 and t == 1.6):
                    be.append(e)
                if (t, k[2]) in ((1.6, 1.0), (2.0, 2.0), (2.4, 3.0)):
                    nine.append(e)
                ang[k] = v["angle_deg"] + c["angle"]
            if "_force_" in f and k in force:
                fe.append(abs(v["force_n"] + corr[k]["force"] - float(force[k]["force_n"])))
    m = lambda x: sum(x) / len(x)
    ratios = " / ".join(f"{ang[(13, t, 3.0)] / ang[(11, t, 3.0)]:.2f}" for t in (1.6, 2.0, 2.4))
    print(f"{os.path.basename(sw)}: tip BE {m(be):.2f} mm ({len(be)} fitted), all 27 {m(all27):.2f} mm, "
          f"the nine {m(nine):.2f} mm, |F error| {m(fe):.3f} N, N13/N11 at 3 bar (T 1.6 / 2.0 / 2.4) {ratios}")
