#!/usr/bin/env python3
"""Lag after a light switch, raw and after a denoiser (studies/denoise-reuse-dynamic.json), for
docs/results/denoise-reuse/RESULTS.md. Per configuration (the values of KEY, columns joined by "+"):
the mean per-frame relMSE (± 95% half-width over the seeds, t distribution) over the phases and at
the switch frames of scripts/mcap_phases.py, its lag after the switch-off at frame 8 (frames until the
relMSE, mean over seeds, is first within 10% of its mean over frames 15-19), and the relMSE two
frames after the switch-off (frame 10), paired per seed against the same integrator and M-cap
without a denoiser (--base METHOD, default none) where the same seeds exist.
    scripts/denoise_lag.py OUT/results.csv [--key=integrator+di.max_history+pt.max_history+denoise.method]"""
import csv
import os
import statistics as st
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mcap_phases import WINDOWS, lag  # noqa: E402
from study_summary import mean_ci  # noqa: E402

AFTER = 10  # two frames after the switch-off


def main(argv):
    key = "integrator+path.max_depth+di.max_history+pt.max_history+denoise.method"
    base = "none"
    args = []
    for a in argv:
        if a.startswith("--key="):
            key = a.split("=", 1)[1]
        elif a.startswith("--base="):
            base = a.split("=", 1)[1]
        else:
            args.append(a)
    if len(args) != 1:
        sys.exit(__doc__)
    cols = key.split("+")
    err = defaultdict(dict)  # (config values, seed) -> frame -> relmse
    order = []
    for r in csv.DictReader(open(args[0])):
        k = tuple(r[c] for c in cols)
        if k not in order:
            order.append(k)
        err[(k, r["seed"])][int(r["frame"])] = float(r["relmse"])
    print("| " + " | ".join(cols) + " | " + " | ".join(w for w, _ in WINDOWS) +
          " | lag (frames) | frame %d − same without denoiser (paired) |" % AFTER)
    print("|---" * (len(cols) + len(WINDOWS) + 2) + "|")
    for k in order:
        seeds = sorted(s for c, s in err if c == k)
        have = err[(k, seeds[0])]
        cells = ["%.4f ± %.4f" % mean_ci([st.mean(err[(k, s)][f] for f in frames) for s in seeds])
                 if all(f in have for f in frames) else "–" for _, frames in WINDOWS]
        per_frame = {f: st.mean(err[(k, s)][f] for s in seeds) for f in sorted(err[(k, seeds[0])])}
        nd = k[:-1] + (base,)
        pair = [s for s in seeds if (nd, s) in err]
        d = "–"
        if k[-1] != base and len(pair) > 1 and AFTER in have:
            m, h = mean_ci([err[(k, s)][AFTER] - err[(nd, s)][AFTER] for s in pair])
            d = "%+.4f ± %.4f" % (m, h)
        steady = all(f in have for f in range(15, 20))
        print("| " + " | ".join(v if v else "–" for v in k) + " | " + " | ".join(cells) +
              " | %s | %s |" % (lag(per_frame) if steady else "–", d))


if __name__ == "__main__":
    main(sys.argv[1:])
