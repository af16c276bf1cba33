#!/usr/bin/env python3
"""Rows of the warm-start benchmark for an identification campaign, from its committed ramps.

Each `surrogate identify` sweep writes one ramp file per design and rig
(`fe_ramps/sweep_NN/*_sensitivities.json`), holding the Newton iterations and the warm-start
flag of every output level and the ramp's cost (ramp and sensitivity seconds,
factorisations). This reads one or more sweep folders and prints, per folder, the JSON row:
ramps, output levels, mean Newton iterations per pressure level (the self-weight level apart),
levels started warm, factorisations, ramp and sensitivity seconds (one core each; the sweep
runs two ramps at a time).

    python3 fe_reference/warm_start/identification_rows.py DIR [DIR ...]

Standard library only.
"""
import glob
import json
import os
import sys


def row(folder):
    files = sorted(glob.glob(os.path.join(folder, "*_sensitivities.json")))
    its, warm, levels, fact, ramp_s, sens_s = [], 0, 0, 0, 0.0, 0.0
    for f in files:
        with open(f) as h:
            r = json.load(h)
        for s in r["steps"][1:]:  # the pressure levels; [0] is the self-weight state
            its.append(s["newton_iterations"])
            warm += bool(s.get("warm_start", False))
            levels += 1
        cost = r["sensitivities"]["cost"]
        fact += cost["factorizations"]
        ramp_s += cost["ramp_s"]
        sens_s += cost["sensitivity_s"]
    return {
        "folder": folder,
        "ramps": len(files),
        "pressure_levels": levels,
        "levels_started_warm": warm,
        "mean_newton_iterations_per_level": round(sum(its) / max(len(its), 1), 2),
        "factorizations": fact,
        "ramp_s": round(ramp_s, 1),
        "sensitivity_s": round(sens_s, 1),
    }


if __name__ == "__main__":
    print(json.dumps([row(d) for d in sys.argv[1:]], indent=2))
