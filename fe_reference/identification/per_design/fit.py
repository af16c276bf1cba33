#!/usr/bin/env python3
"""Per-design print deviations: how far would each printed design's walls have to be off
nominal for the identified model to meet its recordings?

Reads the validate CSV (recorded and FE tips and forces at the identified point) and its
sensitivities (FE derivatives of every output with respect to `wall_bias`, every wall, and
`wall_bias_bellows`, the walls facing the gaps). For each of the nine designs, it fits one wall
offset to that design's 3 pressures (tip Uz, Uy and blocked force, weighted by the
identification's noise floor: 2 mm on a tip coordinate, 0.15 N), linearised about the
identified point, and prints the offset, its standard error and the tip BE before and after.

    python3 fit.py sweep7_coarse.csv sweep7_coarse_sensitivities.json [wall_bias|wall_bias_bellows]
"""
import csv
import json
import math
import sys

TIP_SIGMA_MM = 2.0
FORCE_SIGMA_N = 0.15


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    sens = json.load(open(sys.argv[2]))
    effect = sys.argv[3] if len(sys.argv) > 3 else "wall_bias"
    deriv = {}
    for d in sens["designs"]:
        s = d["sensitivities"]
        k = [p["parameter"] for p in s["parameters"]].index(effect)
        for st in s["steps"]:
            key = (d["n_bellows"], round(d["wall_thickness_mm"], 3), round(st["pressure_bar"], 3), d["mode"])
            deriv[key] = (st["values"], st["derivatives"][k])
    print(f"per-design {effect}, linearised at the identified point (mm)")
    print("| N | T | offset (mm) | std. error | mean tip BE before | after (linear) | |F| error before | after |")
    print("|---|---|---|---|---|---|---|---|")
    designs = sorted({(int(r["n_bellows"]), float(r["wall_thickness_mm"])) for r in rows})
    tot_before = tot_after = 0.0
    out = {}
    for n, t in designs:
        mine = [r for r in rows if int(r["n_bellows"]) == n and float(r["wall_thickness_mm"]) == t]
        res, jac = [], []  # residuals (FE - recorded) in sigma units and their derivatives
        for r in mine:
            p = float(r["pressure_bar"])
            _, db = deriv[(n, round(t, 3), round(p, 3), "bending")]
            _, df = deriv[(n, round(t, 3), round(p, 3), "force")]
            for fe, ex, dd, sg in (
                (r["uz_sim_mm"], r["uz_exp_mm"], db["tip_uz_mm"], TIP_SIGMA_MM),
                (r["uy_sim_mm"], r["uy_exp_mm"], db["tip_uy_mm"], TIP_SIGMA_MM),
                (r["force_sim_n"], r["force_exp_n"], df["force_n"], FORCE_SIGMA_N),
            ):
                res.append((float(fe) - float(ex)) / sg)
                jac.append(dd / sg)
        jj = sum(j * j for j in jac)
        delta = -sum(j * r for j, r in zip(jac, res)) / jj
        se = 1.0 / math.sqrt(jj)
        be_b = be_a = f_b = f_a = 0.0
        for i, r in enumerate(mine):
            uz, uy, f = res[3 * i: 3 * i + 3]
            juz, juy, jf = jac[3 * i: 3 * i + 3]
            be_b += TIP_SIGMA_MM * math.hypot(uz, uy) / 3
            be_a += TIP_SIGMA_MM * math.hypot(uz + juz * delta, uy + juy * delta) / 3
            f_b += FORCE_SIGMA_N * abs(f) / 3
            f_a += FORCE_SIGMA_N * abs(f + jf * delta) / 3
        tot_before += be_b / len(designs)
        tot_after += be_a / len(designs)
        out[f"{n},{t}"] = delta
        print(f"| {n} | {t} | {delta:+.3f} | {se:.3f} | {be_b:.2f} | {be_a:.2f} | {f_b:.3f} | {f_a:.3f} |")
    print(f"mean tip BE over the 27: {tot_before:.2f} mm before, {tot_after:.2f} mm after (linear)")
    json.dump(out, open(f"offsets_{effect}.json", "w"), indent=1)


if __name__ == "__main__":
    main()
