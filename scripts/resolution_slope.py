#!/usr/bin/env python3
"""Frame time against pixel count from the resolution study's results.csv (docs/results/resolution):
per (scene, integrator), the least-squares slope of log(ms_median) on log(pixels) over every run
(sizes x seeds) with its 95% interval (t, n - 2 degrees of freedom; 1 = time proportional to the
pixel count), and the mean ms per Mpixel at each size (a constant column means linear); then, per
(scene, integrator, size), the median frame time, fps and ms per Mpixel, mean ± 95% half-width
over the seeds (RESULTS.md's second table).
    scripts/resolution_slope.py OUT/results.csv"""
import csv
import math
import statistics as st
import sys
from collections import defaultdict

from study_summary import mean_ci, t975


def fit(points):
    """Slope and its 95% half-width of the least-squares line through (x, y) points."""
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    mx, my = st.mean(xs), st.mean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    b = sum((x - mx) * (y - my) for x, y in points) / sxx
    a = my - b * mx
    n = len(points)
    if n < 3:
        return b, float("nan")
    s2 = sum((y - a - b * x) ** 2 for x, y in points) / (n - 2)
    return b, t975(n - 2) * math.sqrt(s2 / sxx)


def main(path):
    runs = defaultdict(list)  # (scene, integrator) -> [(pixels, ms)]
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            px = int(r["film.width"]) * int(r["film.height"])
            runs[(r["scene"], r["integrator"])].append((px, float(r["ms_median"])))
    sizes = sorted({px for pts in runs.values() for px, _ in pts})
    print("| scene | integrator | slope of log ms on log pixels (95% CI) | "
          + " | ".join("ms/Mpixel at %.2f Mpx" % (s / 1e6) for s in sizes) + " |")
    print("|---|---|---|" + "---|" * len(sizes))
    for (scene, integ), pts in sorted(runs.items()):
        b, h = fit([(math.log(px), math.log(ms)) for px, ms in pts])
        cells = []
        for s in sizes:
            v = [ms / (s / 1e6) for px, ms in pts if px == s]
            m, hw = mean_ci(v) if v else (float("nan"), float("nan"))
            cells.append("%.0f ± %.0f" % (m, hw) if len(v) > 1 else "%.0f" % m)
        print("| %s | %s | %.3f ± %.3f | %s |" % (scene, integ, b, h, " | ".join(cells)))
    print()
    print("| scene | integrator | size | ms_median | fps | ms per Mpixel |")
    print("|---|---|---|---|---|---|")
    for (scene, integ), pts in sorted(runs.items()):
        for s in sizes:
            ms = [v for px, v in pts if px == s]
            if not ms:
                continue
            width = round(math.sqrt(s * 16 / 9))
            cols = [mean_ci(ms), mean_ci([1000 / v for v in ms]), mean_ci([v / (s / 1e6) for v in ms])]
            print("| %s | %s | %dx%d | %s |" % (scene, integ, width, s // width, " | ".join(fmt(m, hw) for m, hw in cols)))


def fmt(m, hw):
    """m ± hw with three significant digits in m."""
    digits = max(0, 2 - int(math.floor(math.log10(abs(m))))) if m else 0
    return "%.*f ± %.*f" % (digits, m, digits, hw)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
