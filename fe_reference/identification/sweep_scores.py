"""Scores of a cached identification sweep against the recordings, read straight from its
ramps: shared by `wall_law/sweeps.py` and `mesh_corrected/sweeps.py`.

`score(sweep_dir, correction)` returns, for the sweep's 18 ramps (bending and force at the
9 designs), the tip BE over the configurations fitted (N = 11, T = 1.6 left out, as the data
checks flag its rows), over all 27 and over the study's nine, the mean |force error| and the
N = 13 / N = 11 angle ratio at 3 bar for each T (recorded: 0.99, 0.89, 0.82), or None while the
sweep is incomplete. `correction` maps (N, T, P) to additive corrections of uz, uy, angle and
force (the mesh correction), or is None.
"""
import csv
import glob
import json
import math
import os

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
# the study's nine configurations: T and P move together
NINE = ((1.6, 1.0), (2.0, 2.0), (2.4, 3.0))


def key(r):
    return int(r["n_bellows"]), float(r["wall_thickness_mm"]), float(r["pressure_bar"])


def table(path):
    """A CSV of configurations keyed by (N, T, P)."""
    return {key(r): r for r in csv.DictReader(open(path))}


BEND = table(os.path.join(ROOT, "training_data/bending_experiments.csv"))
FORCE = table(os.path.join(ROOT, "training_data/blocked_force_experiments.csv"))


def steps(path):
    d = json.load(open(path))
    s = d.get("sensitivities")
    return s["steps"] if isinstance(s, dict) else d["steps"]


def design(path):
    name = os.path.basename(path).split("_")
    return int(name[0][1:]), float(name[1][1:])


def mean(x):
    return sum(x) / len(x)


def score(sweep, correction=None):
    files = glob.glob(os.path.join(sweep, "*_sensitivities.json"))
    if len(files) < 18:
        return {"ramps": len(files)}
    zero = {"uz": 0.0, "uy": 0.0, "angle": 0.0, "force": 0.0}
    be, all27, nine, fe, ang = [], [], [], [], {}
    for f in files:
        n, t = design(f)
        for st in steps(f):
            v = st.get("values", st)
            k = (n, t, st["pressure_bar"])
            if "_bending_" in f and k in BEND:
                r, c = BEND[k], correction[k] if correction is not None else zero
                e = math.hypot(v["tip_uz_mm"] + c["uz"] - float(r["tip_uz_mm"]),
                               v["tip_uy_mm"] + c["uy"] - float(r["tip_uy_mm"]))
                all27.append(e)
                if not (n == 11 and t == 1.6):
                    be.append(e)
                if (t, k[2]) in NINE:
                    nine.append(e)
                ang[k] = v["angle_deg"] + c["angle"]
            if "_force_" in f and k in FORCE:
                c = correction[k] if correction is not None else zero
                fe.append(abs(v["force_n"] + c["force"] - float(FORCE[k]["force_n"])))
    ratios = " / ".join(f"{ang[(13, t, 3.0)] / ang[(11, t, 3.0)]:.2f}" for t in (1.6, 2.0, 2.4))
    return {"fitted": mean(be), "n_fitted": len(be), "all27": mean(all27), "nine": mean(nine),
            "force": mean(fe), "ratios": ratios}


def sweeps(here):
    """The sweep folders under `here/fe_ramps`, in order."""
    return sorted(glob.glob(os.path.join(here, "fe_ramps", "sweep_*")))
