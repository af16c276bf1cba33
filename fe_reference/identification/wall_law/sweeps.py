#!/usr/bin/env python3
"""Each cached sweep of the wall-law identification against the recordings, read straight
from its ramps: mean tip BE over the configurations fitted (N = 11, T = 1.6 left out, as the
data checks flag its rows), over the study's nine (all), the mean |force error|, and the
N = 13 / N = 11 angle ratio at 3 bar for each T (recorded: 0.99, 0.89, 0.82).

    python3 fe_reference/identification/wall_law/sweeps.py
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


def steps(path):
    d = json.load(open(path))
    s = d.get("sensitivities")
    return s["steps"] if isinstance(s, dict) else d["steps"]


def design(path):
    name = os.path.basename(path).split("_")
    return int(name[0][1:]), float(name[1][1:])


for sw in sorted(glob.glob(os.path.join(here, "fe_ramps", "sweep_*"))):
    be, nine, fe, ang = [], [], [], {}
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
                r = bend[k]
                e = math.hypot(v["tip_uz_mm"] - float(r["tip_uz_mm"]), v["tip_uy_mm"] - float(r["tip_uy_mm"]))
                if not (n == 11 and t == 1.6):
                    be.append(e)
                if (t, k[2]) in ((1.6, 1.0), (2.0, 2.0), (2.4, 3.0)):
                    nine.append(e)
                ang[k] = v["angle_deg"]
            if "_force_" in f and k in force:
                fe.append(abs(v["force_n"] - float(force[k]["force_n"])))
    m = lambda x: sum(x) / len(x)
    ratios = " / ".join(f"{ang[(13, t, 3.0)] / ang[(11, t, 3.0)]:.2f}" for t in (1.6, 2.0, 2.4))
    print(f"{os.path.basename(sw)}: tip BE {m(be):.2f} mm ({len(be)} fitted), the nine {m(nine):.2f} mm, "
          f"|F error| {m(fe):.3f} N, N13/N11 at 3 bar (T 1.6 / 2.0 / 2.4) {ratios}")
