#!/usr/bin/env python3
"""Paired differences of a study's configurations against one of them, for docs/results/*/RESULTS.md.
Every configuration of a study runs the same seeds (the same random numbers where the configurations
share them), so the per-seed difference to a base configuration cancels what the seeds have in
common (a firefly in the reference scene, the load of the machine at that seed's turn). For each
scene and each value V of KEY: mean ± 95% confidence half-width (t distribution, over seeds) of
metric(V) − metric(BASE) at the last frame, and of (metric x ms_median)(V) − (metric x ms_median)(BASE)
for the error metrics (the equal-time view: error x time is constant in expectation for an
estimator whose error falls as 1/time), the per-seed ratio metric(V) / metric(BASE) (mean ± 95%),
and the base's own mean. KEY may join columns with "+" (integrator+render.spp, BASE pt+4) to
compare configurations that differ in more than one column.
    scripts/study_paired.py OUT/results.csv KEY BASE [--metrics=ms_median,relmse,flip] [--where=K=V ...]
--where keeps only the rows whose column K is V (e.g. --where=integrator=restir-pt where another
integrator's rows share KEY's values); each (scene, KEY value) must then name one configuration.
report.html computes the same analysis itself ("Paired comparison against the baseline", src/study/
paired.cpp): every configuration against the study's "baseline" (or each scene's first configuration),
per metric, with a verdict. This script stays for what the report does not do: another base, a KEY
of joined columns, --where."""
import csv
import math
import os
import statistics as st
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_summary import mean_ci  # noqa: E402

ERROR_METRICS = ("relmse", "flip", "noise")


def key_of(r, key):
    return "+".join(r[k] for k in key.split("+"))


def values(rows, key, metric):
    """(scene, KEY value) -> seed -> metric at the last frame (x ms_median for METRIC*ms)."""
    out = defaultdict(dict)
    m, timed = (metric[:-3], True) if metric.endswith("*ms") else (metric, False)
    for r in rows:
        if r.get(m, "") in ("", "nan"):
            continue
        v = float(r[m]) * (float(r["ms_median"]) if timed else 1.0)
        out[(r["scene"], key_of(r, key))][r["seed"]] = v
    return out


def table(rows, key, base, metric):
    vals = values(rows, key, metric)
    print("\n| scene | %s | %s − %s=%s (paired, 95%%) | ratio to it (paired, 95%%) | base mean |" % (key, metric, key, base))
    print("|---|---|---|---|---|")
    for (scene, v), per_seed in vals.items():
        ref = vals.get((scene, base))
        if v == base or not ref:
            continue
        seeds = sorted(s for s in per_seed if s in ref)
        if len(seeds) < 2:
            continue
        m, h = mean_ci([per_seed[s] - ref[s] for s in seeds])
        b = st.mean(ref[s] for s in seeds)
        rel = " (%+.1f%%)" % (100 * m / b) if b else ""
        ratios = [per_seed[s] / ref[s] for s in seeds if ref[s] != 0]
        ratio = "%.3g ± %.2g" % mean_ci(ratios) if len(ratios) > 1 else "–"
        print("| %s | %s | %+.4g ± %.2g%s | %s | %.4g |" % (scene, v, m, h, rel, ratio, b))


def main(argv):
    metrics = ["ms_median", "relmse", "flip"]
    args, where = [], []
    for a in argv:
        if a.startswith("--metrics="):
            metrics = a.split("=", 1)[1].split(",")
        elif a.startswith("--where="):
            where.append(a.split("=", 1)[1].split("=", 1))
        else:
            args.append(a)
    if len(args) != 3:
        sys.exit(__doc__)
    path, key, base = args
    rows = list(csv.DictReader(open(path)))
    last = max(int(r["frame"]) for r in rows)
    rows = [r for r in rows if int(r["frame"]) == last and all(r.get(k) == v for k, v in where)]
    if not rows or any(k not in rows[0] for k in key.split("+")):
        sys.exit("error: %s: no rows, or no column %s" % (path, key))
    configs = defaultdict(set)
    for r in rows:
        configs[(r["scene"], key_of(r, key))].add(r["config"])
    clash = [k for k, c in configs.items() if len(c) > 1]
    if clash:
        sys.exit("error: %s: %s=%s of %s is %d configurations (%s); narrow it with --where=K=V" %
                 (path, key, clash[0][1], clash[0][0], len(configs[clash[0]]), ", ".join(sorted(configs[clash[0]]))))
    for metric in metrics:
        if metric not in rows[0]:
            continue
        table(rows, key, base, metric)
        if metric in ERROR_METRICS and "ms_median" in rows[0]:
            table(rows, key, base, metric + "*ms")


if __name__ == "__main__":
    main(sys.argv[1:])
