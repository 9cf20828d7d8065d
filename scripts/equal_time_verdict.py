#!/usr/bin/env python3
"""The verdict tables of a study of ReSTIR PT shifts against the path tracer (studies/equal-time.json,
studies/shift-mapping.json) from its results.csv, as the Markdown tables of docs/results/*/RESULTS.md,
one pair per scene: each configuration's relMSE, FLIP and frame
time with 95% confidence intervals over seeds, and each ReSTIR PT shift against the path tracer
at equal time (relMSE x ms, whose expectation is constant for the path tracer since relMSE ~ 1/spp
and ms ~ spp; and FLIP against the path tracer's FLIP interpolated at the same frame time), with
bootstrap 95% intervals over seeds.
    scripts/equal_time_verdict.py OUT/results.csv
With one path tracer configuration (shift-mapping), FLIP at equal time is not computed."""
import csv
import math
import random
import statistics as st
import sys
from collections import defaultdict

from study_summary import mean_ci as ci  # this folder


def label(r):
    return "pt %s spp" % r["render.spp"] if r["integrator"] == "pt" else r["pt.shift"]


def pt_flip_at(pt, ms):
    c = sorted((st.mean(x["ms"]), st.mean(x["flip"])) for x in pt.values())
    k = 0
    while k + 2 < len(c) and c[k + 1][0] < ms:
        k += 1
    t = (math.log(ms) - math.log(c[k][0])) / (math.log(c[k + 1][0]) - math.log(c[k][0]))
    return c[k][1] + t * (c[k + 1][1] - c[k][1])


def verdict(rows):
    groups = defaultdict(lambda: defaultdict(list))
    order = []
    for r in rows:
        k = label(r)
        if k not in groups:
            order.append(k)
        g = groups[k]
        g["ms"].append(float(r["ms_median"]))
        g["relmse"].append(float(r["relmse"]))
        g["flip"].append(float(r["flip"]))
    pt = {k: g for k, g in groups.items() if k.startswith("pt ")}
    print("| configuration | seeds | ms per frame | relMSE | FLIP | relMSE x ms (median) |")
    print("|---|---|---|---|---|---|")
    for k in order:
        g = groups[k]
        cells = ["%.3g ± %.2g" % ci(g[m]) for m in ("ms", "relmse", "flip")]
        work = st.median([a * b for a, b in zip(g["relmse"], g["ms"])])
        print("| %s | %d | %s | %.3g |" % (k, len(g["ms"]), " | ".join(cells), work))
    rng = random.Random(1)

    def pooled_work(sample):
        return st.median([a * b for g in sample.values() for a, b in zip(g["relmse"], g["ms"])])

    def resample(g):
        idx = [rng.randrange(len(g["ms"])) for _ in g["ms"]]
        return {m: [g[m][i] for i in idx] for m in ("ms", "relmse", "flip")}

    flip_too = len(pt) > 1
    print()
    print("| shift | relMSE x ms ÷ path tracer's (95% CI) |" + (" FLIP ÷ path tracer's FLIP at the same ms (95% CI) |" if flip_too else ""))
    print("|---|---|" + ("---|" if flip_too else ""))
    for k in order:
        if k in pt:
            continue
        g = groups[k]
        work = st.median([a * b for a, b in zip(g["relmse"], g["ms"])]) / pooled_work(pt)
        bw, bf = [], []
        for _ in range(2000):
            s = resample(g)
            p = {kk: resample(v) for kk, v in pt.items()}
            bw.append(st.median([a * b for a, b in zip(s["relmse"], s["ms"])]) / pooled_work(p))
            if flip_too:
                bf.append(st.mean(s["flip"]) / pt_flip_at(p, st.mean(s["ms"])))
        bw.sort()
        line = "| %s | %.2f (%.2f – %.2f) |" % (k, work, bw[50], bw[1949])
        if flip_too:
            bf.sort()
            flip = st.mean(g["flip"]) / pt_flip_at(pt, st.mean(g["ms"]))
            line += " %.2f (%.2f – %.2f) |" % (flip, bf[50], bf[1949])
        print(line)


def main(path):
    rows = list(csv.DictReader(open(path)))
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    for i, scene in enumerate(scenes):
        if len(scenes) > 1:
            print(("\n" if i else "") + "### " + scene + "\n")
        verdict([r for r in rows if r["scene"] == scene])


if __name__ == "__main__":
    main(sys.argv[1])
