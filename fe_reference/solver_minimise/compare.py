#!/usr/bin/env python3
"""Tip and blocked force of the minimisation solver against the residual Newton (the reference).

Reads the minimisation ramps `standard/n{N}_t{T}_{mode}_minimise.json` (written by
`surrogate simulate --solver minimise`, commands in README.md) and the residual Newton's ramps of
the same cases from `../baseline/ogden_002_standard_ramps/` (computed with today's defaults),
likewise `coarse/*_minimise.json` against `coarse/*_newton.json`, and writes `comparison.md`.
A case whose minimisation ramp is missing is listed as such. Run from anywhere:

    python3 fe_reference/solver_minimise/compare.py
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
BASE = os.path.join(HERE, "..", "baseline", "ogden_002_standard_ramps")
CASES = [(11, "2", "bending"), (11, "2", "force"), (9, "1.6", "bending"), (9, "1.6", "force")]


def steps(path):
    with open(path) as f:
        d = json.load(f)
    return d["steps"], d.get("wall_time_s")


def table(rows_in, mesh):
    out = [
        f"### {mesh} mesh",
        "",
        "| N | T | mode | P (bar) | tip Uz, Uy Newton (mm) | tip Uz, Uy minimise (mm) | tip Δ (mm) | % of tip | force Newton (N) | force minimise (N) | force Δ % | iterations Newton / minimise |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    worst_tip, worst_force = 0.0, 0.0
    for (n, t, mode), ref, new in rows_in:
        if new is None:
            out.append(f"| {n} | {t} | {mode} | — | minimisation ramp missing | | | | | | | |")
            continue
        for a, b in zip(ref, new):
            p = round(a["pressure_bar"], 3)
            if p == 0:
                continue
            tip = math.hypot(a["tip_uz_mm"], a["tip_uy_mm"])
            d = math.hypot(a["tip_uz_mm"] - b["tip_uz_mm"], a["tip_uy_mm"] - b["tip_uy_mm"])
            rel = 100 * d / tip
            worst_tip = max(worst_tip, rel)
            fa, fb = a.get("force_n"), b.get("force_n")
            if fa is not None and fb is not None:
                frel = 100 * abs(fa - fb) / max(abs(fa), 1e-3)
                worst_force = max(worst_force, frel)
                fcols = f"{fa:.4f} | {fb:.4f} | {frel:.3f}"
            else:
                fcols = "— | — | —"
            out.append(
                f"| {n} | {t} | {mode} | {p:g} | {a['tip_uz_mm']:.3f}, {a['tip_uy_mm']:.3f} | "
                f"{b['tip_uz_mm']:.3f}, {b['tip_uy_mm']:.3f} | {d:.4f} | {rel:.3f} | {fcols} | "
                f"{a['newton_iterations']} / {b['newton_iterations']} |"
            )
    out += ["", f"Largest tip difference {worst_tip:.3f} % of the tip displacement, largest force difference {worst_force:.3f} % (asked: 0.2 %).", ""]
    return out


def main():
    std, coarse = [], []
    for n, t, mode in CASES:
        ref = os.path.join(BASE, f"n{n}_t{t}_{mode}.json")
        new = os.path.join(HERE, "standard", f"n{n}_t{t}_{mode}_minimise.json")
        std.append(((n, t, mode), steps(ref)[0], steps(new)[0] if os.path.exists(new) else None))
        cref = os.path.join(HERE, "coarse", f"n{n}_t{t}_{mode}_newton.json")
        cnew = os.path.join(HERE, "coarse", f"n{n}_t{t}_{mode}_minimise.json")
        if os.path.exists(cref) and os.path.exists(cnew):
            coarse.append(((n, t, mode), steps(cref)[0], steps(cnew)[0]))
    lines = [
        "# Minimisation solver against the residual Newton: tip and blocked force",
        "",
        "Written by `python3 fe_reference/solver_minimise/compare.py` from the ramps in this",
        "folder and `../baseline/ogden_002_standard_ramps/` (commands in README.md). Ogden 002,",
        "κ = 1000 μ0, gravity, contact; Newton: augmented-Lagrangian penalty (ε = 20 MPa/mm,",
        "δ = 0.05 mm, up to 6 Uzawa updates); minimise: log barrier d̂ = 1e-3 mm, p̂ = 0.1 MPa.",
        "",
    ]
    lines += table(std, "standard")
    if coarse:
        lines += table(coarse, "coarse")
    with open(os.path.join(HERE, "comparison.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
