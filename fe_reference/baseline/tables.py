"""Markdown tables of the literature baselines from fe_reference/baseline/*_standard.csv.

Usage: python3 fe_reference/baseline/tables.py [DIR]   (DIR defaults to this file's folder)

Per material: BE over all 27 configurations and over the reference study's nine (T and P
together: T 1.6 at 1 bar, 2.0 at 2 bar, 2.4 at 3 bar, for each N, as `surrogate validate`
prints), by pressure and by wall thickness; the
mean angle error; the force error by pressure (signed: positive = over-prediction). Then one
row per configuration with every material side by side.
"""
import csv
import os
import statistics
import sys

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
MATERIALS = ["ogden_002", "ogden_005", "mooney_rivlin_5"]


def load(m):
    path = os.path.join(here, f"{m}_standard.csv")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in r:
            if k != "error":
                r[k] = float(r[k]) if r[k] not in ("", "NaN") else float("nan")
    return rows


def finite(v):
    return [x for x in v if x == x]


def mean(v):
    v = finite(v)
    return sum(v) / len(v) if v else float("nan")


def median(v):
    v = finite(v)
    return statistics.median(v) if v else float("nan")


def paper_nine(rows):
    ns = sorted({r["n_bellows"] for r in rows})
    ts = sorted({r["wall_thickness_mm"] for r in rows})
    ps = sorted({r["pressure_bar"] for r in rows})
    return [
        r
        for r in rows
        if ps.index(r["pressure_bar"]) == ts.index(r["wall_thickness_mm"])
    ]


tables = {m: load(m) for m in MATERIALS}
print("| material | configs | mean BE, all 27 (mm) | median BE (mm) | mean BE, the study's nine (mm) | median BE, nine (mm) "
      "| mean abs angle error (deg) | mean F error (N) | mean F error at 3 bar (N) | mean abs F error (N) |")
print("|---|---|---|---|---|---|---|---|---|---|")
for m, rows in tables.items():
    if rows is None:
        print(f"| {m} | not run | | | | | | | | |")
        continue
    sub = paper_nine(rows)
    be = [r["be_mm"] for r in rows]
    fe = [r["force_error_n"] for r in rows]
    f3 = [r["force_error_n"] for r in rows if r["pressure_bar"] == 3.0]
    ang = [abs(r["angle_sim_deg"] - r["angle_exp_deg"]) for r in rows]
    print(
        f"| {m} | {len(finite(be))}/{len(rows)} | {mean(be):.2f} | {median(be):.2f} "
        f"| {mean([r['be_mm'] for r in sub]):.2f} | {median([r['be_mm'] for r in sub]):.2f} "
        f"| {mean(ang):.2f} | {mean(fe):+.3f} | {mean(f3):+.3f} | {mean([abs(x) for x in finite(fe)]):.3f} |"
    )

print()
print("Mean BE (mm) by pressure and by wall thickness:")
print()
print("| material | 1 bar | 2 bar | 3 bar | T = 1.6 | T = 2.0 | T = 2.4 |")
print("|---|---|---|---|---|---|---|")
for m, rows in tables.items():
    if rows is None:
        continue
    byp = [mean([r["be_mm"] for r in rows if r["pressure_bar"] == p]) for p in (1.0, 2.0, 3.0)]
    byt = [mean([r["be_mm"] for r in rows if r["wall_thickness_mm"] == t]) for t in (1.6, 2.0, 2.4)]
    print(f"| {m} | " + " | ".join(f"{v:.2f}" for v in byp + byt) + " |")

print()
print("Mean force error F_sim - F_exp (N) by pressure:")
print()
print("| material | 1 bar | 2 bar | 3 bar |")
print("|---|---|---|---|")
for m, rows in tables.items():
    if rows is None:
        continue
    byp = [mean([r["force_error_n"] for r in rows if r["pressure_bar"] == p]) for p in (1.0, 2.0, 3.0)]
    print(f"| {m} | " + " | ".join(f"{v:+.3f}" for v in byp) + " |")

print()
print("Per configuration (BE in mm; force measured / simulated in N; * = one of the study's nine):")
print()
present = [m for m in MATERIALS if tables[m] is not None]
print("| N | T | P | F measured | " + " | ".join(f"BE {m} | F {m}" for m in present) + " |")
print("|---|---|---|---|" + "---|---|" * len(present))
base = tables[present[0]] if present else []
inl9 = {(r["n_bellows"], r["wall_thickness_mm"], r["pressure_bar"]) for r in paper_nine(base)}
for r in base:
    key = (r["n_bellows"], r["wall_thickness_mm"], r["pressure_bar"])
    cells = []
    for m in present:
        o = next(x for x in tables[m] if (x["n_bellows"], x["wall_thickness_mm"], x["pressure_bar"]) == key)
        cells += [f"{o['be_mm']:.2f}", f"{o['force_sim_n']:.3f}"]
    star = "*" if key in inl9 else ""
    print(f"| {int(key[0])}{star} | {key[1]} | {key[2]:.0f} | {r['force_exp_n']:.3f} | " + " | ".join(cells) + " |")
