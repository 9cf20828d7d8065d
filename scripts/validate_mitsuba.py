#!/usr/bin/env python3
"""Compare restir-lab's reference path tracer (`--integrator pt`) with Mitsuba 3's `path` integrator.

For each scene: `restir export-mitsuba` writes the parsed scene as a Mitsuba scene, both renderers
render it at the same resolution and max depth in K independent passes, and the script compares
the image mean luminance (tolerance 1 %) and the 8x8-pixel block means (tolerance 3 %). The K passes
give each renderer's standard error (per-pixel sample variance across passes / K), so a
difference can be told apart from noise: a difference counts only when it exceeds the tolerance by
more than 3 standard errors of the difference. Prints a Markdown table. Called by
scripts/validate-mitsuba.sh, which installs Mitsuba if needed.
"""
import argparse
import os
import re
import subprocess
import sys
import time

import numpy as np
import mitsuba as mi

LUM = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709, as restir-lab's luminance()
MEAN_TOL, BLOCK_TOL, BLOCK = 0.01, 0.03, 8


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"error: {' '.join(cmd)} failed: {r.stderr.strip().splitlines()[-1] if r.stderr.strip() else r.returncode}")
    return r.stdout


def scene_film(restir, scene):
    """(width, height, max_depth) the scene file asks for (restir info), with restir-lab's defaults."""
    info = run([restir, "info", scene])
    m = re.search(r"^film\s+(\S+)x(\S+), spp \S+, max depth (\S+)", info, re.M)
    w, h, d = (m.group(1), m.group(2), m.group(3)) if m else ("-", "-", "-")
    return (int(w) if w != "-" else 640, int(h) if h != "-" else 360, int(d) if d != "-" else 5)


def read_exr(path):
    return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]


def stats(passes):
    """Mean luminance image and the per-pixel variance of that mean, from K independent passes."""
    lum = np.stack([p @ LUM for p in passes])  # K x H x W
    k = lum.shape[0]
    return lum.mean(0), lum.var(0, ddof=1) / k


def blocks(img):
    h, w = (img.shape[0] // BLOCK) * BLOCK, (img.shape[1] // BLOCK) * BLOCK
    return img[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK)


def compare(r_mean, r_var, m_mean, m_var):
    n = r_mean.size
    rm, mm = r_mean.mean(), m_mean.mean()
    r_se, m_se = np.sqrt(r_var.sum()) / n, np.sqrt(m_var.sum()) / n
    diff = (rm - mm) / mm
    diff_se = np.hypot(r_se, m_se) / mm
    # Block means; the relative difference is taken against the pair's mean, floored at 5 % of the
    # image mean so that nearly black blocks are judged on an absolute scale instead of exploding.
    rb, mb = blocks(r_mean).mean(axis=(1, 3)), blocks(m_mean).mean(axis=(1, 3))
    vb = (blocks(r_var).sum(axis=(1, 3)) + blocks(m_var).sum(axis=(1, 3))) / BLOCK**4
    ref = np.maximum(0.5 * (rb + mb), 0.05 * mm)
    d, se = (rb - mb) / ref, np.sqrt(vb) / ref
    worst = np.unravel_index(np.argmax(np.abs(d)), d.shape)
    over = np.abs(d) > BLOCK_TOL
    significant = over & (np.abs(d) > 3 * se)
    return dict(restir=rm, restir_se=r_se, mitsuba=mm, mitsuba_se=m_se, diff=diff, diff_se=diff_se,
                worst=d[worst], worst_se=se[worst], worst_at=worst, over=over.mean(),
                significant=significant.mean(), block_se=float(np.median(se)))


def verdict(c):
    """PASS: within tolerance. DIFF: beyond tolerance AND more than 3 standard errors from zero
    (mean), or more than 2 % of the blocks so. Otherwise the tolerance is missed only where the
    noise is too large to tell ("within noise": more samples needed to decide)."""
    mean_sig = abs(c["diff"]) > MEAN_TOL and abs(c["diff"]) > 3 * c["diff_se"]
    if mean_sig or c["significant"] > 0.02:
        return "DIFF"
    if abs(c["diff"]) <= MEAN_TOL and c["over"] <= 0.02:
        return "PASS"
    return "PASS within noise" + (" (blocks)" if abs(c["diff"]) <= MEAN_TOL else "")


def expected_values(scene):
    """Analytic cases say what each renderer must give: '# expect: restir X mitsuba Y (why)'."""
    with open(scene) as f:
        for line in f:
            m = re.match(r"#\s*expect:\s*restir\s+(\S+)\s+mitsuba\s+(\S+)\s*(.*)", line)
            if m:
                return float(m.group(1)), float(m.group(2)), m.group(3).strip()
    return None


def check_expected(c, expect):
    """Each renderer against its own analytic value (0.2 % or 3 standard errors). Where they agree
    with their values but not with each other, the difference is one of the models, not a bug."""
    er, em, why = expect
    dr, dm = c["restir"] / er - 1, c["mitsuba"] / em - 1
    ok_r = abs(dr) <= max(0.002, 3 * c["restir_se"] / er)
    ok_m = abs(dm) <= max(0.002, 3 * c["mitsuba_se"] / em)
    detail = f"analytic: restir {100 * dr:+.2f} %, mitsuba {100 * dm:+.2f} %"
    if not (ok_r and ok_m):
        return f"DIFF ({detail})"
    if c["verdict"] == "DIFF":
        return f"MODEL: {why.strip('()')} ({detail})"
    return f"{c['verdict']} ({detail})"


def render_restir(a, scene, out, w, h, depth):
    frames = os.path.join(out, "restir_frames")
    # Independent passes = frames of a static camera (each frame has its own random streams);
    # the random pixel pattern keeps the passes independent (Halton would correlate them).
    run([a.restir, "render", scene, "-q", "--integrator", "pt", "--res", f"{w}x{h}", "--spp", str(a.spp // a.passes),
         "--frames", str(a.passes), "--frame-dir", frames, "--average", os.path.join(out, "restir.exr"),
         "--set", f"path.max_depth={depth}", "--set", "render.sample_pattern=random", "--set", "film.filter=box",
         "--set", "film.filter_radius=0.5"])
    return [read_exr(os.path.join(frames, f"frame_{k:04d}.exr")) for k in range(a.passes)]


def render_mitsuba(a, scene, out, w, h, depth):
    run([a.restir, "export-mitsuba", scene, "--out", out, "--set", f"film.width={w}", "--set", f"film.height={h}",
         "--set", f"path.max_depth={depth}", "--set", f"render.spp={a.spp // a.passes}", "--set", "film.filter=box",
         "--set", "film.filter_radius=0.5"])
    ms = mi.load_file(os.path.join(out, "scene.xml"))
    passes = [np.array(mi.render(ms, seed=1000 + k, spp=a.mitsuba_spp // a.passes), dtype=np.float64)
              for k in range(a.passes)]
    mi.Bitmap(np.mean(passes, axis=0).astype(np.float32)).write(os.path.join(out, "mitsuba.exr"))
    return passes


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", nargs="+", help="scene files; SCENE@D renders at max depth D")
    p.add_argument("--restir", default="build/bin/restir")
    p.add_argument("--out", default="out/mitsuba-validation")
    p.add_argument("--width", type=int, default=128)
    p.add_argument("--spp", type=int, default=512, help="restir-lab samples per pixel (all passes)")
    p.add_argument("--mitsuba-spp", type=int, default=512, help="Mitsuba samples per pixel (all passes)")
    p.add_argument("--passes", type=int, default=4, help="independent passes per renderer (for the standard error)")
    p.add_argument("--depth-cap", type=int, default=8, help="max depth = min(the scene's, this)")
    p.add_argument("--variant", default="scalar_rgb")
    a = p.parse_args()
    mi.set_variant(a.variant)
    rows = []
    for spec in a.scenes:
        scene, _, forced = spec.partition("@")
        sw, sh, sd = scene_film(a.restir, scene)
        w, h = a.width, max(8, round(a.width * sh / sw))
        depth = int(forced) if forced else min(sd, a.depth_cap)
        name = os.path.splitext(os.path.basename(scene))[0]
        if name.startswith("scene"):  # the shared scenes: cornell-box/scene-v4.pbrt -> cornell-box-v4
            name = os.path.basename(os.path.dirname(os.path.abspath(scene))) + name[len("scene"):]
        label = f"{name}@{depth}"
        out = os.path.join(a.out, label)
        os.makedirs(out, exist_ok=True)
        t0 = time.time()
        r_pass = render_restir(a, scene, out, w, h, depth)
        t1 = time.time()
        m_pass = render_mitsuba(a, scene, out, w, h, depth)
        t2 = time.time()
        c = compare(*stats(r_pass), *stats(m_pass))
        c.update(name=name, depth=depth, res=f"{w}x{h}", verdict=verdict(c))
        expect = expected_values(scene)
        if expect:
            c["verdict"] = check_expected(c, expect)
        rows.append(c)
        print(f"{label}: restir {c['restir']:.5g} ({t1 - t0:.0f} s), mitsuba {c['mitsuba']:.5g} ({t2 - t1:.0f} s), "
              f"diff {100 * c['diff']:+.2f} % -> {c['verdict']}", file=sys.stderr, flush=True)
    print(f"\n{a.width} px wide, restir-lab `pt` {a.spp} spp, Mitsuba 3 `path` ({a.variant}) {a.mitsuba_spp} spp, "
          f"{a.passes} passes each; ± = one standard error.\n")
    print("| scene | depth | res | restir mean | mitsuba mean | diff % | worst 8x8 block % | blocks > 3 % "
          "| signif. > 3 % | verdict |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for c in rows:
        print(f"| {c['name']} | {c['depth']} | {c['res']} | {c['restir']:.5g} ± {c['restir_se']:.2g} "
              f"| {c['mitsuba']:.5g} ± {c['mitsuba_se']:.2g} | {100 * c['diff']:+.2f} ± {100 * c['diff_se']:.2f} "
              f"| {100 * c['worst']:+.1f} ± {100 * c['worst_se']:.1f} | {100 * c['over']:.1f} % "
              f"| {100 * c['significant']:.1f} % | {c['verdict']} |")
    print("\nblock % = (restir - mitsuba) / mean of the two (floored at 5 % of the image mean); "
          "'signif.' = over 3 % and over 3 standard errors;\n"
          "PASS: mean within 1 % and <= 2 % of the blocks over 3 %; DIFF: the mean over 1 % and over 3 standard errors, "
          "or > 2 % of the blocks significantly over 3 %; otherwise 'within noise'. Analytic cases: each renderer "
          "against its own exact value; MODEL = both exact, the renderers' models differ.")
    return 0 if all(not c["verdict"].startswith("DIFF") for c in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
