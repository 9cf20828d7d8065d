#!/usr/bin/env python3
"""Generates scenes/many-lights.pbrt: a closed 20 x 5 x 12 hall with pillars, partitions and
crates, lit ONLY by thousands of small emitters (CC0).

The emitters are small spheres hanging at random heights (some gathered into clusters) and
small one-sided quads lying on the floor, facing up. Their powers are log-uniform over
3.5 orders of magnitude (the extremes are pinned, so max/min power is exactly 10^3.5), with
random tints; radiance = power / (pi * area) (emitted power of a Lambertian emitter is
pi * L * area; a sphere's area is 4 pi r^2). Total power is normalized to TOTAL_POWER so the
hall is reasonably exposed with the default tonemapping. Deterministic: fixed seed.

Usage: python3 scripts/gen_many_lights.py [--spheres 2400] [--quads 600] [--seed 20241123]
"""
import argparse
import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pbrtgen import Mesh, fmt, fmt3  # noqa: E402

X0, X1, Z0, Z1, HEIGHT = -10.0, 10.0, -6.0, 6.0, 5.0
DECADES = 3.5
TOTAL_POWER = 900.0   # W-ish (scene units), summed over all emitters
SPHERE_RADIUS = 0.05
QUAD_SIZE = 0.12

# The camera animation (scenes/many-lights.camera.json, also written here): emitters keep
# CAMERA_CLEARANCE away from its path.
CAMERA_KEYS = [((0.0, 2.4, -5.7), (0.0, 1.2, 2.5)), ((-2.5, 2.6, -5.3), (-0.8, 1.2, 2.5)),
               ((-4.5, 2.8, -4.6), (-1.5, 1.3, 2.5)), ((-7.0, 3.0, -4.2), (-2.0, 1.4, 2.5))]
CAMERA_FOV = 55
CAMERA_CLEARANCE = 1.0

# Occluders: (lo, hi) boxes.
PILLARS = [((x - 0.3, 0.0, z - 0.3), (x + 0.3, HEIGHT, z + 0.3)) for x in (-6.0, -2.0, 2.0, 6.0) for z in (-1.0, 3.0)]
PARTITIONS = [((-8.5, 0.0, 0.9), (-3.5, 2.2, 1.1)),     # a low wall across the left half
              ((3.0, 0.0, -4.5), (3.2, 3.0, -1.8)),     # a wall segment along z, front right
              ((5.0, 0.0, 4.4), (9.0, 1.2, 4.6))]       # a bench-height wall at the back right


def crates(rng):
    out = []
    for _ in range(14):
        while True:
            sx, sy, sz = rng.uniform(0.5, 1.4), rng.uniform(0.4, 1.6), rng.uniform(0.5, 1.4)
            x, z = rng.uniform(X0 + 1, X1 - 1), rng.uniform(Z0 + 1, Z1 - 1)
            b = ((x - sx / 2, 0.0, z - sz / 2), (x + sx / 2, sy, z + sz / 2))
            if not any(overlaps(b, o, 0.3) for o in PILLARS + PARTITIONS + out):
                out.append(b)
                break
    return out


def overlaps(a, b, margin):
    return all(a[0][k] - margin < b[1][k] and b[0][k] - margin < a[1][k] for k in (0, 2))


def blocked(x, y, z, r, boxes):
    """True if a ball of radius r (+ clearance) at (x, y, z) touches any box."""
    m = r + 0.05
    for lo, hi in boxes:
        if lo[0] - m < x < hi[0] + m and lo[2] - m < z < hi[2] + m and y - m < hi[1]:
            return True
    return False


def near_camera_path(p):
    for (a, _), (b, _) in zip(CAMERA_KEYS, CAMERA_KEYS[1:]):
        ab = [b[k] - a[k] for k in range(3)]
        t = sum((p[k] - a[k]) * ab[k] for k in range(3)) / sum(c * c for c in ab)
        t = min(max(t, 0.0), 1.0)
        if math.dist(p, [a[k] + t * ab[k] for k in range(3)]) < CAMERA_CLEARANCE:
            return True
    return False


def tint(rng):
    """A random light colour with luminance 1: mostly warm/cool whites, some saturated."""
    h = rng.random()
    s = rng.choice([0.05, 0.15, 0.3, 0.3, 0.6, 0.9])
    i = int(h * 6) % 6
    f = h * 6 - int(h * 6)
    p, q, t = 1 - s, 1 - s * f, 1 - s * (1 - f)
    r, g, b = [(1, t, p), (q, 1, p), (p, 1, t), (p, q, 1), (t, p, 1), (1, p, q)][i]
    lum = 0.2126 * r + 0.7152 * g + 0.0722 * b
    return (r / lum, g / lum, b / lum)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spheres", type=int, default=2400)
    ap.add_argument("--quads", type=int, default=600)
    ap.add_argument("--seed", type=int, default=20241123)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    boxes = PILLARS + PARTITIONS + crates(rng)

    n = args.spheres + args.quads
    logp = [rng.uniform(0, DECADES) for _ in range(n)]
    logp[0], logp[1] = 0.0, DECADES                       # pin the extremes
    rng.shuffle(logp)
    rel = [10 ** l for l in logp]
    scale = TOTAL_POWER / sum(rel)
    powers = [p * scale for p in rel]

    clusters = [(rng.uniform(X0 + 1, X1 - 1), rng.uniform(2.5, 4.2), rng.uniform(Z0 + 1, Z1 - 1)) for _ in range(14)]
    emitters = []   # (kind, position, radiance rgb, area)
    for k in range(n):
        col = tint(rng)
        if k < args.spheres:
            r = SPHERE_RADIUS
            while True:
                if rng.random() < 0.3:
                    cx, cy, cz = rng.choice(clusters)
                    x, y, z = cx + rng.gauss(0, 0.6), cy + rng.gauss(0, 0.3), cz + rng.gauss(0, 0.6)
                else:
                    x, y, z = rng.uniform(X0, X1), rng.uniform(0.3, HEIGHT - 0.4), rng.uniform(Z0, Z1)
                if (X0 + 0.2 < x < X1 - 0.2 and Z0 + 0.2 < z < Z1 - 0.2 and 0.15 < y < HEIGHT - 0.2
                        and not blocked(x, y, z, r, boxes) and not near_camera_path((x, y, z))):
                    break
            area = 4 * math.pi * r * r
            emitters.append(("sphere", (x, y, z), powers[k] / (math.pi * area), col, area))
        else:
            a = QUAD_SIZE
            while True:
                x, z = rng.uniform(X0 + 0.3, X1 - 0.3), rng.uniform(Z0 + 0.3, Z1 - 0.3)
                if not blocked(x, 0.0, z, a, boxes):
                    break
            emitters.append(("quad", (x, 0.004, z), powers[k] / (math.pi * a * a), col, a * a))

    room = Mesh().add_box((X0, 0, Z0), (X1, HEIGHT, Z1), outward=False)
    pillars = Mesh()
    for lo, hi in PILLARS:
        pillars.add_box(lo, hi)
    other = Mesh()
    for lo, hi in boxes[len(PILLARS):]:
        other.add_box(lo, hi)

    out = [f"""# restir-lab many-lights hall (CC0; generated by scripts/gen_many_lights.py --seed {args.seed}).
# A closed 20 x 5 x 12 hall (floor, ceiling, four walls) with 8 pillars, 3 partitions and 14
# crates, lit ONLY by {n} small emitters: {args.spheres} spheres (r = {SPHERE_RADIUS}) hanging at random
# heights, partly in clusters, and {args.quads} one-sided {QUAD_SIZE} x {QUAD_SIZE} quads on the floor facing
# up. Emitted powers are log-uniform over 10^{DECADES} (max/min = {10 ** DECADES:.0f}), total {TOTAL_POWER:g}.
# Tests: light selection with thousands of lights (uniform vs power-proportional vs ReSTIR DI
# resampling), occlusion-heavy visibility (pillars), temporal reuse under camera motion.

LookAt {fmt3(CAMERA_KEYS[0][0])}   {fmt3(CAMERA_KEYS[0][1])}   0 1 0
Camera "perspective" "float fov" {CAMERA_FOV}
Film "rgb" "integer xresolution" 640 "integer yresolution" 360
Sampler "independent" "integer pixelsamples" 64
Integrator "path" "integer maxdepth" 6

WorldBegin

MakeNamedMaterial "walls" "string type" "diffuse" "rgb reflectance" [0.6 0.58 0.55]
MakeNamedMaterial "floor" "string type" "diffuse" "rgb reflectance" [0.35 0.33 0.3]
MakeNamedMaterial "pillars" "string type" "diffuse" "rgb reflectance" [0.7 0.7 0.72]
MakeNamedMaterial "crates" "string type" "diffuse" "rgb reflectance" [0.55 0.4 0.25]

AttributeBegin
  NamedMaterial "walls"
"""]
    # add_box's first quad is the bottom (the floor); keep it separate for its material
    walls, floor = Mesh(), Mesh()
    floor.P, floor.idx = room.P[0:4], [0, 1, 2, 0, 2, 3]
    walls.P, walls.idx = room.P[4:], [i - 4 for i in room.idx[6:]]
    out.append(walls.pbrt())
    out.append('AttributeEnd\n\nAttributeBegin\n  NamedMaterial "floor"\n')
    out.append(floor.pbrt())
    out.append('AttributeEnd\n\nAttributeBegin\n  NamedMaterial "pillars"\n')
    out.append(pillars.pbrt())
    out.append('AttributeEnd\n\nAttributeBegin\n  NamedMaterial "crates"\n')
    out.append(other.pbrt())
    out.append('AttributeEnd\n\n# Emitters (the material under an emitter is the default diffuse).\n')
    h = QUAD_SIZE / 2
    for kind, (x, y, z), L, col, area in emitters:
        rgb = fmt3(tuple(L * c for c in col))
        if kind == "sphere":
            out.append(f'AttributeBegin\n Translate {fmt(x)} {fmt(y)} {fmt(z)}\n'
                       f' AreaLightSource "diffuse" "rgb L" [{rgb}]\n'
                       f' Shape "sphere" "float radius" {SPHERE_RADIUS}\nAttributeEnd\n')
        else:
            # quad in the y=0 plane around the origin, wound so that its normal is +y
            out.append(f'AttributeBegin\n Translate {fmt(x)} {fmt(y)} {fmt(z)}\n'
                       f' AreaLightSource "diffuse" "rgb L" [{rgb}]\n'
                       f' Shape "trianglemesh" "point3 P" [-{h} 0 -{h} -{h} 0 {h} {h} 0 {h} {h} 0 -{h}]'
                       f' "integer indices" [0 1 2 0 2 3]\nAttributeEnd\n')
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "many-lights.pbrt")
    text = "".join(out)
    with open(path, "w") as f:
        f.write(text)
    keys = [{"eye": list(e), "target": list(t), "up": [0, 1, 0], "fov": CAMERA_FOV} for e, t in CAMERA_KEYS]
    with open(os.path.join(os.path.dirname(path), "many-lights.camera.json"), "w") as f:
        f.write('{"keys": [\n' + ",\n".join("  " + json.dumps(k) for k in keys) + "\n]}\n")
    pa = [L * area * math.pi for _, _, L, _, area in emitters]
    print(f"many-lights.pbrt: {len(emitters)} emitters ({args.spheres} spheres, {args.quads} quads), "
          f"power {min(pa):.4g} .. {max(pa):.4g} (ratio {max(pa) / min(pa):.0f}), total {sum(pa):.1f}, "
          f"{len(text) / 1e6:.3f} MB")


if __name__ == "__main__":
    main()
