#!/usr/bin/env python3
"""Period table of the long M-cap study (studies/m-cap-long.json; the blinking room, a light on for
frames 0-49 and off for 50-99 of every 100) for docs/results/m-cap-long/RESULTS.md. Per cap:
  - the mean per-frame relMSE in the settled part of each phase (frames 30-49: light on, 80-99:
    light off) of period 0 and of periods 2 to the last, ± the 95% half-width over the seeds
    (t distribution over the seeds' means);
  - the trend over periods 2.. (least-squares slope of the settled on-phase relMSE per period,
    per seed, then mean ± 95% half-width over the seeds): does the error keep growing?
  - the paired differences between caps in the settled phases of periods 2.. (per seed, the same
    seed's random numbers for every cap; mean ± 95% half-width over the seeds, and the ratio);
  - whether the uncapped penalty grows: none − the smallest cap per period, the slope of that
    difference per seed, and its change from the first half of the run to the second.
    scripts/mcap_long.py OUT/results.csv [--compact FILE]
--compact writes cap,seed,frame,relmse,convergence (the columns the table reads) to FILE."""
import csv
import os
import statistics as st
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_summary import mean_ci as ci  # noqa: E402

PERIOD, ON, OFF = 100, range(30, 50), range(80, 100)


def slope(ys):
    xs = range(len(ys))
    mx, my = st.mean(xs), st.mean(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def main(path, compact=None):
    err = defaultdict(dict)  # (cap, seed) -> frame -> relmse
    rows = list(csv.DictReader(open(path)))
    for r in rows:
        cap = r["di.max_history"] if "di.max_history" in r else r["cap"]  # results.csv or a --compact file
        err[(int(float(cap)), r["seed"])][int(r["frame"])] = float(r["relmse"])
    if compact:
        with open(compact, "w") as f:
            f.write("cap,seed,frame,relmse,convergence\n")
            for r in rows:
                conv = "%.5g" % float(r["convergence"]) if r["convergence"] else ""
                f.write("%s,%s,%s,%.5g,%s\n" % (r["di.max_history"], r["seed"], r["frame"], float(r["relmse"]), conv))
    caps = sorted({c for c, _ in err}, key=lambda c: (c != 0, c))
    periods = (max(max(fr) for fr in err.values()) + 1) // PERIOD
    print("| cap | on, period 0 | on, periods 2-%d | off, period 0 | off, periods 2-%d | on-phase slope per period, periods 2-%d |"
          % (periods - 1, periods - 1, periods - 1))
    print("|---|---|---|---|---|---|")
    for cap in caps:
        seeds = sorted(s for c, s in err if c == cap)

        def phase(s, p, frames):
            return st.mean(err[(cap, s)][p * PERIOD + f] for f in frames)
        cells = []
        for frames in (ON, OFF):
            for ps in ([0], range(2, periods)):
                cells.append("%.4f ± %.4f" % ci([st.mean(phase(s, p, frames) for p in ps) for s in seeds]))
        cells = [cells[0], cells[1], cells[2], cells[3]]
        trend = ci([slope([phase(s, p, ON) for p in range(2, periods)]) for s in seeds])
        print("| %s | %s | %+.4f ± %.4f |" % ("none" if cap == 0 else cap, " | ".join(cells), trend[0], trend[1]))
    paired(err, caps, periods)
    penalty_trend(err, caps, periods)


def paired(err, caps, periods):
    def settled(cap, s, frames):
        return st.mean(st.mean(err[(cap, s)][p * PERIOD + f] for f in frames) for p in range(2, periods))
    name = lambda c: "none" if c == 0 else str(c)  # noqa: E731
    print("\n| difference (periods 2-%d) | light on | ratio | light off | ratio |\n|---|---|---|---|---|" % (periods - 1))
    pairs = [(a, b) for i, a in enumerate(caps) for b in caps[i + 1:]]
    for a, b in pairs:
        seeds = sorted(s for c, s in err if c == a and (b, s) in err)
        cells = []
        for frames in (ON, OFF):
            d = ci([settled(a, s, frames) - settled(b, s, frames) for s in seeds])
            ratio = st.mean(settled(a, s, frames) for s in seeds) / st.mean(settled(b, s, frames) for s in seeds)
            cells += ["%+.4f ± %.4f" % d, "×%.3f" % ratio]
        print("| %s − %s | %s |" % (name(a), name(b), " | ".join(cells)))


def penalty_trend(err, caps, periods):
    """Does the uncapped penalty grow? Per period, none − the smallest cap (paired per seed); then
    the least-squares slope of that difference over periods 2.. per seed (mean ± 95%, and how many
    seeds have a positive slope). A growing error shows as a positive, resolved slope."""
    if 0 not in caps or len(caps) < 2:
        return
    best = caps[1]
    seeds = sorted(s for c, s in err if c == 0 and (best, s) in err)

    def diff(s, p, frames):
        return st.mean(err[(0, s)][p * PERIOD + f] - err[(best, s)][p * PERIOD + f] for f in frames)
    print("\n| period | none − %d, light on | none − %d, light off |\n|---|---|---|" % (best, best))
    for p in range(periods):
        print("| %d | %s |" % (p, " | ".join("%+.4f ± %.4f" % ci([diff(s, p, fr) for s in seeds]) for fr in (ON, OFF))))
    for name, frames in (("on", ON), ("off", OFF)):
        slopes = [slope([diff(s, p, frames) for p in range(2, periods)]) for s in seeds]
        print("slope of none − %d per period, light %s, periods 2-%d: %+.5f ± %.5f (%d of %d seeds positive)"
              % ((best, name, periods - 1) + ci(slopes) + (sum(x > 0 for x in slopes), len(slopes))))
        # First half of the run against the second: the change of the paired penalty per seed, and
        # the ratio none / best of the mean levels in each half.
        halves = (range(0, periods // 2), range(periods // 2, periods))
        change = [st.mean(diff(s, p, frames) for p in halves[1]) - st.mean(diff(s, p, frames) for p in halves[0])
                  for s in seeds]

        def ratio(ps):
            def level(c):
                return st.mean(err[(c, s)][p * PERIOD + f] for s in seeds for p in ps for f in frames)
            return level(0) / level(best)
        print("  second half − first half of that penalty: %+.4f ± %.4f (%d of %d seeds positive); none / %d: ×%.3f → ×%.3f"
              % (ci(change) + (sum(x > 0 for x in change), len(change), best, ratio(halves[0]), ratio(halves[1]))))


if __name__ == "__main__":
    args = sys.argv[1:]
    compact = None
    if "--compact" in args:
        i = args.index("--compact")
        compact = args[i + 1]
        del args[i:i + 2]
    if len(args) != 1:
        sys.exit(__doc__)
    main(args[0], compact)
