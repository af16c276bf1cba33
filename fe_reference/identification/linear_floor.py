#!/usr/bin/env python3
"""How far can the model's parameters move the fit, linearised at one point?

Reads one FE sweep with sensitivities (one bending and one force ramp per recorded design,
as written by `surrogate validate --sensitivities all` or `surrogate identify`) and the shipped
experiments, weighs the residuals as `surrogate identify` does (tip sigma = hypot(chord x
angle scatter, 2 mm), force sigma = hypot(recorded scatter, 0.15 N)), and solves the
unbounded linear least-squares problem r + J d = min for a set of parameters, then for that
set plus each other parameter in turn, and for every parameter at once.

Unbounded and linear: an optimistic measure of what the parameters can do near this point
(the steps it asks for may be far outside any physical range). Standard library only.

    python3 fe_reference/identification/linear_floor.py \
        fe_reference/sensitivities/ogden002_coarse/baseline_ramps
"""
import csv
import json
import math
import os
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
TIP_FLOOR_MM, FORCE_FLOOR_N, FREE_LENGTH_MM = 2.0, 0.15, 92.0
BASE = ["mu1", "alpha1", "mu2", "alpha2", "gap_bias", "wall_bias_skin", "wall_bias_side", "base_bias",
        "plate_offset"]


def read(name):
    with open(os.path.join(ROOT, "training_data", name)) as f:
        return {(int(r["n_bellows"]), float(r["wall_thickness_mm"]), float(r["pressure_bar"])): r
                for r in csv.DictReader(f)}


def lstsq(a, b):
    """min |a x - b| by the normal equations with a tiny ridge (Gauss-Jordan)."""
    k = len(a[0])
    m = [[sum(a[i][p] * a[i][q] for i in range(len(a))) for q in range(k)] for p in range(k)]
    scale = max(m[p][p] for p in range(k)) or 1.0
    for p in range(k):
        m[p][p] += 1e-12 * scale
    v = [sum(a[i][p] * b[i] for i in range(len(a))) for p in range(k)]
    for c in range(k):
        piv = max(range(c, k), key=lambda i: abs(m[i][c]))
        m[c], m[piv], v[c], v[piv] = m[piv], m[c], v[piv], v[c]
        for i in range(k):
            if i != c and m[c][c] != 0.0:
                f = m[i][c] / m[c][c]
                m[i] = [x - f * y for x, y in zip(m[i], m[c])]
                v[i] -= f * v[c]
    return [v[i] / m[i][i] for i in range(k)]


def main(d):
    bend, force = read("bending_experiments.csv"), read("blocked_force_experiments.csv")
    r, jac, what, names = [], [], [], None
    for (n, t, p), b in sorted(bend.items()):
        for mode in ("bending", "force"):
            with open(os.path.join(d, f"n{n}_t{t:g}_{mode}_sensitivities.json")) as f:
                s = json.load(f)["sensitivities"]
            names = [q["parameter"] for q in s["parameters"]]
            st = next(x for x in s["steps"] if abs(x["pressure_bar"] - p) < 1e-9)
            v, der = st["values"], st["derivatives"]
            if mode == "bending":
                chord = math.hypot(FREE_LENGTH_MM - float(b["tip_uz_mm"]), float(b["tip_uy_mm"]))
                sig = math.hypot(chord * math.radians(float(b["angle_std_deg"])), TIP_FLOOR_MM)
                for o in ("tip_uz_mm", "tip_uy_mm"):
                    r.append((v[o] - float(b[o])) / sig)
                    jac.append([x[o] / sig for x in der])
                    what.append(("tip", (n, t, p), sig))
            else:
                fr = force[(n, t, p)]
                sig = math.hypot(float(fr["force_std_n"]), FORCE_FLOOR_N)
                r.append((v["force_n"] - float(fr["force_n"])) / sig)
                jac.append([(x["force_n"] or 0.0) / sig for x in der])
                what.append(("force", (n, t, p), sig))
    idx = {n: i for i, n in enumerate(names)}

    def fit(ps):
        a = [[row[idx[q]] for q in ps] for row in jac]
        x = lstsq(a, [-v for v in r])
        return x, [ri + sum(ai * xi for ai, xi in zip(row, x)) for ri, row in zip(r, a)]

    def summary(res):
        tips, forces = {}, []
        for ri, (kind, cfg, sig) in zip(res, what):
            if kind == "tip":
                tips.setdefault(cfg, []).append(ri * sig)
            else:
                forces.append(abs(ri * sig))
        be = {c: math.hypot(*v) for c, v in tips.items()}
        return sum(x * x for x in res), sum(be.values()) / len(be), sum(forces) / len(forces), be

    c, be, fe, _ = summary(r)
    print(f"at the point: chi2 {c:.1f}, mean tip BE {be:.2f} mm, mean |F error| {fe:.3f} N")
    base = [q for q in BASE if q in idx]
    x, res = fit(base)
    c, be, fe, _ = summary(res)
    print(f"{'+'.join(base)}: chi2 {c:.1f}, BE {be:.2f} mm, |F| {fe:.3f} N")
    print("  steps: " + ", ".join(f"{q} {v:+.3g}" for q, v in zip(base, x)))
    print("one more parameter:")
    for q in names:
        if q not in base:
            x, res = fit(base + [q])
            c, be, fe, _ = summary(res)
            print(f"  {q:<24} chi2 {c:7.1f}, BE {be:.2f} mm, |F| {fe:.3f} N (its step {x[-1]:+.3g})")
    x, res = fit(names)
    c, be, fe, bes = summary(res)
    print(f"all {len(names)} parameters: chi2 {c:.1f}, BE {be:.2f} mm, |F| {fe:.3f} N")
    print("  tip BE left per configuration (mm), T = 1.6 / 2.0 / 2.4, each at 1 / 2 / 3 bar:")
    for n in sorted({k[0] for k in bes}):
        cells = [f"{bes[(n, t, p)]:4.1f}" for t in (1.6, 2.0, 2.4) for p in (1.0, 2.0, 3.0)]
        print(f"  N = {n:2d}: " + " ".join(cells))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else
         os.path.join(ROOT, "fe_reference", "sensitivities", "ogden002_coarse", "baseline_ramps"))
