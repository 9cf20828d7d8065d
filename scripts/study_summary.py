#!/usr/bin/env python3
"""Per-configuration summary of a study's results.csv as a Markdown table, for docs/results/*/RESULTS.md:
each metric's mean ± 95% confidence half-width over seeds (t distribution) at the last frame, one
row per (scene, values of the given keys).
    scripts/study_summary.py OUT/results.csv KEY [KEY ...] [--metrics ms_median,relmse,...]"""
import csv
import math
import statistics as st
import sys
from collections import defaultdict

# Two-sided 95% quantiles of Student's t for 1 ... 15 degrees of freedom (the last one beyond).
T975 = [12.71, 4.30, 3.18, 2.78, 2.57, 2.45, 2.36, 2.31, 2.26, 2.23, 2.20, 2.18, 2.16, 2.14, 2.13]


def t975(dof):
    return T975[min(max(dof, 1), len(T975)) - 1]


def mean_ci(v):
    """Mean and 95% confidence half-width (t distribution) of the values; NaN width for one value."""
    m = st.mean(v)
    h = t975(len(v) - 1) * st.stdev(v) / math.sqrt(len(v)) if len(v) > 1 else float("nan")
    return m, h


def cell(v):
    v = [x for x in v if not math.isnan(x)]
    if not v:
        return "–"
    if len(v) < 2 or st.stdev(v) == 0:
        return "%.4g" % st.mean(v)
    return "%.4g ± %.2g" % mean_ci(v)


def main(argv):
    path, keys, metrics = argv[0], [], ["ms_median", "relmse", "flip"]
    for a in argv[1:]:
        if a.startswith("--metrics="):
            metrics = a.split("=", 1)[1].split(",")
        else:
            keys.append(a)
    rows = list(csv.DictReader(open(path)))
    last = max(int(r["frame"]) for r in rows)
    groups, order = defaultdict(list), []
    for r in rows:
        if int(r["frame"]) != last:
            continue
        k = (r["scene"],) + tuple(r[x] for x in keys)
        if k not in groups:
            order.append(k)
        groups[k].append(r)
    metrics = [m for m in metrics if m in rows[0]]
    print("| scene | " + "".join(k + " | " for k in keys) + "seeds | " + " | ".join(metrics) + " |")
    print("|---" * (len(keys) + 2 + len(metrics)) + "|")
    for k in order:
        g = groups[k]
        vals = [cell([float(r[m]) if r[m] not in ("", "nan") else math.nan for r in g]) for m in metrics]
        print("| " + " | ".join(k) + " | %d | " % len(g) + " | ".join(vals) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
