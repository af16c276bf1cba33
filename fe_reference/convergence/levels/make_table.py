"""Which resolution matters: tip displacement and blocked force of intermediate meshes against
the extrapolated values of ../table.md (N = 11, T = 2, Ogden 002, gravity)."""
import json
import math
import os

here = os.path.dirname(os.path.abspath(__file__))
conv = os.path.dirname(here)
EXT_U = {1: 23.998, 2: 34.490, 3: 43.316}  # ../table.md, tip_u_mm, extrapolated
EXT_F = {1: 0.083, 2: 0.998, 3: 2.169}  # ../table.md, force_n, extrapolated
meshes = [
    ("coarse: h 6, 1 through a wall", "../n11_t2.0_bending_coarse.json", "../n11_t2.0_force_coarse.json"),
    ("h 3, 1 through a wall", "bending_h3_w1.json", "force_h3_w1.json"),
    ("h 6, 2 through a wall", "bending_h6_w2.json", "force_h6_w2.json"),
    ("h 6, 3 through a wall", "bending_h6_w3.json", None),
    ("standard: h 3, 2 through a wall", "../n11_t2.0_bending_standard.json", "../n11_t2.0_force_standard.json"),
]
lines = ["| mesh | dofs | tip \\|U\\| error 1 / 2 / 3 bar | force error 1 / 2 / 3 bar |", "|---|---|---|---|"]
for name, b, f in meshes:
    rb = json.load(open(os.path.join(here, b)))
    eu = []
    for s in rb["steps"]:
        p = round(s["pressure_bar"])
        if p in EXT_U:
            u = math.hypot(s["tip_uz_mm"], s["tip_uy_mm"])
            eu.append(f"{100 * (u - EXT_U[p]) / EXT_U[p]:+.1f} %")
    ef = ["–"]
    if f:
        rf = json.load(open(os.path.join(here, f)))
        ef = []
        for s in rf["steps"]:
            p = round(s["pressure_bar"])
            if p in EXT_F:
                ef.append(f"{100 * (s['force_n'] - EXT_F[p]) / EXT_F[p]:+.0f} %")
    lines.append(f"| {name} | {rb['dofs']} | {' / '.join(eu)} | {' / '.join(ef)} |")
print("\n".join(lines))
