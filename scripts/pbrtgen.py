"""Small helpers shared by the scene generators in scripts/ (standard library only).

Geometry is emitted as pbrt-v4 "trianglemesh" shapes. Every quad is wound so that the geometric
normal cross(p1 - p0, p2 - p0) points along the requested `facing` direction; that matters for
one-sided area lights (pbrt-v4 emits along the geometric normal) and keeps closed boxes
consistently oriented (outward), rooms inward.
"""
import math


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    l = length(a)
    return (a[0] / l, a[1] / l, a[2] / l)


def fmt(v):
    """Compact float formatting (no trailing zeros, no '-0')."""
    s = ("%.5f" % v).rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def fmt3(v):
    return " ".join(fmt(c) for c in v)


def quad(p0, p1, p2, p3, facing):
    """The quad p0 p1 p2 p3 (in order around its boundary) as 4 points whose winding makes
    cross(q1 - q0, q2 - q0) point along `facing`."""
    n = cross(sub(p1, p0), sub(p2, p0))
    if dot(n, facing) < 0:
        return [p0, p3, p2, p1]
    return [p0, p1, p2, p3]


class Mesh:
    """Triangles accumulated into one pbrt "trianglemesh"."""

    def __init__(self):
        self.P = []
        self.idx = []

    def add_quad(self, p0, p1, p2, p3, facing):
        q = quad(p0, p1, p2, p3, facing)
        b = len(self.P)
        self.P.extend(q)
        self.idx.extend([b, b + 1, b + 2, b, b + 2, b + 3])
        return self

    def add_tri(self, a, b, c):
        base = len(self.P)
        self.P.extend([a, b, c])
        self.idx.extend([base, base + 1, base + 2])
        return self

    def add_box(self, lo, hi, outward=True):
        """Axis-aligned box; outward=False makes the faces point inside (a room)."""
        x0, y0, z0 = lo
        x1, y1, z1 = hi
        s = 1 if outward else -1
        self.add_quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1), (0, -s, 0))  # bottom
        self.add_quad((x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1), (0, s, 0))  # top
        self.add_quad((x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (0, 0, -s))  # z0
        self.add_quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (0, 0, s))  # z1
        self.add_quad((x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1), (-s, 0, 0))  # x0
        self.add_quad((x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1), (s, 0, 0))  # x1
        return self

    def add_prism(self, base, height):
        """A vertical prism (box) over the convex quad `base` (4 (x, z) points) from y=0 to
        y=height, outward-facing: used for rotated boxes."""
        cx = sum(p[0] for p in base) / 4
        cz = sum(p[1] for p in base) / 4
        bot = [(x, 0.0, z) for x, z in base]
        top = [(x, height, z) for x, z in base]
        self.add_quad(*top, facing=(0, 1, 0))
        self.add_quad(*bot, facing=(0, -1, 0))
        for i in range(4):
            j = (i + 1) % 4
            mx = (base[i][0] + base[j][0]) / 2 - cx
            mz = (base[i][1] + base[j][1]) / 2 - cz
            self.add_quad(bot[i], bot[j], top[j], top[i], facing=(mx, 0, mz))
        return self

    def triangles(self):
        for t in range(0, len(self.idx), 3):
            yield self.P[self.idx[t]], self.P[self.idx[t + 1]], self.P[self.idx[t + 2]]

    def pbrt(self, indent="  "):
        pts = " ".join(fmt3(p) for p in self.P)
        ind = " ".join(str(i) for i in self.idx)
        return (f'{indent}Shape "trianglemesh"\n{indent}  "point3 P" [ {pts} ]\n'
                f'{indent}  "integer indices" [ {ind} ]\n')


# ---------------------------------------------------------------------------------------------
# A tiny ray caster, used by generators to verify visibility claims (e.g. that a light is not
# directly visible from the camera).

def ray_triangle(o, d, a, b, c):
    e1 = sub(b, a)
    e2 = sub(c, a)
    p = cross(d, e2)
    det = dot(e1, p)
    if abs(det) < 1e-12:
        return None
    inv = 1.0 / det
    s = sub(o, a)
    u = dot(s, p) * inv
    if u < 0 or u > 1:
        return None
    q = cross(s, e1)
    v = dot(d, q) * inv
    if v < 0 or u + v > 1:
        return None
    t = dot(e2, q) * inv
    return t if t > 1e-6 else None


def camera_rays(eye, target, up, fov_deg, width, height, nx, ny):
    """pbrt-v4 perspective camera rays (left-handed LookAt, fov of the shorter axis) through an
    nx x ny grid of pixel centres; yields (px, py, direction)."""
    fwd = normalize(sub(target, eye))
    right = normalize(cross(normalize(up), fwd))
    cup = cross(fwd, right)
    t = math.tan(math.radians(fov_deg) / 2)
    aspect = width / height
    sx, sy = (t * aspect, t) if aspect >= 1 else (t, t / aspect)
    for j in range(ny):
        for i in range(nx):
            u = ((i + 0.5) / nx) * 2 - 1
            v = 1 - ((j + 0.5) / ny) * 2
            d = add(add(fwd, mul(right, u * sx)), mul(cup, v * sy))
            yield i, j, normalize(d)
