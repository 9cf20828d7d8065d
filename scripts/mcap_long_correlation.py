#!/usr/bin/env python3
"""Why an uncapped history costs error in the long M-cap study (docs/results/m-cap-long): is the
uncapped error more correlated between neighbouring pixels (spatial reuse sharing samples that new
candidates no longer refresh)? Renders scenes/blinking-room.pbrt with restir-di for 1200 frames
at di.max_history 0 (no cap) and 5, per seed, keeps frames 40 (light on) and 90 (light off) of
every 100, and measures each against the study's path-traced references box-filtered down to the
render's size:
  - relMSE with the 0.5% largest errors clipped (the fireflies, which hit every cap alike);
  - the correlation of the (clipped) luminance error of horizontally adjacent pixels;
  - relMSE of 2x2 block means over the full relMSE (0.25 for independent pixel errors, 1 for
    errors shared by the block).
Per cap and phase: the mean of each per period, and the change of the correlation from the first
half of the run to the second (per seed, mean ± 95% half-width over the seeds).
Needs numpy and the OpenEXR module (pip install OpenEXR numpy).
    scripts/mcap_long_correlation.py RESTIR REFERENCES_DIR [--size 160x90] [--seeds 6] [--work DIR]
REFERENCES_DIR: out/m-cap-long/references of a run of the study at a multiple of --size (its two
EXRs: the darker is the light-off state)."""
import argparse
import glob
import os
import shutil
import statistics as st
import subprocess
import sys
import tempfile

import numpy as np
import OpenEXR

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_summary import mean_ci  # noqa: E402

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "blinking-room.pbrt")
PERIODS, PHASES = 12, (("off", 90), ("on", 40))


def load(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        a = ch["RGB"].pixels if "RGB" in ch else np.stack([ch[c].pixels for c in "RGB"], -1)
    return np.asarray(a, dtype=np.float64)


def down(a, k):
    h, w, c = a.shape
    return a[:h // k * k, :w // k * k].reshape(h // k, k, w // k, k, c).mean((1, 3))


def metrics(img, ref):
    e = img - ref
    q = np.quantile(np.abs(e), 0.995)
    e = np.clip(e, -q, q)

    def rel(e, r):
        return float(np.mean(e ** 2 / (r ** 2 + 1e-2)))
    full = rel(e, ref)
    lum = e.mean(-1)
    corr = float(np.corrcoef(lum[:, :-1].ravel(), lum[:, 1:].ravel())[0, 1])
    return full, corr, rel(down(e, 2), down(ref, 2)) / full


def render(restir, work, w, h, cap, seed):
    d = os.path.join(work, "%d_%d" % (cap, seed))
    os.makedirs(d, exist_ok=True)
    subprocess.run([restir, "render", SCENE, "--integrator", "restir-di", "--spp", "1", "--frames", str(PERIODS * 100),
                    "--set", "film.width=%d" % w, "--set", "film.height=%d" % h, "--set", "di.max_history=%d" % cap,
                    "--set", "render.seed=%d" % seed, "--frame-dir", d, "-o", os.path.join(d, "last.exr")],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    keep = {"frame_%04d.exr" % (p * 100 + f) for p in range(PERIODS) for _, f in PHASES}
    for name in os.listdir(d):
        if name not in keep:
            os.remove(os.path.join(d, name))
    return d


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("restir")
    ap.add_argument("references")
    ap.add_argument("--size", default="160x90")
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--work", help="keep the frames here (default: a temporary folder, removed)")
    a = ap.parse_args()
    w, h = (int(x) for x in a.size.split("x"))
    refs = sorted((load(p) for p in glob.glob(os.path.join(a.references, "*.exr"))), key=lambda r: r.mean())
    if len(refs) != 2 or refs[0].shape[1] % w or refs[0].shape[1] // w != refs[0].shape[0] // h:
        sys.exit("error: %s: expected the two references of the blinking room at a multiple of %s" % (a.references, a.size))
    k = refs[0].shape[1] // w
    ref = {"off": down(refs[0], k), "on": down(refs[1], k)}
    work = a.work or tempfile.mkdtemp(prefix="mcap-corr-")
    try:
        dirs = {(cap, s): render(a.restir, work, w, h, cap, s) for s in range(1, a.seeds + 1) for cap in (0, 5)}
        print("%s, %d seeds; per period 0-%d: mean over the seeds" % (a.size, a.seeds, PERIODS - 1))
        for phase, f in PHASES:
            for cap in (0, 5):
                m = {s: [metrics(load(os.path.join(dirs[(cap, s)], "frame_%04d.exr" % (p * 100 + f))), ref[phase])
                         for p in range(PERIODS)] for s in range(1, a.seeds + 1)}
                name = "none" if cap == 0 else str(cap)
                for i, label in enumerate(("relMSE (clipped)", "neighbour corr.", "2x2 / full")):
                    row = [st.mean(m[s][p][i] for s in m) for p in range(PERIODS)]
                    print("light %-3s cap %-4s %-17s %s" % (phase, name, label, " ".join("%.4f" % x for x in row)))
                half = PERIODS // 2
                change = [st.mean(x[1] for x in m[s][half:]) - st.mean(x[1] for x in m[s][:half]) for s in m]
                print("light %-3s cap %-4s neighbour corr. second half − first: %+.3f ± %.3f (%d of %d seeds up)"
                      % ((phase, name) + mean_ci(change) + (sum(c > 0 for c in change), len(change))))
    finally:
        if not a.work:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
