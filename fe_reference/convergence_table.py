"""Mesh-convergence table (GCI, Celik et al. 2008) from fe_reference/convergence/*.json."""
import json
import math
import os
import sys

out = sys.argv[1]
LEVELS = ["coarse", "standard", "fine"]


def richardson(v, h):
    """Observed order p and extrapolated value (Celik et al. 2008), or None.

    v, h: values and representative sizes on [coarse, standard, fine]. In Celik's notation
    1 = fine, 2 = standard, 3 = coarse, r21 = h2/h1, r32 = h3/h2, e21 = v2 - v1, e32 = v3 - v2.
    """
    e21, e32 = v[1] - v[2], v[0] - v[1]
    if e21 == 0 or e32 == 0 or e32 / e21 <= 0:
        return None  # oscillatory or flat: no extrapolation
    r21, r32 = h[1] / h[2], h[0] / h[1]

    def f(p):  # p ln r21 - |ln|e32/e21| + q(p)| = 0
        q = math.log((r21**p - 1) / (r32**p - 1))
        return p * math.log(r21) - abs(math.log(abs(e32 / e21)) + q)

    lo, hi = 0.05, 12.0
    if f(lo) * f(hi) > 0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(lo) * f(mid) <= 0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    ext = (r21**p * v[2] - v[1]) / (r21**p - 1)
    return p, ext


def value(step, q):
    """A step's quantity; tip_u_mm is the tip displacement magnitude |(Uz, Uy)|."""
    if q == "tip_u_mm":
        return math.hypot(step["tip_uz_mm"], step["tip_uy_mm"])
    return step.get(q)


# the `simulate` flags of each table's runs (as in convergence.sh)
FLAGS = {
    "bending": "--mode bending --no-contact",
    "force": "--mode force",
    "bending_contact": "--mode bending",
}


def missing(mode, runs, title):
    """The section of a table whose runs are not all there: each level, its file, whether it is
    committed, and the command that makes it."""
    rows = [
        "| level | file | committed | command that makes it |",
        "|---|---|---|---|",
    ]
    for lv in LEVELS:
        f = f"fe_reference/convergence/n11_t2.0_{mode}_{lv}.json"
        cmd = (
            f"`RAYON_NUM_THREADS=1 surrogate simulate --n 11 --t 2.0 --pressures 0,1,2,3 "
            f"--material ogden_002 --mesh {lv} {FLAGS[mode]} --out {f}`"
        )
        rows.append(f"| {lv} | `{f}` | {'yes' if lv in runs else '**missing**'} | {cmd} |")
    return (
        f"## {title}\n\n"
        f"**Incomplete: {len(LEVELS) - len(runs)} of {len(LEVELS)} runs missing**, so this "
        "section has no convergence table yet. `bash fe_reference/convergence.sh` runs only "
        "the missing ones (it keeps every committed JSON) and rewrites this table.\n\n"
        + "\n".join(rows)
        + "\n"
    )


def table(mode, quantities, title):
    runs = {}
    for lv in LEVELS:
        f = os.path.join(out, f"n11_t2.0_{mode}_{lv}.json")
        if os.path.exists(f):
            runs[lv] = json.load(open(f))
    if len(runs) < 3:
        return missing(mode, runs, title)
    # representative element size from the number of unknowns
    h = [runs[lv]["dofs"] ** (-1.0 / 3.0) for lv in LEVELS]
    meta = "\n".join(
        f"- {lv}: {runs[lv]['nodes']} nodes, {runs[lv]['elements']} elements, "
        f"{runs[lv]['dofs']} dofs, {runs[lv]['wall_time_s']:.0f} s (one thread)"
        for lv in LEVELS
    )
    lines = [
        "| P (bar) | quantity | coarse | standard | fine | observed order p | extrapolated | coarse vs ext. | standard vs ext. | fine vs ext. |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for i, step in enumerate(runs["coarse"]["steps"]):
        pbar = step["pressure_bar"]
        if pbar == 0:
            continue
        for q in quantities:
            v = [value(runs[lv]["steps"][i], q) for lv in LEVELS]
            if any(x is None for x in v):
                continue
            rr = richardson(v, h)
            if rr is None:
                lines.append(
                    f"| {pbar:.0f} | {q} | {v[0]:.3f} | {v[1]:.3f} | {v[2]:.3f} | oscillatory | – | – | – | – |"
                )
                continue
            p, ext = rr
            rel = [f"{100 * abs(x - ext) / abs(ext):.2f} %" for x in v]
            lines.append(
                f"| {pbar:.0f} | {q} | {v[0]:.3f} | {v[1]:.3f} | {v[2]:.3f} | {p:.2f} | {ext:.3f} | {rel[0]} | {rel[1]} | {rel[2]} |"
            )
    return f"## {title}\n\n{meta}\n\n" + "\n".join(lines) + "\n"


body = (
    "# Mesh convergence, N=11, T=2.0, Ogden 002, gravity on\n\n"
    "Regenerate: `bash fe_reference/convergence.sh` (table only: "
    "`python3 fe_reference/convergence_table.py fe_reference/convergence`).\n\n"
    "The three levels refine everywhere at once: target element size h = 6, 3, 2 mm and 1, 2, 3 "
    "quadratic elements through a wall (coarse, standard, fine); segments shorter than h, such as "
    "the 1 mm gaps, keep one element. The representative size is dofs^(-1/3); the observed order "
    "p and the extrapolated value follow the GCI procedure of Celik et al. (2008).\n\n"
    + table("bending", ["tip_u_mm", "tip_uz_mm", "tip_uy_mm", "angle_deg"], "Bending, no contact")
    + "\n"
    + table("force", ["force_n"], "Blocked force, contact on")
    + "\n"
    + table(
        "bending_contact",
        ["tip_u_mm", "tip_uz_mm", "tip_uy_mm", "angle_deg"],
        "Bending, contact on (as in the snapshots and the baseline)",
    )
    + """
## Reading

- `standard` is the production level: its tip displacement |(Uz, Uy)| is within 1 % of the
  extrapolated value at 1, 2 and 3 bar (issue 2, verification 7), its blocked force within
  about 1 % at 3 bar (issue 3, verification 5; larger relative errors at 1 bar, where the force
  is small). Uz alone, a small component, is within 2 %.
- The observed orders (3.5 to 6) exceed the order 3 expected of quadratic elements: `coarse`
  is not yet in the asymptotic range, so the extrapolated values carry an uncertainty of the
  order of the standard-to-fine difference.
- Bending with contact on, the configuration of the snapshots and the baseline: `standard`
  is within 0.2 % (tip |(Uz, Uy)|, angle) of `fine` at 1 bar and within 0.5 % of the
  extrapolated value at 2 and 3 bar, where the bellows touch. At 1 bar the three levels do not
  converge monotonically (coarse is 6 % softer, standard 0.3 % stiffer than fine), so no
  order or extrapolation is given there; the standard-to-fine difference is the estimate.
- `coarse` (one element through a wall) is 5 to 6 % too stiff in bending without contact,
  and with contact on it bends 7 to 12 % too far once the bellows touch (its one-element gaps
  close early); its blocked force is far off at low pressure. It is for tests, quick looks
  and the identification's Jacobians. Results that are compared with the experiments use
  `standard`.
"""
)
open(os.path.join(out, "table.md"), "w").write(body)
print(body)
