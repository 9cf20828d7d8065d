#!/usr/bin/env python3
"""Generates scenes/ajar-door.pbrt: Veach's "door ajar" setting (CC0).

Two closed rooms side by side, 5 x 2.8 x 6 each, separated by a 15 cm wall with a doorway.
The camera is in the dark room A; the door stands ajar (DOOR_ANGLE degrees) into room B, whose
ceiling light is not visible from the camera: room A is lit almost only by light that has
bounced around room B and leaks through the gap between the door's free edge and the jamb.
Checks (ray casting on a grid of camera rays): no camera ray sees the light, some see into room B
through the gap.

Usage: python3 scripts/gen_ajar_door.py [--floor glossy|diffuse] [--check 96]
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pbrtgen import Mesh, camera_rays, fmt3, ray_triangle  # noqa: E402

W, H, D = 5.0, 2.8, 6.0          # each room: x extent, height, z extent
T = 0.15                         # dividing wall thickness (x in [W, W+T])
XB = W + T                       # room B starts here
X_END = XB + W                   # far wall of room B
DOOR_Z0, DOOR_Z1, DOOR_H = 2.2, 3.1, 2.1
DOOR_ANGLE = 18.0                # degrees, the door swings into room B
DOOR_THICK = 0.04
EYE, TARGET, UP, FOV = (0.5, 1.55, 0.45), (5.15, 1.05, 3.1), (0, 1, 0), 55.0
LIGHT = (7.0, 9.0, 0.5, 1.7)     # x0 x1 z0 z1 of the ceiling light in room B
LIGHT_L = (420.0, 390.0, 330.0)

FURNITURE_A = [((2.2, 0, 3.8), (3.4, 0.75, 4.8)),      # table
               ((0.02, 0, 4.2), (0.6, 1.9, 5.8)),      # cabinet against the x=0 wall
               ((3.6, 0, 0.6), (4.6, 0.45, 1.2)),      # bench
               ((1.5, 0, 5.55), (3.0, 1.2, 5.98))]     # low shelf against the back wall
FURNITURE_B = [((8.0, 0, 4.0), (9.5, 1.0, 5.5)),
               ((5.6, 0, 0.3), (6.4, 1.5, 1.1))]


def door_mesh():
    a = math.radians(DOOR_ANGLE)
    w = DOOR_Z1 - DOOR_Z0 - 0.01
    along = (math.sin(a), math.cos(a))          # hinge -> free edge, in (x, z)
    across = (math.cos(a), -math.sin(a))        # panel thickness direction (into room B)
    hx, hz = XB, DOOR_Z0 + 0.005
    base = [(hx, hz), (hx + along[0] * w, hz + along[1] * w),
            (hx + along[0] * w + across[0] * DOOR_THICK, hz + along[1] * w + across[1] * DOOR_THICK),
            (hx + across[0] * DOOR_THICK, hz + across[1] * DOOR_THICK)]
    return Mesh().add_prism(base, DOOR_H - 0.01)


def build():
    shell = Mesh()          # both rooms' walls and ceilings, facing inward (floor separate)
    full = Mesh().add_box((0, 0, 0), (X_END, H, D), outward=False)
    floor = Mesh()
    floor.P, floor.idx = full.P[0:4], [0, 1, 2, 0, 2, 3]
    shell.P, shell.idx = full.P[4:], [i - 4 for i in full.idx[6:]]
    wall = Mesh()
    wall.add_box((W, 0, 0), (XB, H, DOOR_Z0))
    wall.add_box((W, 0, DOOR_Z1), (XB, H, D))
    wall.add_box((W, DOOR_H, DOOR_Z0), (XB, H, DOOR_Z1))
    furniture = Mesh()
    for lo, hi in FURNITURE_A + FURNITURE_B:
        furniture.add_box(lo, hi)
    x0, x1, z0, z1 = LIGHT
    ly = H - 0.002
    light = Mesh().add_quad((x0, ly, z0), (x1, ly, z0), (x1, ly, z1), (x0, ly, z1), (0, -1, 0))
    return dict(shell=shell, floor=floor, wall=wall, door=door_mesh(), furniture=furniture, light=light)


def check(meshes, n):
    """Casts an n x (n*9/16) grid of camera rays; returns (rays, hits on the light, hits in room B)."""
    tris = []
    for name, m in meshes.items():
        for t in m.triangles():
            tris.append((name, t))
    ny = max(1, n * 9 // 16)
    light_hits = room_b = total = 0
    for _, _, d in camera_rays(EYE, TARGET, UP, FOV, 640, 360, n, ny):
        best, what = 1e30, None
        for name, (a, b, c) in tris:
            t = ray_triangle(EYE, d, a, b, c)
            if t is not None and t < best:
                best, what = t, name
        total += 1
        if what == "light":
            light_hits += 1
        if what is not None and EYE[0] + d[0] * best > XB + 1e-3:
            room_b += 1
    return total, light_hits, room_b


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--floor", choices=["glossy", "diffuse"], default="glossy")
    ap.add_argument("--check", type=int, default=96, help="camera rays across (0: skip the check)")
    args = ap.parse_args()
    m = build()
    floor_mat = "floor-glossy" if args.floor == "glossy" else "floor-diffuse"
    out = [f"""# restir-lab "door ajar" (after Veach's thesis, fig. 10.4; CC0, scripts/gen_ajar_door.py).
# Two closed rooms 5 x 2.8 x 6 side by side; the camera is in room A (x < 5), the door to room B
# stands {DOOR_ANGLE:g} degrees ajar into room B, whose ceiling light (x {LIGHT[0]:g}..{LIGHT[1]:g}, z {LIGHT[2]:g}..{LIGHT[3]:g}) cannot be
# seen from the camera. Room A receives light almost only through the gap after bounces in room B.
# Tests: difficult indirect illumination (ReSTIR GI / PT path reuse vs. path tracing), DI that
# is nearly always occluded (ReSTIR DI's visibility reuse, shadowed reservoirs).
# Floor: "{floor_mat}" (scripts/gen_ajar_door.py --floor glossy|diffuse; both are defined
# below, so switching is also a one-word edit of the NamedMaterial under "floor").

LookAt {fmt3(EYE)}   {fmt3(TARGET)}   {fmt3(UP)}
Camera "perspective" "float fov" {FOV:g}
Film "rgb" "integer xresolution" 640 "integer yresolution" 360
Sampler "independent" "integer pixelsamples" 64
Integrator "path" "integer maxdepth" 10

WorldBegin

MakeNamedMaterial "walls" "string type" "diffuse" "rgb reflectance" [0.7 0.68 0.62]
MakeNamedMaterial "floor-diffuse" "string type" "diffuse" "rgb reflectance" [0.45 0.35 0.25]
MakeNamedMaterial "floor-glossy" "string type" "conductor"
  "rgb reflectance" [0.75 0.6 0.45] "float roughness" 0.2 "bool remaproughness" false
MakeNamedMaterial "door" "string type" "diffuse" "rgb reflectance" [0.5 0.32 0.18]
MakeNamedMaterial "furniture" "string type" "diffuse" "rgb reflectance" [0.55 0.55 0.5]

# Room B's ceiling light ({LIGHT[1] - LIGHT[0]:g} x {LIGHT[3] - LIGHT[2]:g}, one-sided, facing down).
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [{fmt3(LIGHT_L)}]
"""]
    out.append(m["light"].pbrt())
    sections = [("walls", "shell", "Walls and ceilings of both rooms (facing inward)"),
                (floor_mat, "floor", "Floor of both rooms"),
                ("walls", "wall", "Dividing wall with the doorway (z %g..%g, height %g)" % (DOOR_Z0, DOOR_Z1, DOOR_H)),
                ("door", "door", "The door, hinged at x=%g z=%g, %g degrees open" % (XB, DOOR_Z0, DOOR_ANGLE)),
                ("furniture", "furniture", "Furniture: table, cabinet, bench, shelf (room A); two boxes (room B)")]
    out.append("AttributeEnd\n")
    for mat, key, comment in sections:
        out.append(f'\n# {comment}\nAttributeBegin\n  NamedMaterial "{mat}"\n')
        out.append(m[key].pbrt())
        out.append("AttributeEnd\n")
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "ajar-door.pbrt")
    with open(path, "w") as f:
        f.write("".join(out))
    msg = "ajar-door.pbrt written"
    if args.check:
        total, light_hits, room_b = check(m, args.check)
        msg += f"; camera rays: {total}, see the light: {light_hits}, see into room B: {room_b}"
        if light_hits:
            sys.exit(msg + "\nerror: the light is directly visible from the camera")
        if not room_b:
            sys.exit(msg + "\nerror: the gap is not visible from the camera")
    print(msg)


if __name__ == "__main__":
    main()
