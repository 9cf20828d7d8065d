#!/usr/bin/env python3
"""Generates scenes/teapot/teapot.ply (the Utah teapot, tessellated) and scenes/teapot.pbrt.

The control points and patches are Martin Newell's 1975 Utah teapot data (32 bicubic Bezier
patches over 306 control points, the four bottom patches being the customary later addition).
The data set has been freely published and redistributed for decades (Crow 1987, "The Origins
of the Teapot"; countless graphics textbooks and libraries) and is treated as public domain.
Everything else in this script is CC0, like the scenes it writes.

Usage: python3 scripts/gen_teapot.py [--n 12]   (run from anywhere; writes into scenes/)

The PLY is in the data's own frame (z up, base at z=0, about 6.4 x 4 x 3.15 units); the
scenes rotate it into the y-up world with `Rotate -90 1 0 0`. It is binary little-endian with
`vertex x y z nx ny nz` (float) and `face vertex_indices` (uchar count, int indices). Normals
come from the patch derivatives, cross(dP/du, dP/dv), oriented outward per patch, with the
degenerate derivatives at the lid and bottom poles replaced by the limit taken just inside the
patch. Triangles are wound counter-clockwise around the outward normal (their face normal
cross(p1 - p0, p2 - p0) agrees with the vertex normals); zero-area triangles at the poles are
dropped.
"""
import argparse
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pbrtgen import Mesh, cross, dot, fmt, length, normalize, sub  # noqa: E402

# Newell's 306 control points (x y z), 1-based in PATCHES below.
POINTS_TEXT = """
1.4 0.0 2.4  1.4 -0.784 2.4  0.784 -1.4 2.4  0.0 -1.4 2.4
1.3375 0.0 2.53125  1.3375 -0.749 2.53125  0.749 -1.3375 2.53125  0.0 -1.3375 2.53125
1.4375 0.0 2.53125  1.4375 -0.805 2.53125  0.805 -1.4375 2.53125  0.0 -1.4375 2.53125
1.5 0.0 2.4  1.5 -0.84 2.4  0.84 -1.5 2.4  0.0 -1.5 2.4
-0.784 -1.4 2.4  -1.4 -0.784 2.4  -1.4 0.0 2.4
-0.749 -1.3375 2.53125  -1.3375 -0.749 2.53125  -1.3375 0.0 2.53125
-0.805 -1.4375 2.53125  -1.4375 -0.805 2.53125  -1.4375 0.0 2.53125
-0.84 -1.5 2.4  -1.5 -0.84 2.4  -1.5 0.0 2.4
-1.4 0.784 2.4  -0.784 1.4 2.4  0.0 1.4 2.4
-1.3375 0.749 2.53125  -0.749 1.3375 2.53125  0.0 1.3375 2.53125
-1.4375 0.805 2.53125  -0.805 1.4375 2.53125  0.0 1.4375 2.53125
-1.5 0.84 2.4  -0.84 1.5 2.4  0.0 1.5 2.4
0.784 1.4 2.4  1.4 0.784 2.4
0.749 1.3375 2.53125  1.3375 0.749 2.53125
0.805 1.4375 2.53125  1.4375 0.805 2.53125
0.84 1.5 2.4  1.5 0.84 2.4
1.75 0.0 1.875  1.75 -0.98 1.875  0.98 -1.75 1.875  0.0 -1.75 1.875
2.0 0.0 1.35  2.0 -1.12 1.35  1.12 -2.0 1.35  0.0 -2.0 1.35
2.0 0.0 0.9  2.0 -1.12 0.9  1.12 -2.0 0.9  0.0 -2.0 0.9
-0.98 -1.75 1.875  -1.75 -0.98 1.875  -1.75 0.0 1.875
-1.12 -2.0 1.35  -2.0 -1.12 1.35  -2.0 0.0 1.35
-1.12 -2.0 0.9  -2.0 -1.12 0.9  -2.0 0.0 0.9
-1.75 0.98 1.875  -0.98 1.75 1.875  0.0 1.75 1.875
-2.0 1.12 1.35  -1.12 2.0 1.35  0.0 2.0 1.35
-2.0 1.12 0.9  -1.12 2.0 0.9  0.0 2.0 0.9
0.98 1.75 1.875  1.75 0.98 1.875
1.12 2.0 1.35  2.0 1.12 1.35
1.12 2.0 0.9  2.0 1.12 0.9
2.0 0.0 0.45  2.0 -1.12 0.45  1.12 -2.0 0.45  0.0 -2.0 0.45
1.5 0.0 0.225  1.5 -0.84 0.225  0.84 -1.5 0.225  0.0 -1.5 0.225
1.5 0.0 0.15  1.5 -0.84 0.15  0.84 -1.5 0.15  0.0 -1.5 0.15
-1.12 -2.0 0.45  -2.0 -1.12 0.45  -2.0 0.0 0.45
-0.84 -1.5 0.225  -1.5 -0.84 0.225  -1.5 0.0 0.225
-0.84 -1.5 0.15  -1.5 -0.84 0.15  -1.5 0.0 0.15
-2.0 1.12 0.45  -1.12 2.0 0.45  0.0 2.0 0.45
-1.5 0.84 0.225  -0.84 1.5 0.225  0.0 1.5 0.225
-1.5 0.84 0.15  -0.84 1.5 0.15  0.0 1.5 0.15
1.12 2.0 0.45  2.0 1.12 0.45
0.84 1.5 0.225  1.5 0.84 0.225
0.84 1.5 0.15  1.5 0.84 0.15
-1.6 0.0 2.025  -1.6 -0.3 2.025  -1.5 -0.3 2.25  -1.5 0.0 2.25
-2.3 0.0 2.025  -2.3 -0.3 2.025  -2.5 -0.3 2.25  -2.5 0.0 2.25
-2.7 0.0 2.025  -2.7 -0.3 2.025  -3.0 -0.3 2.25  -3.0 0.0 2.25
-2.7 0.0 1.8  -2.7 -0.3 1.8  -3.0 -0.3 1.8  -3.0 0.0 1.8
-1.5 0.3 2.25  -1.6 0.3 2.025  -2.5 0.3 2.25  -2.3 0.3 2.025
-3.0 0.3 2.25  -2.7 0.3 2.025  -3.0 0.3 1.8  -2.7 0.3 1.8
-2.7 0.0 1.575  -2.7 -0.3 1.575  -3.0 -0.3 1.35  -3.0 0.0 1.35
-2.5 0.0 1.125  -2.5 -0.3 1.125  -2.65 -0.3 0.9375  -2.65 0.0 0.9375
-2.0 -0.3 0.9  -1.9 -0.3 0.6  -1.9 0.0 0.6
-3.0 0.3 1.35  -2.7 0.3 1.575  -2.65 0.3 0.9375  -2.5 0.3 1.125
-1.9 0.3 0.6  -2.0 0.3 0.9
1.7 0.0 1.425  1.7 -0.66 1.425  1.7 -0.66 0.6  1.7 0.0 0.6
2.6 0.0 1.425  2.6 -0.66 1.425  3.1 -0.66 0.825  3.1 0.0 0.825
2.3 0.0 2.1  2.3 -0.25 2.1  2.4 -0.25 2.025  2.4 0.0 2.025
2.7 0.0 2.4  2.7 -0.25 2.4  3.3 -0.25 2.4  3.3 0.0 2.4
1.7 0.66 0.6  1.7 0.66 1.425  3.1 0.66 0.825  2.6 0.66 1.425
2.4 0.25 2.025  2.3 0.25 2.1  3.3 0.25 2.4  2.7 0.25 2.4
2.8 0.0 2.475  2.8 -0.25 2.475  3.525 -0.25 2.49375  3.525 0.0 2.49375
2.9 0.0 2.475  2.9 -0.15 2.475  3.45 -0.15 2.5125  3.45 0.0 2.5125
2.8 0.0 2.4  2.8 -0.15 2.4  3.2 -0.15 2.4  3.2 0.0 2.4
3.525 0.25 2.49375  2.8 0.25 2.475  3.45 0.15 2.5125  2.9 0.15 2.475
3.2 0.15 2.4  2.8 0.15 2.4
0.0 0.0 3.15  0.0 -0.002 3.15  0.002 0.0 3.15
0.8 0.0 3.15  0.8 -0.45 3.15  0.45 -0.8 3.15  0.0 -0.8 3.15
0.0 0.0 2.85
0.2 0.0 2.7  0.2 -0.112 2.7  0.112 -0.2 2.7  0.0 -0.2 2.7
-0.002 0.0 3.15  -0.45 -0.8 3.15  -0.8 -0.45 3.15  -0.8 0.0 3.15
-0.112 -0.2 2.7  -0.2 -0.112 2.7  -0.2 0.0 2.7
0.0 0.002 3.15  -0.8 0.45 3.15  -0.45 0.8 3.15  0.0 0.8 3.15
-0.2 0.112 2.7  -0.112 0.2 2.7  0.0 0.2 2.7
0.45 0.8 3.15  0.8 0.45 3.15
0.112 0.2 2.7  0.2 0.112 2.7
0.4 0.0 2.55  0.4 -0.224 2.55  0.224 -0.4 2.55  0.0 -0.4 2.55
1.3 0.0 2.55  1.3 -0.728 2.55  0.728 -1.3 2.55  0.0 -1.3 2.55
1.3 0.0 2.4  1.3 -0.728 2.4  0.728 -1.3 2.4  0.0 -1.3 2.4
-0.224 -0.4 2.55  -0.4 -0.224 2.55  -0.4 0.0 2.55
-0.728 -1.3 2.55  -1.3 -0.728 2.55  -1.3 0.0 2.55
-0.728 -1.3 2.4  -1.3 -0.728 2.4  -1.3 0.0 2.4
-0.4 0.224 2.55  -0.224 0.4 2.55  0.0 0.4 2.55
-1.3 0.728 2.55  -0.728 1.3 2.55  0.0 1.3 2.55
-1.3 0.728 2.4  -0.728 1.3 2.4  0.0 1.3 2.4
0.224 0.4 2.55  0.4 0.224 2.55
0.728 1.3 2.55  1.3 0.728 2.55
0.728 1.3 2.4  1.3 0.728 2.4
0.0 0.0 0.0
1.5 0.0 0.15  1.5 0.84 0.15  0.84 1.5 0.15  0.0 1.5 0.15
1.5 0.0 0.075  1.5 0.84 0.075  0.84 1.5 0.075  0.0 1.5 0.075
1.425 0.0 0.0  1.425 0.798 0.0  0.798 1.425 0.0  0.0 1.425 0.0
-0.84 1.5 0.15  -1.5 0.84 0.15  -1.5 0.0 0.15
-0.84 1.5 0.075  -1.5 0.84 0.075  -1.5 0.0 0.075
-0.798 1.425 0.0  -1.425 0.798 0.0  -1.425 0.0 0.0
-1.5 -0.84 0.15  -0.84 -1.5 0.15  0.0 -1.5 0.15
-1.5 -0.84 0.075  -0.84 -1.5 0.075  0.0 -1.5 0.075
-1.425 -0.798 0.0  -0.798 -1.425 0.0  0.0 -1.425 0.0
0.84 -1.5 0.15  1.5 -0.84 0.15
0.84 -1.5 0.075  1.5 -0.84 0.075
0.798 -1.425 0.0  1.425 -0.798 0.0
"""

# 32 patches, 16 one-based control point indices each (4 rows of 4; u runs along a row, v across
# the rows). Groups: rim 0-3, body 4-11, handle 12-15, spout 16-19, lid knob 20-23, lid 24-27,
# bottom 28-31.
PATCHES_TEXT = """
1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16
4 17 18 19 8 20 21 22 12 23 24 25 16 26 27 28
19 29 30 31 22 32 33 34 25 35 36 37 28 38 39 40
31 41 42 1 34 43 44 5 37 45 46 9 40 47 48 13
13 14 15 16 49 50 51 52 53 54 55 56 57 58 59 60
16 26 27 28 52 61 62 63 56 64 65 66 60 67 68 69
28 38 39 40 63 70 71 72 66 73 74 75 69 76 77 78
40 47 48 13 72 79 80 49 75 81 82 53 78 83 84 57
57 58 59 60 85 86 87 88 89 90 91 92 93 94 95 96
60 67 68 69 88 97 98 99 92 100 101 102 96 103 104 105
69 76 77 78 99 106 107 108 102 109 110 111 105 112 113 114
78 83 84 57 108 115 116 85 111 117 118 89 114 119 120 93
121 122 123 124 125 126 127 128 129 130 131 132 133 134 135 136
124 137 138 121 128 139 140 125 132 141 142 129 136 143 144 133
133 134 135 136 145 146 147 148 149 150 151 152 69 153 154 155
136 143 144 133 148 156 157 145 152 158 159 149 155 160 161 69
162 163 164 165 166 167 168 169 170 171 172 173 174 175 176 177
165 178 179 162 169 180 181 166 173 182 183 170 177 184 185 174
174 175 176 177 186 187 188 189 190 191 192 193 194 195 196 197
177 184 185 174 189 198 199 186 193 200 201 190 197 202 203 194
204 204 204 204 207 208 209 210 211 211 211 211 212 213 214 215
204 204 204 204 210 217 218 219 211 211 211 211 215 220 221 222
204 204 204 204 219 224 225 226 211 211 211 211 222 227 228 229
204 204 204 204 226 230 231 207 211 211 211 211 229 232 233 212
212 213 214 215 234 235 236 237 238 239 240 241 242 243 244 245
215 220 221 222 237 246 247 248 241 249 250 251 245 252 253 254
222 227 228 229 248 255 256 257 251 258 259 260 254 261 262 263
229 232 233 212 257 264 265 234 260 266 267 238 263 268 269 242
270 270 270 270 279 280 281 282 275 276 277 278 271 272 273 274
270 270 270 270 282 289 290 291 278 286 287 288 274 283 284 285
270 270 270 270 291 298 299 300 288 295 296 297 285 292 293 294
270 270 270 270 300 305 306 279 297 303 304 275 294 301 302 271
"""


def parse_data():
    vals = [float(t) for t in POINTS_TEXT.split()]
    assert len(vals) == 306 * 3, len(vals)
    pts = [tuple(vals[i:i + 3]) for i in range(0, len(vals), 3)]
    idx = [int(t) for t in PATCHES_TEXT.split()]
    assert len(idx) == 32 * 16 and min(idx) == 1 and max(idx) == 306
    patches = [[pts[i - 1] for i in idx[p * 16:(p + 1) * 16]] for p in range(32)]
    return pts, patches


def bern(t):
    s = 1 - t
    return (s * s * s, 3 * t * s * s, 3 * t * t * s, t * t * t)


def dbern(t):
    s = 1 - t
    return (-3 * s * s, 3 * s * s - 6 * t * s, 6 * t * s - 3 * t * t, 3 * t * t)


def eval_patch(cp, u, v):
    """Point, dP/du, dP/dv of a bicubic patch (cp: 16 points, row i = v, column j = u)."""
    bu, bv, du, dv = bern(u), bern(v), dbern(u), dbern(v)
    P = [0.0, 0.0, 0.0]
    Pu = [0.0, 0.0, 0.0]
    Pv = [0.0, 0.0, 0.0]
    for i in range(4):
        for j in range(4):
            c = cp[4 * i + j]
            w, wu, wv = bu[j] * bv[i], du[j] * bv[i], bu[j] * dv[i]
            for k in range(3):
                P[k] += w * c[k]
                Pu[k] += wu * c[k]
                Pv[k] += wv * c[k]
    return tuple(P), tuple(Pu), tuple(Pv)


def patch_normal(cp, u, v):
    """Unnormalized cross(dP/du, dP/dv); where it vanishes (a row of coincident control points at
    the lid knob / bottom poles) take the limit from just inside the patch."""
    _, pu, pv = eval_patch(cp, u, v)
    n = cross(pu, pv)
    eps = 1e-4
    while length(n) < 1e-9 and eps < 0.1:
        uu = min(max(u, eps), 1 - eps)
        vv = min(max(v, eps), 1 - eps)
        _, pu, pv = eval_patch(cp, uu, vv)
        n = cross(pu, pv)
        eps *= 10
    return n


def outward_sign(group, p, n):
    """+1 if cross(dP/du, dP/dv) at the patch centre (p, n) points out of the teapot."""
    if group in ("rim", "lid"):
        s = n[2]                                   # top surfaces face up
    elif group == "bottom":
        s = -n[2]
    elif group in ("body", "knob"):
        s = n[0] * p[0] + n[1] * p[1]              # radially outward
    else:                                          # handle / spout: half tubes, centre at |y| max
        s = n[1] * p[1]
    return 1 if s > 0 else -1


GROUPS = ["rim"] * 4 + ["body"] * 8 + ["handle"] * 4 + ["spout"] * 4 + ["knob"] * 4 + ["lid"] * 4 + ["bottom"] * 4


def tessellate(n):
    _, patches = parse_data()
    verts, norms, faces = [], [], []
    for pi, cp in enumerate(patches):
        pc, _, _ = eval_patch(cp, 0.5, 0.5)
        sign = outward_sign(GROUPS[pi], pc, patch_normal(cp, 0.5, 0.5))
        base = len(verts)
        for i in range(n + 1):
            for j in range(n + 1):
                u, v = j / n, i / n
                p, _, _ = eval_patch(cp, u, v)
                nn = normalize(patch_normal(cp, u, v))
                verts.append(p)
                norms.append((nn[0] * sign, nn[1] * sign, nn[2] * sign))
        for i in range(n):
            for j in range(n):
                a = base + i * (n + 1) + j
                b, c, d = a + 1, a + n + 2, a + n + 1  # (u+), (u+, v+), (v+)
                for tri in ((a, b, c), (a, c, d)):
                    if sign < 0:
                        tri = (tri[0], tri[2], tri[1])
                    e = cross(sub(verts[tri[1]], verts[tri[0]]), sub(verts[tri[2]], verts[tri[0]]))
                    if length(e) > 1e-10:
                        faces.append(tri)
    return verts, norms, faces


def write_ply(path, verts, norms, faces):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    header = ("ply\nformat binary_little_endian 1.0\n"
              "comment Utah teapot (Newell 1975 Bezier data, public domain), scripts/gen_teapot.py\n"
              f"element vertex {len(verts)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        for p, nn in zip(verts, norms):
            f.write(struct.pack("<6f", *p, *nn))
        for t in faces:
            f.write(struct.pack("<B3i", 3, *t))


def check(verts, norms, faces):
    agree = 0
    for t in faces:
        e = normalize(cross(sub(verts[t[1]], verts[t[0]]), sub(verts[t[2]], verts[t[0]])))
        avg = [sum(norms[k][c] for k in t) for c in range(3)]
        if dot(e, avg) > 0:
            agree += 1
    for nn in norms:
        assert abs(length(nn) - 1) < 1e-5
    return agree / len(faces)


# ---------------------------------------------------------------------------------------------
# scenes/teapot.pbrt

TEAPOT_SCALE = 0.3   # the data's 6.5 x 4 x 3.15 units become about 2 x 1.2 x 0.95


def teapot_instance(x, z, yaw, material, comment):
    return (f"# {comment}\nAttributeBegin\n  Translate {fmt(x)} 0 {fmt(z)}\n  Rotate {fmt(yaw)} 0 1 0\n"
            f"  Scale {TEAPOT_SCALE} {TEAPOT_SCALE} {TEAPOT_SCALE}\n"
            "  Rotate -90 1 0 0   # the teapot data is z-up; this world is y-up\n"
            f'  NamedMaterial "{material}"\n  Shape "plymesh" "string filename" "teapot/teapot.ply"\n'
            "AttributeEnd\n\n")


def sweep_backdrop():
    """A photo-studio sweep: floor (y=0) curving up into a back wall at z=4, facing the camera."""
    prof = [(0.0, -14.0), (0.0, 2.5)]
    r = 1.5
    for k in range(1, 9):
        a = (k / 8) * (math.pi / 2)
        prof.append((r - r * math.cos(a), 2.5 + r * math.sin(a)))
    prof.append((10.0, 4.0))
    m = Mesh()
    for (y0, z0), (y1, z1) in zip(prof, prof[1:]):
        facing = (0, z1 - z0, -(y1 - y0))  # +y on the floor, -z on the wall
        m.add_quad((-20, y0, z0), (20, y0, z0), (20, y1, z1), (-20, y1, z1), facing)
    return m


def write_scene(path):
    light = Mesh().add_quad((-3.5, 6, -3), (-0.5, 6, -3), (-0.5, 6, -0.5), (-3.5, 6, -0.5), (0, -1, 0))
    s = []
    s.append("""# restir-lab: five Utah teapots in a studio sweep (after the thesis' fig. 4.3).
# Generated by scripts/gen_teapot.py; CC0 (teapot data: Newell 1975, public domain).
# Tests: glossy and specular paths (conductors alpha 0.08 / 0.3, smooth and rough glass) where
# ReSTIR DI's reuse at glossy vertices and GI/PT shift mappings (reconnection vs. random
# replay) behave very differently; one rectangular area light + a dim environment.
# Roughness: conductors say "remaproughness" false, so "roughness" is the GGX alpha; the
# dielectric uses pbrt-v4's default remapping (alpha = sqrt(roughness)).

LookAt 0 1.9 -6.7   0 0.5 0.6   0 1 0
Camera "perspective" "float fov" 30
Film "rgb" "integer xresolution" 640 "integer yresolution" 360
Sampler "independent" "integer pixelsamples" 64
Integrator "path" "integer maxdepth" 8

WorldBegin

MakeNamedMaterial "backdrop" "string type" "diffuse" "rgb reflectance" [0.55 0.55 0.55]
MakeNamedMaterial "gold-glossy" "string type" "conductor"
  "rgb eta" [0.143119 0.374957 1.44248] "rgb k" [3.98316 2.38572 1.60322]
  "float roughness" 0.08 "bool remaproughness" false
MakeNamedMaterial "copper-rough" "string type" "conductor"
  "rgb eta" [0.200438 0.924033 1.10221] "rgb k" [3.91295 2.45285 2.14219]
  "float roughness" 0.3 "bool remaproughness" false
MakeNamedMaterial "glass-smooth" "string type" "dielectric" "float eta" 1.5
MakeNamedMaterial "glass-rough" "string type" "dielectric" "float eta" 1.5 "float roughness" 0.05
MakeNamedMaterial "diffuse-blue" "string type" "diffuse" "rgb reflectance" [0.15 0.25 0.6]

# Key light: a 3 x 2.5 one-sided quad facing down, above and in front of the teapots (out of view).
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [14 13 12]
""")
    s.append(light.pbrt())
    s.append("""AttributeEnd

# Dim fill from an interior environment map (CC0, ../shared); +z of the map turned to +y.
AttributeBegin
  Rotate -90 1 0 0
  LightSource "infinite" "string filename" "../../shared/scenes/envmaps/interior.exr" "float scale" 0.3
AttributeEnd

AttributeBegin
  NamedMaterial "backdrop"
""")
    s.append(sweep_backdrop().pbrt())
    s.append("AttributeEnd\n\n")
    # back row of three, front row of two; yaw turns the spouts a little toward the camera
    s.append(teapot_instance(-2.3, 1.4, 20, "gold-glossy", "glossy conductor (gold, alpha 0.08)"))
    s.append(teapot_instance(0.0, 1.6, 0, "glass-smooth", "smooth glass (eta 1.5)"))
    s.append(teapot_instance(2.3, 1.4, -20, "copper-rough", "rough conductor (copper, alpha 0.3)"))
    s.append(teapot_instance(-1.15, -0.7, 30, "glass-rough", "rough glass (eta 1.5, roughness 0.05)"))
    s.append(teapot_instance(1.15, -0.7, -30, "diffuse-blue", "diffuse"))
    with open(path, "w") as f:
        f.write("".join(s))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=12, help="quads per patch side (default 12)")
    args = ap.parse_args()
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes")
    verts, norms, faces = tessellate(args.n)
    frac = check(verts, norms, faces)
    write_ply(os.path.join(root, "teapot", "teapot.ply"), verts, norms, faces)
    write_scene(os.path.join(root, "teapot.pbrt"))
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    print(f"teapot.ply: {len(verts)} vertices, {len(faces)} triangles, bounds {lo} .. {hi}, "
          f"{100 * frac:.2f}% of faces agree with their vertex normals")


if __name__ == "__main__":
    main()
