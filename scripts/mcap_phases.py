#!/usr/bin/env python3
"""Phase table of an M-cap study in the dynamic room (studies/m-cap-dynamic*.json), for
docs/results/*/RESULTS.md: per cap, the mean per-frame relMSE over each phase (± 95% half-width
over the seeds' phase means, t distribution) and the lag after the switch-off at frame 8: the
frames after frame 8 until the relMSE (mean over seeds) is first within 10% of its mean over
frames 15-19 (the steady level with the light off). Then the switch frames (8: off, 20: on) per
cap, and the paired differences (per seed, the same seed's random numbers for every cap; mean ±
95% half-width over the seeds, and in % of the base) of every cap against --base CAP (default 1) in
each phase and at each switch frame.
    scripts/mcap_phases.py OUT/results.csv CAP_KEY [--base CAP]   (CAP_KEY: di.max_history, pt.max_history)"""
import csv
import os
import statistics as st
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_summary import mean_ci  # noqa: E402

PHASES = [("frames 1-7 (light sweeping)", range(1, 8)), ("frames 15-19 (one light off)", range(15, 20)),
          ("frames 25-31", range(25, 32))]
SWITCH, STEADY = 8, range(15, 20)
SWITCHES = [("frame 8 (switch-off)", range(8, 9)), ("frame 20 (switch-on)", range(20, 21))]
WINDOWS = PHASES[:1] + SWITCHES[:1] + PHASES[1:2] + SWITCHES[1:] + PHASES[2:]  # in frame order


def ci(values):
    return "%.4f ± %.4f" % mean_ci(values)


def lag(per_frame):
    steady = st.mean(per_frame[f] for f in STEADY)
    for f in sorted(per_frame):
        if f >= SWITCH and abs(per_frame[f] - steady) <= 0.1 * steady:
            return f - SWITCH
    return None


def paired(err, caps, base):
    """Per cap: cap − base in each phase and switch frame, paired per seed."""
    print("\n| cap − %s (paired) | %s |" % ("none" if base == 0 else base, " | ".join(p for p, _ in WINDOWS)))
    print("|---|" + "---|" * len(WINDOWS))
    for cap in caps:
        if cap == base:
            continue
        seeds = sorted(s for c, s in err if c == cap and (base, s) in err)
        cells = []
        for _, frames in WINDOWS:
            d = [st.mean(err[(cap, s)][f] for f in frames) - st.mean(err[(base, s)][f] for f in frames) for s in seeds]
            b = st.mean(st.mean(err[(base, s)][f] for f in frames) for s in seeds)
            m, h = mean_ci(d)
            cells.append("%+.4f ± %.4f (%+.1f ± %.1f%%)" % (m, h, 100 * m / b, 100 * h / b))
        print("| %s | %s |" % ("none" if cap == 0 else cap, " | ".join(cells)))


def main(path, key, base=1):
    err = defaultdict(dict)  # (cap, seed) -> frame -> relmse
    for r in csv.DictReader(open(path)):
        err[(int(float(r[key])), r["seed"])][int(r["frame"])] = float(r["relmse"])
    caps = sorted({c for c, _ in err}, key=lambda c: (c != 0, c))
    print("| cap | " + " | ".join(p for p, _ in WINDOWS) + " | lag after switch-off (frames) |")
    print("|---|" + "---|" * (len(WINDOWS) + 1))
    for cap in caps:
        seeds = [s for c, s in err if c == cap]
        cells = [ci([st.mean(err[(cap, s)][f] for f in frames) for s in seeds]) for _, frames in WINDOWS]
        frames = sorted(err[(cap, seeds[0])])
        mean_per_frame = {f: st.mean(err[(cap, s)][f] for s in seeds) for f in frames}
        print("| %s | %s | %s |" % ("none" if cap == 0 else cap, " | ".join(cells), lag(mean_per_frame)))
    if base in caps:
        paired(err, caps, base)


if __name__ == "__main__":
    args = sys.argv[1:]
    base = 1
    if "--base" in args:
        i = args.index("--base")
        base = int(args[i + 1])
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    main(args[0], args[1], base)
