#!/usr/bin/env python3
"""Where the Newton iterations of a ramp go, from its trace (SURROGATE_TRACE=1 on stderr).

Each Newton solve of the trace is one of: a failed increment (cut back, or retried without
the predictor), an augmented-Lagrangian re-solve (after an Uzawa update of the contact
shifts), or a converged load increment; a converged increment's iterations are split at the
iteration from which the normalised residual stays below 1e-2 (the quadratic phase) into the
iterations before it and those in it.

    python3 fe_reference/solver_minimise/iterations.py LOG newton|minimise
"""
import re
import sys


def analyse(path, tag):
    """(converged increments, iterations by kind) for the whole trace and per output level."""
    solves, cur, after_update, level, names = [], None, False, 0, {}
    for line in open(path):
        if "augmented update" in line:
            after_update = True
            continue
        if line.startswith(("coarse:", "standard:", "simulate:")) or "predictor" in line:
            after_update = False
        m = re.match(r"(coarse|standard|simulate): step \d+/\d+: (\S+ bar)", line)
        if m:
            names[level] = m.group(2)
            if cur:
                solves.append(cur)
                cur = None
            level += 1
            continue
        m = re.match(r"\s+" + tag + r"\s+(\d+).*\|r\|/f = (\S+)", line)
        if m:
            it, r = int(m.group(1)), float(m.group(2))
            if it == 0:
                if cur:
                    solves.append(cur)
                cur = {"r": [], "update": after_update, "level": level}
                after_update = False
            cur["r"].append(r)
    if cur:
        solves.append(cur)
    kinds = ["failed increments", "augmented re-solves",
             "increments before the quadratic phase", "increments in the quadratic phase"]
    levels = {}
    for s in solves:
        n_inc, cat = levels.setdefault(s["level"], [0, dict.fromkeys(kinds, 0)])
        x = s["r"]
        its = len(x) - 1
        if x[-1] > 1e-7:
            cat["failed increments"] += its
        elif s["update"]:
            cat["augmented re-solves"] += its
        else:
            levels[s["level"]][0] += 1
            k = next((i for i, v in enumerate(x) if all(w < 1e-2 for w in x[i:])), its)
            cat["increments before the quadratic phase"] += k
            cat["increments in the quadratic phase"] += its - k
    total = dict.fromkeys(kinds, 0)
    for _, cat in levels.values():
        for k in kinds:
            total[k] += cat[k]
    levels = {names.get(lv, f"level {lv + 1}"): v for lv, v in sorted(levels.items())}
    return sum(v[0] for v in levels.values()), total, levels


if __name__ == "__main__":
    n, cat, levels = analyse(sys.argv[1], sys.argv[2])
    total = sum(cat.values())
    print(f"{total} iterations, {n} converged increments: " + ", ".join(f"{k} {v}" for k, v in cat.items()))
    print("| output level | increments | iterations | failed | augmented re-solves | before the quadratic phase | in it |")
    print("|---|---|---|---|---|---|---|")
    for lv, (n_inc, c) in levels.items():
        v = list(c.values())
        print(f"| {lv} | {n_inc} | {sum(v)} | " + " | ".join(str(x) for x in v) + " |")
