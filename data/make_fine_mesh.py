#!/usr/bin/env python3
"""Writes an already-fine mesh: a modeller-style OBJ export of a vase.

    python3 data/make_fine_mesh.py OUT.obj [--around N]

The case compare/run.sh adds to its sweep as the view "fine": a mesh whose
triangles are already about 1-3 pixels wide in the sweep's camera, as a
modelling program would export a finished model (subdivided and smoothed
before export), so the tracer has little left to refine. It is generated at
run time (5.3 MB at the default density): it is not in the repository.

The vase is a surface of revolution, y up, standing on y = 0, 2 units tall:

- profile (radius against height): a rounded foot (quarter circle) from the
  flat bottom, a bulging wall with a wavy profile (two sine ripples on a bulb
  and a neck), a rim rolled over the top (a half circle) and an inner wall
  that goes 0.3 down inside the neck and ends there: the mesh is open, its
  boundary is the inner wall's lower edge (seen through the opening from the
  sweep's camera, which looks down at 20 degrees);
- fluting: the radius varies by 2.5 percent with 12 lobes around the axis;
- the flat bottom is closed by concentric rings of fewer and fewer vertices
  (zipped together by angle) and a fan of 8 at the centre, so no vertex has a
  valence above about 8 there;
- N vertices around (--around, default 180) and rows along the profile spaced
  by arc length at about the same spacing as around (at radius 0.55), so the
  quads are roughly square; each quad is cut into two triangles along the
  same diagonal. N = 180: 28,415 vertices, 56,648 triangles, edges about
  0.019 units, 1-3 px in the sweep's 640x480 camera (the vase is about half
  the image height; 17.6k triangles seen in 36k pixels: 2 pixels each);
  N = 90: 14,084 triangles, the same in pixels for the quick sweep at 320x240.

Like an export it carries per-vertex normals (vn: the exact normal of the
surface of revolution, not of the triangles) and uvs (vt: u around, v along
the profile's arc length; the seam at u = 0/1 has its own vt column, the
bottom a planar projection), faces as v/vt/vn, and `o`, `s` and a header
comment. Positions are shared across the uv seam (one v per point). Triangles
are counter-clockwise seen from the side the vn normals point to (outside of
the outer wall and the bottom, inside of the neck for the inner wall).

Deterministic, standard library only. Prints the counts to stderr.
"""

import math
import sys

HEIGHT = 2.0
FOOT = 0.08          # radius of the foot's quarter circle
RIM = 0.035          # radius of the rim's half circle (wall thickness 0.07)
INNER_DEPTH = 0.3    # how far the inner wall goes down inside the neck
FLUTES, FLUTE_DEPTH = 12, 0.025


def wall_radius(y):
    """The outer wall's radius at height y: a bulb, a neck, a flared lip and
    two ripples."""
    s = y / HEIGHT
    bulb = 0.62 * math.exp(-((s - 0.35) / 0.28) ** 2)
    lip = 0.22 * math.exp(-((s - 1.0) / 0.12) ** 2)
    ripple = 0.018 * math.sin(2 * math.pi * 5 * s) + 0.01 * math.sin(2 * math.pi * 11 * s + 0.7)
    return 0.28 + bulb + lip + ripple


def profile_curve(samples_per_unit=4000):
    """Dense polyline (r, y) from the bottom's outer edge up the outer wall,
    over the rim and down the inner wall."""
    pts = []
    base_r = wall_radius(FOOT)
    # foot: quarter circle from (base_r - FOOT, 0) to (base_r, FOOT), centre (base_r - FOOT, FOOT)
    n = 200
    for k in range(n):
        a = -math.pi / 2 + (math.pi / 2) * k / n
        pts.append((base_r - FOOT + FOOT * math.cos(a), FOOT + FOOT * math.sin(a)))
    # outer wall
    top = HEIGHT - RIM
    n = int((top - FOOT) * samples_per_unit)
    for k in range(n):
        y = FOOT + (top - FOOT) * k / n
        pts.append((wall_radius(y), y))
    # rim: half circle over the top, centre (wall_radius(top) - RIM, top)
    c = wall_radius(top) - RIM
    n = 400
    for k in range(n):
        a = math.pi * k / n
        pts.append((c + RIM * math.cos(a), top + RIM * math.sin(a)))
    # inner wall, parallel to the outer one, 2 * RIM inside
    n = int(INNER_DEPTH * samples_per_unit)
    for k in range(n + 1):
        y = top - INNER_DEPTH * k / n
        pts.append((wall_radius(y) - 2 * RIM, y))
    return pts


def resample(pts, spacing):
    """Points along the polyline at equal arc length (about `spacing`), with
    the unit tangent (dr, dy) and the arc length fraction at each."""
    acc = [0.0]
    for a, b in zip(pts, pts[1:]):
        acc.append(acc[-1] + math.hypot(b[0] - a[0], b[1] - a[1]))
    total = acc[-1]
    rows = max(2, int(round(total / spacing)))
    out = []
    j = 0
    for k in range(rows + 1):
        s = total * k / rows
        while j < len(pts) - 2 and acc[j + 1] < s:
            j += 1
        f = (s - acc[j]) / (acc[j + 1] - acc[j]) if acc[j + 1] > acc[j] else 0.0
        r = pts[j][0] + f * (pts[j + 1][0] - pts[j][0])
        y = pts[j][1] + f * (pts[j + 1][1] - pts[j][1])
        # tangent from a few samples either side (smooth across polyline joints)
        j0, j1 = max(0, j - 2), min(len(pts) - 1, j + 3)
        dr, dy = pts[j1][0] - pts[j0][0], pts[j1][1] - pts[j0][1]
        d = math.hypot(dr, dy)
        out.append((r, y, dr / d, dy / d, s / total))
    return out


def flute(theta):
    return 1.0 + FLUTE_DEPTH * math.cos(FLUTES * theta), -FLUTE_DEPTH * FLUTES * math.sin(FLUTES * theta)


def normalize(v):
    d = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (v[0] / d, v[1] / d, v[2] / d)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def build(around):
    spacing = 2 * math.pi * 0.55 / around
    prof = resample(profile_curve(), spacing)
    verts, normals, uvs, faces = [], [], [], []  # faces: ((v, vt), (v, vt), (v, vt)), vn = v

    # wall grid: row j along the profile, column i around
    rows = []
    for (r, y, tr, ty, s) in prof:
        row = []
        for i in range(around):
            th = 2 * math.pi * i / around
            f, df = flute(th)
            c, sn = math.cos(th), math.sin(th)
            p = (r * f * c, y, r * f * sn)
            d_t = (tr * f * c, ty, tr * f * sn)                  # d/d(arc length)
            d_th = (r * (df * c - f * sn), 0.0, r * (df * sn + f * c))  # d/d(theta)
            n = normalize(cross(d_t, d_th))
            if r < 1e-9:
                n = (0.0, -1.0, 0.0)
            row.append(len(verts))
            verts.append(p)
            normals.append(n)
        rows.append(row)
    vt_rows = []
    for (r, y, tr, ty, s) in prof:
        vt_rows.append(len(uvs))
        for i in range(around + 1):
            uvs.append((i / around, s))
    for j in range(len(rows) - 1):
        for i in range(around):
            i1 = (i + 1) % around
            a, b, c, d = rows[j][i], rows[j + 1][i], rows[j + 1][i1], rows[j][i1]
            ta, tb, tc, td = vt_rows[j] + i, vt_rows[j + 1] + i, vt_rows[j + 1] + i + 1, vt_rows[j] + i + 1
            faces.append(((a, ta), (b, tb), (c, tc)))
            faces.append(((a, ta), (c, tc), (d, td)))

    # flat bottom: rings inward from the foot's first row, then a centre fan
    r0 = prof[0][0]
    outer = [(rows[0][i], 2 * math.pi * i / around) for i in range(around)]
    rings = [outer]
    k = 1
    while True:
        r = r0 - k * spacing * 0.9
        if r < spacing * 1.2:
            break
        n = max(8, int(round(2 * math.pi * r / spacing)))
        off = math.pi / n * (k % 2)
        ring = []
        for i in range(n):
            th = 2 * math.pi * i / n + off
            f, _ = flute(th)
            ring.append((len(verts), th))
            verts.append((r * f * math.cos(th), 0.0, r * f * math.sin(th)))
            normals.append((0.0, -1.0, 0.0))
        rings.append(ring)
        k += 1
    centre = len(verts)
    verts.append((0.0, 0.0, 0.0))
    normals.append((0.0, -1.0, 0.0))
    bottom_vt = {}

    def bvt(v):
        if v not in bottom_vt:
            x, _, z = verts[v]
            bottom_vt[v] = len(uvs)
            uvs.append((0.5 + x / (2.2 * r0), 0.5 + z / (2.2 * r0)))
        return bottom_vt[v]

    bottom = []
    for A, B in zip(rings, rings[1:]):
        na, nb = len(A), len(B)
        ia = ib = 0
        # zip two rings by angle (B's angles shifted so both start near 0)
        while ia < na or ib < nb:
            ta = A[(ia + 1) % na][1] + (2 * math.pi if ia + 1 >= na else 0.0)
            tb = B[(ib + 1) % nb][1] + (2 * math.pi if ib + 1 >= nb else 0.0)
            if ib >= nb or (ia < na and ta <= tb):
                bottom.append((A[ia % na][0], A[(ia + 1) % na][0], B[ib % nb][0]))
                ia += 1
            else:
                bottom.append((A[ia % na][0], B[(ib + 1) % nb][0], B[ib % nb][0]))
                ib += 1
    last = rings[-1]
    for i in range(len(last)):
        bottom.append((last[i][0], last[(i + 1) % len(last)][0], centre))
    for tri in bottom:
        faces.append(tuple((v, bvt(v)) for v in tri))

    # orient every triangle counter-clockwise seen from its vertices' normals
    oriented = []
    for f in faces:
        p = [verts[v] for v, _ in f]
        gn = cross(sub(p[1], p[0]), sub(p[2], p[0]))
        vn = [sum(normals[v][k] for v, _ in f) for k in range(3)]
        oriented.append(f if dot(gn, vn) >= 0 else (f[0], f[2], f[1]))
    return verts, normals, uvs, oriented, len(prof)


def main():
    args = sys.argv[1:]
    around = 180
    if "--around" in args:
        i = args.index("--around")
        around = int(args[i + 1])
        del args[i:i + 2]
    if args in (["-h"], ["--help"]):
        print(__doc__)
        sys.exit(0)
    # An unknown option is not an output file name (`--help` once became one).
    if len(args) != 1 or args[0].startswith("-") or around < 8:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    verts, normals, uvs, faces, nrows = build(around)
    with open(args[0], "w") as out:
        w = out.write
        w("# vase, exported by data/make_fine_mesh.py --around %d (subdivtrace)\n" % around)
        w("# %d vertices, %d triangles\n" % (len(verts), len(faces)))
        w("o vase\n")
        for p in verts:
            w("v %.6f %.6f %.6f\n" % p)
        for t in uvs:
            w("vt %.6f %.6f\n" % t)
        for n in normals:
            w("vn %.6f %.6f %.6f\n" % n)
        w("s 1\n")
        for f in faces:
            w("f " + " ".join("%d/%d/%d" % (v + 1, t + 1, v + 1) for v, t in f) + "\n")
    print("%s: %d vertices, %d triangles (%d around, %d rows along the profile)"
          % (args[0], len(verts), len(faces), around, nrows), file=sys.stderr)


if __name__ == "__main__":
    main()
