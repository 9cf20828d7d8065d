#!/usr/bin/env python3
"""Phase table of an M-cap study in the dynamic room (studies/m-cap-dynamic*.json), for
docs/results/*/RESULTS.md: per cap, the mean per-frame relMSE over each phase (± 95% half-width
over the seeds' phase means, t distribution) and the lag after the switch-off at frame 8: the
frames after frame 8 until the relMSE (mean over seeds) is first within 10% of its mean over
frames 15-19 (the steady level with the light off).
    scripts/mcap_phases.py OUT/results.csv CAP_KEY        (e.g. di.max_history, pt.max_history)"""
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


def ci(values):
    return "%.4f ± %.4f" % mean_ci(values)


def lag(per_frame):
    steady = st.mean(per_frame[f] for f in STEADY)
    for f in sorted(per_frame):
        if f >= SWITCH and abs(per_frame[f] - steady) <= 0.1 * steady:
            return f - SWITCH
    return None


def main(path, key):
    err = defaultdict(dict)  # (cap, seed) -> frame -> relmse
    for r in csv.DictReader(open(path)):
        err[(int(float(r[key])), r["seed"])][int(r["frame"])] = float(r["relmse"])
    caps = sorted({c for c, _ in err}, key=lambda c: (c != 0, c))
    print("| cap | " + " | ".join(p for p, _ in PHASES) + " | lag after switch-off (frames) |")
    print("|---|" + "---|" * (len(PHASES) + 1))
    for cap in caps:
        seeds = [s for c, s in err if c == cap]
        cells = [ci([st.mean(err[(cap, s)][f] for f in frames) for s in seeds]) for _, frames in PHASES]
        frames = sorted(err[(cap, seeds[0])])
        mean_per_frame = {f: st.mean(err[(cap, s)][f] for s in seeds) for f in frames}
        print("| %s | %s | %s |" % ("none" if cap == 0 else cap, " | ".join(cells), lag(mean_per_frame)))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
