#!/usr/bin/env python3
"""The FE at each design's own wall offset (verify/, from verify.sh) against the recordings:
per-design tip BE and force error, and the means over the 27 configurations and the study's
nine (T and P together), next to the identified point's (sweep7_coarse.csv).

    python3 verified.py
"""
import csv
import json
import math
import os

here = os.path.dirname(os.path.abspath(__file__))
rows = list(csv.DictReader(open(os.path.join(here, "sweep7_coarse.csv"))))
offsets = json.load(open(os.path.join(here, "offsets_wall_bias.json")))
NINE = {(1.6, 1.0), (2.0, 2.0), (2.4, 3.0)}
print("| N | T | wall offset (mm) | tip BE at the identified point (1 / 2 / 3 bar) | with the offset (FE) | F error before (N) | after |")
print("|---|---|---|---|---|---|---|")
be0, be1, f0, f1, nine0, nine1 = [], [], [], [], [], []
designs = sorted({(int(r["n_bellows"]), float(r["wall_thickness_mm"])) for r in rows})
for n, t in designs:
    b = json.load(open(os.path.join(here, f"verify/n{n}_t{t}_bending.json")))["steps"]
    f = json.load(open(os.path.join(here, f"verify/n{n}_t{t}_force.json")))["steps"]
    mine = [r for r in rows if int(r["n_bellows"]) == n and float(r["wall_thickness_mm"]) == t]
    cells_b, cells_a, fe_b, fe_a = [], [], [], []
    for r in mine:
        p = float(r["pressure_bar"])
        sb = next(s for s in b if abs(s["pressure_bar"] - p) < 1e-9)
        sf = next(s for s in f if abs(s["pressure_bar"] - p) < 1e-9)
        ez, ey = float(r["uz_exp_mm"]), float(r["uy_exp_mm"])
        before = float(r["be_mm"])
        after = math.hypot(sb["tip_uz_mm"] - ez, sb["tip_uy_mm"] - ey)
        fb = float(r["force_sim_n"]) - float(r["force_exp_n"])
        fa = sf["force_n"] - float(r["force_exp_n"])
        cells_b.append(before)
        cells_a.append(after)
        fe_b.append(abs(fb))
        fe_a.append(abs(fa))
        be0.append(before)
        be1.append(after)
        f0.append(abs(fb))
        f1.append(abs(fa))
        if (t, p) in NINE:
            nine0.append(before)
            nine1.append(after)
    fmt = lambda v: " / ".join(f"{x:.1f}" for x in v)
    print(f"| {n} | {t} | {offsets[f'{n},{t}']:+.3f} | {fmt(cells_b)} | {fmt(cells_a)} | {sum(fe_b)/3:.3f} | {sum(fe_a)/3:.3f} |")
m = lambda v: sum(v) / len(v)
print(f"\nmean tip BE, 27 configurations: {m(be0):.2f} mm at the identified point, {m(be1):.2f} mm with the per-design offsets")
print(f"mean tip BE, the study's nine: {m(nine0):.2f} mm, {m(nine1):.2f} mm")
print(f"mean |force error|: {m(f0):.3f} N, {m(f1):.3f} N")
