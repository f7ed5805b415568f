#!/usr/bin/env python3
"""Integration tests of the patched POV-Ray's subdivision_mesh primitive.

usage: povray_tests.py --povray BIN --include DIR --work DIR
                       [--cli BIN] [--source-dir DIR] TEST [TEST...]
       povray_tests.py --list

Each TEST renders small scenes (160x120, one thread unless stated) with the
patched povray, headless, and checks the result. Exit status: 0 pass, 1 fail,
77 skipped (something the test needs is missing). Only the standard library is
used: images are written as binary PPM (+FP) and compared here.
"""

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import time

SKIP = 77
WIDTH, HEIGHT = 160, 120


class Failure(Exception):
    pass


class Skip(Exception):
    pass


# ---------------------------------------------------------------------------
# Meshes


def icosahedron():
    """Vertices, faces (outward winding) and per-vertex normals/uvs of a unit
    icosahedron; rotated so that no face is seen edge-on by the camera."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    raw = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
           (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
           (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    norm = math.sqrt(1 + t * t)
    verts = [(x / norm, y / norm, z / norm) for x, y, z in raw]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
             (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
             (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
             (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    normals = list(verts)  # a sphere's normals: the angle-weighted ones too
    uvs = [(0.5 + math.atan2(z, x) / (2 * math.pi), math.acos(max(-1.0, min(1.0, y))) / math.pi)
           for x, y, z in verts]
    return verts, faces, normals, uvs


def fmt_vec(v):
    return "<" + ", ".join("%.17g" % c for c in v) + ">"


def mesh2_body(verts, faces, normals=None, uvs=None):
    """The inside of a mesh2 block; normals and uvs per vertex."""
    out = ["vertex_vectors { %d, %s }" % (len(verts), ", ".join(fmt_vec(v) for v in verts))]
    if normals:
        out.append("normal_vectors { %d, %s }" % (len(normals), ", ".join(fmt_vec(n) for n in normals)))
    if uvs:
        out.append("uv_vectors { %d, %s }" % (len(uvs), ", ".join(fmt_vec(u) for u in uvs)))
    out.append("face_indices { %d, %s }" % (len(faces), ", ".join("<%d, %d, %d>" % f for f in faces)))
    return "\n    ".join(out)


def write_obj(path, verts, faces):
    with open(path, "w") as f:
        for v in verts:
            f.write("v %.17g %.17g %.17g\n" % v)
        for a, b, c in faces:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


# ---------------------------------------------------------------------------
# Rendering and images

SCENE_HEADER = """#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 0.4, -4> look_at <0, 0, 0> angle 40 }
light_source { <4, 6, -5> rgb 1 }
light_source { <-6, 2, -3> rgb 0.3 shadowless }
background { rgb <0.15, 0.18, 0.25> }
"""


class Context:
    def __init__(self, args, name):
        absolute = lambda p: os.path.abspath(p) if p else p
        self.povray = absolute(args.povray)
        self.include = absolute(args.include)
        self.cli = absolute(args.cli)
        self.source_dir = absolute(args.source_dir)
        self.work = os.path.join(absolute(args.work), name)
        os.makedirs(self.work, exist_ok=True)
        if not (self.povray and os.access(self.povray, os.X_OK)):
            raise Skip("patched povray not built: %s" % self.povray)

    def path(self, name):
        return os.path.join(self.work, name)

    def render(self, name, scene, threads=1, expect_ok=True, extra=(), size=(WIDTH, HEIGHT)):
        """Writes scene to NAME.pov, renders NAME.ppm; returns (rc, stderr, image, seconds)."""
        pov = self.path(name + ".pov")
        out = self.path(name + ".ppm")
        with open(pov, "w") as f:
            f.write(scene)
        if os.path.exists(out):
            os.remove(out)
        cmd = [self.povray, "+I" + pov, "+O" + out, "+FP", "+W%d" % size[0], "+H%d" % size[1],
               "-D", "-V", "+WT%d" % threads, "+L" + self.include, "+L" + self.work]
        cmd += list(extra)
        start = time.monotonic()
        proc = subprocess.run(cmd, cwd=self.work, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              timeout=300)
        seconds = time.monotonic() - start
        err = proc.stderr.decode("utf-8", "replace") + proc.stdout.decode("utf-8", "replace")
        with open(self.path(name + ".log"), "w") as f:
            f.write(" ".join(cmd) + "\n" + err)
        image = None
        if proc.returncode == 0 and os.path.exists(out):
            image = read_ppm(out)
        if expect_ok and (proc.returncode != 0 or image is None):
            raise Failure("%s: povray exited %d\n%s" % (name, proc.returncode, tail(err)))
        print("  rendered %-28s %6.2f s" % (name, seconds))
        return proc.returncode, err, image, seconds


def tail(text, n=15):
    return "\n".join(text.strip().splitlines()[-n:])


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    # Header: P6, width, height, maxval, one whitespace; POV-Ray adds '#' comments
    # (software, render date) between the fields.
    m = re.match(rb"P6(?:\s+|#[^\n]*\n)+(\d+)(?:\s+|#[^\n]*\n)+(\d+)(?:\s+|#[^\n]*\n)+(\d+)\s", data)
    if not m:
        raise Failure("%s: not a binary PPM" % path)
    w, h, maxval = int(m.group(1)), int(m.group(2)), int(m.group(3))
    if maxval != 255:
        raise Failure("%s: expected 8-bit PPM, maxval %d" % (path, maxval))
    pixels = data[m.end():m.end() + w * h * 3]
    if len(pixels) != w * h * 3:
        raise Failure("%s: truncated" % path)
    return (w, h, pixels)


def compare(a, b):
    """(fraction of pixels whose largest channel difference exceeds 2/255,
    mean absolute channel difference in 1/255 units, largest difference)."""
    (wa, ha, pa), (wb, hb, pb) = a, b
    if (wa, ha) != (wb, hb):
        raise Failure("image sizes differ: %dx%d vs %dx%d" % (wa, ha, wb, hb))
    over = 0
    total = 0
    largest = 0
    for i in range(0, len(pa), 3):
        d = max(abs(pa[i] - pb[i]), abs(pa[i + 1] - pb[i + 1]), abs(pa[i + 2] - pb[i + 2]))
        total += abs(pa[i] - pb[i]) + abs(pa[i + 1] - pb[i + 1]) + abs(pa[i + 2] - pb[i + 2])
        if d > 2:
            over += 1
        largest = max(largest, d)
    n = wa * ha
    return over / n, total / (3.0 * n), largest


def differing_pixels(a, b):
    """Number of pixels that are not byte-identical."""
    return sum(1 for i in range(0, len(a[2]), 3) if a[2][i:i + 3] != b[2][i:i + 3])


def coverage(image, background):
    """Fraction of pixels that differ from the background colour by more than 2/255."""
    w, h, p = image
    hit = 0
    for i in range(0, len(p), 3):
        if max(abs(p[i + c] - background[c]) for c in range(3)) > 2:
            hit += 1
    return hit / (w * h)


BACKGROUND_8BIT = None  # measured from a render of the empty scene when needed


def assert_close(name, a, b, max_fraction, max_mean):
    fraction, mean, largest = compare(a, b)
    print("  %s: %.3f%% pixels differ by > 2/255, mean diff %.3f/255, max %d/255"
          % (name, 100 * fraction, mean, largest))
    if fraction > max_fraction or mean > max_mean:
        raise Failure("%s: images differ more than allowed (%.3f%% > %.3f%% or mean %.3f > %.3f)"
                      % (name, 100 * fraction, 100 * max_fraction, mean, max_mean))


# Tolerances for "the same surface as mesh2". POV-Ray's mesh2 stores vertices
# and normals in single precision (SNGL_VECT) and intersects in its own way;
# libsubdivtrace works in double. The difference moves a silhouette or a
# triangle edge by ~1e-7 of the object's size, which flips a pixel only where
# a pixel centre lies that close to an edge, and changes shading by far less
# than 1/255. So nearly every pixel must match to 2/255; 0.5% of the pixels
# (96 of 19200) may differ (edge pixels, and shadow-terminator pixels where a
# shadow ray grazes the surface), and the mean must stay under 0.5/255.
SAME_FRACTION = 0.005
SAME_MEAN = 0.5


# ---------------------------------------------------------------------------
# Tests

def ico_texture(finish="specular 0.4 roughness 0.02"):
    return ("texture { uv_mapping pigment { checker rgb <1, 0.55, 0.2> rgb <0.2, 0.4, 1> scale 0.125 } "
            "finish { %s } }" % finish)


def test_level0_equals_mesh2(ctx):
    """max_level 0 is the base mesh: the same picture as native mesh2 with the
    same vertices, normals and uvs (smooth shading, uv-mapped checker)."""
    verts, faces, normals, uvs = icosahedron()
    body = mesh2_body(verts, faces, normals, uvs)
    xform = "rotate <20, 30, 0> scale 1.2"
    native = SCENE_HEADER + "mesh2 { %s %s %s }\n" % (body, ico_texture(), xform)
    subdiv = SCENE_HEADER + "subdivision_mesh { mesh2 { %s } max_level 0 %s %s }\n" % (
        body, ico_texture(), xform)
    _, _, a, _ = ctx.render("native", native)
    _, _, b, _ = ctx.render("subdiv_level0", subdiv)
    assert_close("level 0 vs mesh2", a, b, SAME_FRACTION, SAME_MEAN)


def adaptive_scene(extra_objects=""):
    verts, faces, normals, uvs = icosahedron()
    body = mesh2_body(verts, faces, None, uvs)
    return (SCENE_HEADER +
            "plane { y, -1.3 pigment { checker rgb 0.9 rgb 0.3 } finish { reflection 0.25 } }\n"
            "subdivision_mesh { mesh2 { %s } max_level 6 tolerance 0.5 %s "
            "rotate <20, 30, 0> scale 1.2 }\n" % (body, ico_texture("specular 0.4 reflection 0.2"))
            + extra_objects)


def test_threads_identical(ctx):
    """Pixels do not depend on the thread count: +WT1 and +WT2 give identical
    images of an adaptive surface with reflections (secondary rays) and shadows."""
    scene = adaptive_scene()
    _, _, a, _ = ctx.render("wt1", scene, threads=1)
    _, _, b, _ = ctx.render("wt2", scene, threads=2)
    if a != b:
        fraction, mean, largest = compare(a, b)
        raise Failure("+WT1 and +WT2 differ: %.3f%% pixels, max %d/255" % (100 * fraction, largest))
    print("  +WT1 == +WT2 (byte-identical)")


def csg_test(ctx, op):
    """CSG `op` of the primitive (max_level 0) with a sphere matches the same
    CSG with a closed mesh2 (inside_vector set): all intersections and the
    inside test agree with POV-Ray's own."""
    verts, faces, normals, uvs = icosahedron()
    body = mesh2_body(verts, faces, normals, uvs)
    if op == "merge":
        mat = "pigment { rgbf <1, 0.55, 0.2, 0.6> } finish { specular 0.3 }"
    else:
        mat = "pigment { rgb <1, 0.55, 0.2> } finish { specular 0.3 }"
    other = "sphere { <0.55, 0.45, -0.6>, 0.7 }"
    native = SCENE_HEADER + "%s { mesh2 { %s inside_vector <0.3, 0.5, 0.81> } %s %s rotate <20, 30, 0> scale 1.2 }\n" % (
        op, body, other, mat)
    subdiv = SCENE_HEADER + "%s { subdivision_mesh { mesh2 { %s } max_level 0 } %s %s rotate <20, 30, 0> scale 1.2 }\n" % (
        op, body, other, mat)
    _, _, a, _ = ctx.render("native_" + op, native)
    _, _, b, _ = ctx.render("subdiv_" + op, subdiv)
    assert_close("%s vs mesh2" % op, a, b, SAME_FRACTION, SAME_MEAN)
    # The adaptive surface in the same CSG renders too (no reference to match).
    adaptive = subdiv.replace("max_level 0", "max_level 5 tolerance 1")
    ctx.render("adaptive_" + op, adaptive)


def test_csg_difference(ctx):
    csg_test(ctx, "difference")


def test_csg_intersection(ctx):
    csg_test(ctx, "intersection")


def test_csg_merge(ctx):
    csg_test(ctx, "merge")


def test_features(ctx):
    """A transformed (non-uniform scale, rotation, shear by matrix), textured,
    reflective and refractive instance, copies of one declared object with
    different transforms, and an inverse in a difference, all in one scene:
    renders without error, draws something, and the summary has our stats."""
    verts, faces, normals, uvs = icosahedron()
    body = mesh2_body(verts, faces, None, uvs)
    scene = (SCENE_HEADER +
             "plane { y, -1.2 pigment { checker rgb 0.9 rgb 0.3 } }\n"
             "#declare S = subdivision_mesh { mesh2 { %s } scheme loop max_level 6 tolerance 1 cache_mb 16 }\n"
             "object { S scale <0.6, 0.9, 0.6> rotate <10, 40, 0> matrix <1,0,0, 0.3,1,0, 0,0,1, 0,0,0> translate <-1.3, 0, 0.5>\n"
             "  %s }\n"
             "object { S scale 0.7 translate <0.1, -0.3, -0.4>\n"
             "  material { texture { pigment { rgbf <0.9, 1, 0.9, 0.85> } finish { reflection 0.1 specular 0.6 } }\n"
             "  interior { ior 1.5 } } }\n"
             "difference { box { <-0.5, -0.5, -0.5>, <0.5, 0.5, 0.5> } object { S inverse scale 0.65 }\n"
             "  pigment { rgb <0.3, 0.9, 0.4> } rotate y*25 translate <1.4, 0, 0.8> }\n"
             % (body, ico_texture("specular 0.4 reflection 0.3")))
    rc, err, image, _ = ctx.render("features", scene)
    if "Subdivision Mesh" not in err or "deepest level reached" not in err:
        raise Failure("render summary lacks the subdivision_mesh statistics:\n%s" % tail(err, 40))
    m = re.search(r"deepest level reached:\s+(-?\d+)", err)
    if not m or int(m.group(1)) < 1:
        raise Failure("expected adaptive refinement below level 0, summary says %s" % (m and m.group(1)))
    _, _, empty, _ = ctx.render("features_empty", SCENE_HEADER)
    bg = empty[2][0:3]
    cov = coverage(image, bg)
    print("  %.1f%% of the pixels show objects" % (100 * cov))
    if cov < 0.3:
        raise Failure("only %.1f%% of the image differs from the background" % (100 * cov))


def test_open_mesh(ctx):
    """An open mesh (the icosahedron without the five faces round one vertex)
    renders as a patch: visible from both sides, no inside."""
    verts, faces, normals, uvs = icosahedron()
    open_faces = [f for f in faces if 3 not in f]
    body = mesh2_body(verts, open_faces, None, uvs)
    scene = (SCENE_HEADER +
             "subdivision_mesh { mesh2 { %s } max_level 5 %s rotate x*70 scale 1.2 }\n" % (body, ico_texture()))
    rc, err, image, _ = ctx.render("open", scene)
    _, _, empty, _ = ctx.render("open_empty", SCENE_HEADER)
    cov = coverage(image, empty[2][0:3])
    print("  %.1f%% of the pixels show the open mesh" % (100 * cov))
    if cov < 0.1:
        raise Failure("open mesh not visible")


NO_MESH = object()  # marks a bad case whose block has no mesh2

BAD_CASES = {
    # name: (lines of the subdivision_mesh block after its mesh2 (or, with
    #        NO_MESH first, instead of it), 1-based line among them that the
    #        error must name, text the message must contain)
    "negative_tolerance": (["  tolerance -0.5"], 1, "tolerance must be positive"),
    "zero_tolerance": (["  tolerance 0"], 1, "tolerance must be positive"),
    "negative_max_level": (["  max_level -1"], 1, "max_level must be an integer"),
    "max_level_over_cap": (["  max_level {cap_plus_one}"], 1, "max_level must be an integer from 0 to {cap}"),
    "unknown_scheme": (["  scheme catmull"], 1, "Unknown subdivision scheme"),
    "unknown_refine": (["  refine fast"], 1, "Unknown subdivision_mesh refine rule 'fast': expected error or size"),
    "repeated_refine": (["  refine size", "  tolerance 2", "  refine error"], 3, "refine is given more than once"),
    "cache_mb_zero": (["  cache_mb 0"], 1, "cache_mb must be from 1 to 1048576 (it is 0)"),
    "cache_mb_huge": (["  cache_mb 1e30"], 1, "cache_mb must be from 1 to 1048576 (it is 1e+30)"),
    "empty_file_name": ([NO_MESH, '  file ""'], 1, "subdivision_mesh file name is empty"),
    "undeclared_identifier": ([NO_MESH, "  Not_Declared_Mesh"], 1, "undeclared identifier 'Not_Declared_Mesh'"),
    "not_a_mesh": ([NO_MESH, "  Ball"], 1, "'Ball' is another kind of object"),
    "repeated_scheme": (["  scheme loop", "  scheme butterfly"], 2, "scheme is given more than once"),
    "repeated_tolerance": (["  tolerance 1", "  max_level 3", "  tolerance 2"], 3,
                           "tolerance is given more than once"),
    "weld_and_no_weld": (["  weld 1e-6", "  no_weld"], 2, "no_weld is given more than once"),
    "negative_weld": (["  weld -1"], 1, "weld must be from 0 to 1 (it is -1)"),
    "texture_index_out_of_range": ("bad_texture", 0, "Texture index out of range"),
    "missing_file": (None, 0, "no_such_mesh.obj"),
    "index_out_of_range": ("bad_index", 0, "mesh2"),
}


def max_level_cap(ctx):
    header = os.path.join(ctx.source_dir or "", "libsubdivtrace/include/subdivtrace/tracer.h")
    try:
        with open(header) as f:
            m = re.search(r"k_max_level_cap\s*=\s*(\d+)", f.read())
        return int(m.group(1))
    except (OSError, AttributeError):
        raise Skip("cannot read k_max_level_cap from %s" % header)


def bad_case_test(ctx, name):
    """A bad subdivision_mesh is a parse error: povray exits non-zero and the
    message names the right line."""
    lines, rel_line, text = BAD_CASES[name]
    verts, faces, normals, uvs = icosahedron()
    cap = max_level_cap(ctx)
    text = text.format(cap=cap)
    head = SCENE_HEADER.splitlines()
    scene = list(head)
    scene.append("#declare Ball = sphere { 0, 1 }")
    scene.append("// the object under test")
    first = len(scene) + 1  # line number of "subdivision_mesh {"
    if lines is None:
        scene += ["subdivision_mesh {", '  file "no_such_mesh.obj"', "  pigment { rgb 1 }", "}"]
        expect_line = first + 1
    elif lines == "bad_index":
        bad_faces = faces[:-1] + [(0, 1, 12)]
        scene += ["subdivision_mesh {", "  mesh2 { %s }" % mesh2_body(verts, bad_faces).replace("\n", " "),
                  "  pigment { rgb 1 }", "}"]
        expect_line = first + 1
    elif lines == "bad_texture":
        body = mesh2_body(verts, faces).replace("\n", " ")
        body = body.replace("face_indices { 20, <0, 11, 5>", "texture_list { 1, texture { pigment { rgb 1 } } } "
                            "face_indices { 20, <0, 11, 5>, 1")
        scene += ["subdivision_mesh {", "  mesh2 { %s }" % body, "  pigment { rgb 1 }", "}"]
        expect_line = first + 1
    elif lines[0] is NO_MESH:
        scene += ["subdivision_mesh {"] + lines[1:] + ["  pigment { rgb 1 }", "}"]
        expect_line = first + rel_line
    else:
        scene += ["subdivision_mesh {", "  mesh2 { %s }" % mesh2_body(verts, faces).replace("\n", " ")]
        scene += [l.format(cap_plus_one=cap + 1) for l in lines]
        scene += ["  pigment { rgb 1 }", "}"]
        expect_line = first + 1 + rel_line
    rc, err, _, _ = ctx.render("bad_" + name, "\n".join(scene) + "\n", expect_ok=False)
    if rc == 0:
        raise Failure("povray accepted the bad scene (exit 0)")
    # POV-Ray wraps long messages at 80 columns; join the continuation lines.
    flat = re.sub(r"\n ", " ", err)
    m = re.search(r"line (\d+): Parse Error: ([^\n]*)", flat)
    if not m:
        raise Failure("no 'line N: Parse Error' message:\n%s" % tail(err))
    print("  exit %d, line %s: %s" % (rc, m.group(1), m.group(2)))
    if int(m.group(1)) != expect_line:
        raise Failure("error names line %s, expected %d" % (m.group(1), expect_line))
    if text not in m.group(2):
        raise Failure("message %r lacks %r" % (m.group(2), text))


def uniform_level_images(ctx, scheme, level, limit=False):
    """Renders native mesh2 of the uniform level-K mesh (exported by the CLI,
    with the level's normals; with `limit`, its vertices pushed to the limit
    surface) and subdivision_mesh with max_level K and a tiny tolerance (every
    ray refines to level K). Returns both images."""
    if not (ctx.cli and os.access(ctx.cli, os.X_OK)):
        raise Skip("subdivtrace CLI not built: %s" % ctx.cli)
    verts, faces, normals, uvs = icosahedron()
    obj = ctx.path("ico.obj")
    write_obj(obj, verts, faces)
    inc = ctx.path("ico_%s_l%d%s.inc" % (scheme, level, "_limit" if limit else ""))
    ident = "Ico_%s_L%d" % (scheme.capitalize(), level)
    cmd = [ctx.cli, "export-mesh2", obj, "-o", inc, "--scheme", scheme, "--levels", str(level),
           "--name", ident] + (["--limit"] if limit else [])
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=120)
    if proc.returncode != 0:
        raise Failure("%s failed (%d):\n%s" % (" ".join(cmd), proc.returncode,
                                               tail(proc.stdout.decode("utf-8", "replace"))))
    mat = "pigment { rgb <1, 0.55, 0.2> } finish { specular 0.4 roughness 0.02 }"
    xform = "rotate <20, 30, 0> scale 1.2"
    native = SCENE_HEADER + '#include "%s"\nobject { %s %s %s }\n' % (os.path.basename(inc), ident, mat, xform)
    subdiv = SCENE_HEADER + ('subdivision_mesh { file "ico.obj" scheme %s max_level %d tolerance 1e-6 %s %s }\n'
                             % (scheme, level, mat, xform))
    tag = "%s_l%d%s" % (scheme, level, "_limit" if limit else "")
    _, _, a, _ = ctx.render("native_" + tag, native)
    _, err, b, _ = ctx.render("subdiv_" + tag, subdiv)
    m = re.search(r"deepest level reached:\s+(-?\d+)", err)
    if m and int(m.group(1)) != level:
        raise Failure("deepest level reached is %s, expected %d" % (m.group(1), level))
    return a, b


def uniform_level_test(ctx, scheme, level=2):
    """max_level K with a tiny tolerance is the picture of the uniform level-K
    mesh as native mesh2 (interpolating schemes: the drawn corners are the
    level-K vertices; Loop: the tracer draws a leaf's corners at their limit
    points, so the export is pushed to the limit with --limit)."""
    a, b = uniform_level_images(ctx, scheme, level, limit=(scheme == "loop"))
    assert_close("max_level %d (%s) vs uniform mesh2" % (level, scheme), a, b, SAME_FRACTION, SAME_MEAN)


def test_loop_converges_to_uniform(ctx):
    """Loop's level-K control mesh converges to the limit surface the tracer
    draws: the picture of max_level K approaches that of the uniform level-K
    mesh2 as K grows (measured 24%, 7.4%, 0.8% of pixels differing at K = 1,
    2, 3), and is close at K = 3."""
    fractions = []
    for level in (1, 2, 3):
        a, b = uniform_level_images(ctx, "loop", level)
        fraction, mean, largest = compare(a, b)
        print("  level %d: %.3f%% pixels differ, mean %.3f/255" % (level, 100 * fraction, mean))
        fractions.append(fraction)
    if not (fractions[0] > fractions[1] > fractions[2]):
        raise Failure("differences do not shrink with the level: %s" % fractions)
    if fractions[2] > 0.02:
        raise Failure("level 3 still differs on %.2f%% of the pixels (> 2%%)" % (100 * fractions[2]))


def test_no_shadow_acne(ctx):
    """POV-Ray spawns shadow rays at the hit point itself (no offset; it only
    ignores depths below MIN_ISECT_DEPTH). On a convex adaptive surface no
    shadow ray may find the surface it left: the image with shadows equals the
    one with no_shadow (pixels whose diffuse term is already ~0 at the
    terminator aside: at most 0.1% may differ by more than 2/255)."""
    verts, faces, normals, uvs = icosahedron()
    body = mesh2_body(verts, faces)
    images = []
    for tag, flag in (("shadows", ""), ("no_shadow", "no_shadow")):
        scene = (SCENE_HEADER.replace("shadowless", "") +
                 "subdivision_mesh { mesh2 { %s } max_level 6 tolerance 1 pigment { rgb 0.8 } "
                 "finish { ambient 0.05 diffuse 0.9 } %s scale 1.2 }\n" % (body, flag))
        images.append(ctx.render("acne_" + tag, scene, threads=2)[2])
    assert_close("shadows vs no_shadow", images[0], images[1], 0.001, 0.1)


# Flat-lit scenes: no shadows, no reflections, so a pixel depends only on the
# object it shows (used to compose solo renders into the expected image).
FLAT_HEADER = """#version 3.7;
global_settings { assumed_gamma 1.0 }
light_source { <4, 6, -5> rgb 1 shadowless }
background { rgb <0.15, 0.18, 0.25> }
"""


def compose(images, empty):
    """Per pixel: the first image that differs from the empty render there."""
    w, h, bg = empty
    out = bytearray(bg)
    for i in range(0, len(bg), 3):
        for _, _, p in images:
            if p[i:i + 3] != bg[i:i + 3]:
                out[i:i + 3] = p[i:i + 3]
                break
    return (w, h, bytes(out))


def deepest_level(err):
    m = re.search(r"deepest level reached:\s+(-?\d+)", err)
    if not m:
        raise Failure("render summary lacks 'deepest level reached'")
    return int(m.group(1))


def copies_test(ctx, camera):
    """Two copies of one declared surface at scales 1 and 8 are each refined
    for their own footprint: rendered together, each copy's pixels equal
    those of the copy rendered alone, and alone they reach different levels
    (the larger one covers more pixels and refines deeper)."""
    verts, faces, normals, uvs = icosahedron()
    decl = ("#declare S = subdivision_mesh { mesh2 { %s } max_level 10 tolerance 1 "
            "pigment { rgb <1, 0.55, 0.2> } finish { specular 0.4 } }\n" % mesh2_body(verts, faces))
    small = "object { S rotate <20, 30, 0> translate <-10, 3, 0> }\n"
    large = "object { S rotate <20, 30, 0> scale 8 translate <4, 0, 10> }\n"
    head = FLAT_HEADER + camera + decl
    tag = camera.split()[2]
    _, _, both, _ = ctx.render("both_" + tag, head + small + large)
    _, err_small, alone_small, _ = ctx.render("small_" + tag, head + small)
    _, err_large, alone_large, _ = ctx.render("large_" + tag, head + large)
    _, _, empty, _ = ctx.render("empty_" + tag, head)
    levels = deepest_level(err_small), deepest_level(err_large)
    print("  deepest level alone: scale 1 -> %d, scale 8 -> %d" % levels)
    if not levels[1] > levels[0]:
        raise Failure("the scale-8 copy does not refine deeper than the scale-1 copy: %s" % (levels,))
    expected = compose([alone_small, alone_large], empty)
    fraction, mean, largest = compare(both, expected)
    differ = differing_pixels(both, expected)
    print("  together vs each alone: %d pixels differ" % differ)
    if differ:
        raise Failure("copies rendered together differ from each alone in %d pixels (max %d/255)"
                      % (differ, largest))


def test_copies_own_view_perspective(ctx):
    copies_test(ctx, "camera { perspective location <0, 2, -40> look_at <0, 0, 0> angle 40 }\n")


def test_copies_own_view_orthographic(ctx):
    copies_test(ctx, "camera { orthographic location <0, 2, -40> look_at <0, 0, 0> "
                     "right x*34 up y*25.5 }\n")


TEXTURE_LIST = ("texture_list { 3, texture { pigment { rgb <1, 0.2, 0.1> } finish { specular 0.3 } }, "
                "texture { pigment { rgb <0.2, 0.9, 0.3> } }, "
                "texture { uv_mapping pigment { checker rgb <0.2, 0.3, 1> rgb 1 scale 0.125 } } }")


def textured_body(verts, faces, uvs, per_vertex):
    """mesh2 body (vertex normals = the sphere's) with a texture_list:
    per_vertex gives each face its corners' indices (vertex index mod 3,
    blended across the face), else one index per face (face index mod 3);
    half the faces of the one-index kind have none."""
    parts = ["vertex_vectors { %d, %s }" % (len(verts), ", ".join(fmt_vec(v) for v in verts)),
             "normal_vectors { %d, %s }" % (len(verts), ", ".join(fmt_vec(v) for v in verts))]
    if uvs:
        parts.append("uv_vectors { %d, %s }" % (len(uvs), ", ".join(fmt_vec(u) for u in uvs)))
    parts.append(TEXTURE_LIST)
    items = []
    for i, f in enumerate(faces):
        if per_vertex:
            items.append("<%d, %d, %d>, %d, %d, %d" % (f + tuple(v % 3 for v in f)))
        elif i % 2:
            items.append("<%d, %d, %d>, %d" % (f + (i % 3,)))
        else:
            items.append("<%d, %d, %d>" % f)
    parts.append("face_indices { %d, %s }" % (len(faces), ", ".join(items)))
    return "\n    ".join(parts)


def level0_pair(ctx, name, body, mods, native_extra="", header=SCENE_HEADER):
    """Renders mesh2 { body } and subdivision_mesh { mesh2 { body } max_level 0 }
    with the same modifiers; asserts they match like level0_equals_mesh2."""
    native = header + "mesh2 { %s %s %s }\n" % (body, native_extra, mods)
    subdiv = header + "subdivision_mesh { mesh2 { %s %s } max_level 0 %s }\n" % (body, native_extra, mods)
    _, _, a, _ = ctx.render("native_" + name, native)
    _, _, b, _ = ctx.render("subdiv_" + name, subdiv)
    differ = differing_pixels(a, b)
    print("  %s: %d of %d pixels not identical" % (name, differ, WIDTH * HEIGHT))
    assert_close("%s: level 0 vs mesh2" % name, a, b, SAME_FRACTION, SAME_MEAN)


def test_texture_list_equals_mesh2(ctx):
    """texture_list with one texture index per face (the rest take the
    object's texture) and with three (blended across the face), and
    uv_mapping: at max_level 0 the same picture as mesh2."""
    verts, faces, normals, uvs = icosahedron()
    mods = "pigment { rgb 0.7 } rotate <20, 30, 0> scale 1.2"
    level0_pair(ctx, "per_face", textured_body(verts, faces, uvs, False), mods)
    level0_pair(ctx, "per_vertex", textured_body(verts, faces, uvs, True), mods)


# POV-Ray's own scenes/objects/mesh2.pov, "Mesh_B": a cube with a pyramid on
# each face whose faces do not agree on a winding (mesh2 does not care), with
# uv_vectors and uv_indices and no normals.
STELLATED_CUBE_VERTS = [(-1, -1, -1), (1, -1, -1), (-1, 1, -1), (1, 1, -1),
                        (-1, -1, 1), (1, -1, 1), (-1, 1, 1), (1, 1, 1),
                        (-1.5, 0, 0), (1.5, 0, 0), (0, -1.5, 0), (0, 1.5, 0), (0, 0, -1.5), (0, 0, 1.5)]
STELLATED_CUBE_FACES = [(8, 0, 2), (8, 0, 4), (8, 6, 2), (8, 6, 4), (9, 1, 3), (9, 1, 5),
                        (9, 7, 3), (9, 7, 5), (10, 0, 1), (10, 0, 4), (10, 5, 1), (10, 5, 4),
                        (11, 2, 3), (11, 2, 6), (11, 7, 3), (11, 7, 6), (12, 0, 1), (12, 0, 2),
                        (12, 3, 1), (12, 3, 2), (13, 4, 5), (13, 4, 6), (13, 7, 5), (13, 7, 6)]
STELLATED_CUBE_UVS = [(0, 0), (1, 1), (1, -1), (-1, 1), (-1, -1)]
STELLATED_CUBE_UV_INDICES = [(0, 1, 2), (0, 1, 3), (0, 4, 2), (0, 4, 3)] * 6


def outward(faces, verts):
    """The same faces, each wound so that its normal points away from the origin."""
    out = []
    for a, b, c in faces:
        pa, pb, pc = verts[a], verts[b], verts[c]
        u = [pb[i] - pa[i] for i in range(3)]
        v = [pc[i] - pa[i] for i in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        out.append((a, b, c) if sum(n[i] * (pa[i] + pb[i] + pc[i]) for i in range(3)) > 0 else (a, c, b))
    return out


def stellated_cube_body(faces, uv_indices, normals=False):
    """mesh2 body; every third face blends three textures of TEXTURE_LIST (so
    a face the library turns must turn its texture indices too), the others
    take the object's uv-mapped texture."""
    verts = STELLATED_CUBE_VERTS
    parts = ["vertex_vectors { %d, %s }" % (len(verts), ", ".join(fmt_vec(v) for v in verts))]
    if normals:
        # The angle-weighted normals, known by symmetry: along each apex's
        # axis and each cube corner's diagonal.
        unit = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
        parts.append("normal_vectors { %d, %s }" % (len(unit), ", ".join(fmt_vec(n) for n in unit)))
    parts.append("uv_vectors { %d, %s }" % (len(STELLATED_CUBE_UVS),
                                            ", ".join(fmt_vec(u) for u in STELLATED_CUBE_UVS)))
    parts.append(TEXTURE_LIST)
    items = []
    for i, f in enumerate(faces):
        items.append("<%d, %d, %d>, %d, %d, %d" % (f + tuple(v % 3 for v in f)) if i % 3 == 0
                     else "<%d, %d, %d>" % f)
    parts.append("face_indices { %d, %s }" % (len(faces), ", ".join(items)))
    parts.append("uv_indices { %d, %s }" % (len(uv_indices), ", ".join("<%d, %d, %d>" % u for u in uv_indices)))
    return "\n    ".join(parts)


def test_mixed_winding(ctx):
    """The mixed-winding cube of POV-Ray's mesh2.pov: the library turns the
    faces that disagree with their neighbours (with their uvs and texture
    indices), so at max_level 0 it is mesh2 with the normals the symmetry
    gives (before, half of each apex's triangles cancelled the other half's
    normals and the refined cube came out star-shaped), inline and declared;
    refined, it is the same surface as the cube written with one winding."""
    faces, uvi = STELLATED_CUBE_FACES, STELLATED_CUBE_UV_INDICES
    mods = ("texture { uv_mapping pigment { spiral2 8 color_map { [0.5 rgb 1] [0.5 rgb <0, 0, 0.4>] } "
            "scale 0.8 } finish { specular 0.3 } } scale 0.8 rotate <20, 30, 0>")
    native = SCENE_HEADER + "mesh2 { %s %s }\n" % (stellated_cube_body(faces, uvi, normals=True), mods)
    _, _, expected, _ = ctx.render("native_smooth", native)
    body = stellated_cube_body(faces, uvi)
    inline = SCENE_HEADER + "subdivision_mesh { mesh2 { %s } max_level 0 %s }\n" % (body, mods)
    _, err, b, _ = ctx.render("subdiv_inline0", inline)
    assert_close("inline max_level 0 vs mesh2 with the symmetric normals", b, expected, SAME_FRACTION, SAME_MEAN)
    if "turned 12 of 24 triangles" not in " ".join(err.split()):  # POV-Ray wraps its warnings
        raise Failure("expected the warning that 12 of 24 triangles were turned:\n" + tail(err))
    declared = SCENE_HEADER + "#declare M = mesh2 { %s }\nsubdivision_mesh { M max_level 0 %s }\n" % (body, mods)
    _, _, b, _ = ctx.render("subdiv_declared0", declared)
    assert_close("declared max_level 0 vs mesh2 with the symmetric normals", b, expected, SAME_FRACTION, SAME_MEAN)

    one_winding = outward(faces, STELLATED_CUBE_VERTS)
    uv_one_winding = [u if f == g else (u[0], u[2], u[1]) for f, g, u in zip(faces, one_winding, uvi)]
    refined = "max_level 5 tolerance 0.5"
    _, _, mixed, _ = ctx.render("subdiv_mixed5", SCENE_HEADER + "subdivision_mesh { mesh2 { %s } %s %s }\n"
                                % (body, refined, mods))
    _, err, same, _ = ctx.render("subdiv_outward5", SCENE_HEADER + "subdivision_mesh { mesh2 { %s } %s %s }\n"
                                 % (stellated_cube_body(one_winding, uv_one_winding), refined, mods))
    if "turned" in err:
        raise Failure("the cube written with one winding was turned:\n" + tail(err))
    assert_close("refined: mixed winding vs one winding", mixed, same, SAME_FRACTION, SAME_MEAN)


def test_uv_without_uv_vectors_equals_mesh2(ctx):
    """Without uv_vectors mesh2's uv is (0, 0) everywhere; so is ours: a
    uv-mapped gradient renders the same at max_level 0."""
    verts, faces, normals, uvs = icosahedron()
    mods = ("texture { uv_mapping pigment { gradient <1, 1, 0> color_map { [0 rgb <1, 0, 0>] "
            "[1 rgb <0, 0, 1>] } translate 0.5 } } rotate <20, 30, 0> scale 1.2")
    level0_pair(ctx, "no_uv", mesh2_body(verts, faces, normals), mods)


def test_inside_vector_equals_mesh2(ctx):
    """inside_vector as mesh2 uses it: an open mesh with one becomes a solid
    whose inside is the parity of crossings along it (CSG intersection with
    a box), the same picture as mesh2 with the same inside_vector."""
    verts, faces, normals, uvs = icosahedron()
    open_faces = [f for f in faces if 3 not in f]
    # Gouraud normals of the open mesh: what the normal scheme computes.
    body = mesh2_body(verts, open_faces, gouraud_normals(verts, open_faces))
    mat = "pigment { rgb <1, 0.55, 0.2> } finish { specular 0.3 }"
    xform = "rotate <20, 30, 0> scale 1.2"
    box = "box { <-0.6, -2, -2>, <2, 2, 2> }"
    native = SCENE_HEADER + "intersection { mesh2 { %s inside_vector <0.3, 0.5, 0.81> } %s %s %s }\n" % (
        body, box, mat, xform)
    subdiv = SCENE_HEADER + ("intersection { subdivision_mesh { mesh2 { %s inside_vector <0.3, 0.5, 0.81> } "
                             "max_level 0 } %s %s %s }\n" % (body, box, mat, xform))
    _, _, a, _ = ctx.render("native_inside_vector", native)
    _, _, b, _ = ctx.render("subdiv_inside_vector", subdiv)
    assert_close("inside_vector vs mesh2", a, b, SAME_FRACTION, SAME_MEAN)


def largest_jump(image, background):
    """Largest channel difference between horizontally or vertically adjacent
    pixels that both show the object (not the background)."""
    w, h, p = image

    def on(i):
        return max(abs(p[i + c] - background[c]) for c in range(3)) > 2
    largest = 0
    for y in range(h - 1):
        for x in range(w - 1):
            i = 3 * (y * w + x)
            if not on(i):
                continue
            for j in (i + 3, i + 3 * w):
                if on(j):
                    largest = max(largest, max(abs(p[i + c] - p[j + c]) for c in range(3)))
    return largest


def test_texture_blend_continuous(ctx):
    """At higher levels the blended texture_list stays continuous across base
    edges (weights are barycentric on the base triangle at every level):
    lit by ambient light only, no two adjacent pixels of the surface differ
    by more than a small step, while one texture per face (the control)
    shows jumps at the base edges."""
    verts, faces, normals, uvs = icosahedron()
    flat = FLAT_HEADER.replace("rgb 1 shadowless", "rgb 0") + \
        "camera { location <0, 0.4, -4> look_at <0, 0, 0> angle 40 }\n"
    lists = {"blend": textured_body(verts, faces, None, True),
             "per_face": textured_body(verts, faces, None, False)}
    flat_list = ("texture_list { 3, texture { pigment { rgb <1, 0.2, 0.1> } finish { ambient 1 diffuse 0 } }, "
                 "texture { pigment { rgb <0.2, 0.9, 0.3> } finish { ambient 1 diffuse 0 } }, "
                 "texture { pigment { rgb <0.2, 0.3, 1> } finish { ambient 1 diffuse 0 } } }")
    _, _, empty, _ = ctx.render("jump_empty", flat)
    jumps = {}
    for name, body in lists.items():
        body = body.replace(TEXTURE_LIST, flat_list)
        scene = flat + ("subdivision_mesh { mesh2 { %s } max_level 5 tolerance 1 "
                        "texture { pigment { rgb 0.5 } finish { ambient 1 diffuse 0 } } "
                        "rotate <20, 30, 0> scale 1.2 }\n" % body)
        _, err, image, _ = ctx.render("jump_" + name, scene)
        jumps[name] = largest_jump(image, empty[2][0:3])
        print("  %s: deepest level %d, largest step between adjacent pixels %d/255"
              % (name, deepest_level(err), jumps[name]))
    if jumps["per_face"] < 100:
        raise Failure("control without blending shows no jump (%d/255): test cannot see one" % jumps["per_face"])
    if jumps["blend"] > 40:
        raise Failure("blended textures jump by %d/255 between adjacent pixels" % jumps["blend"])


def test_declared_mesh(ctx):
    """subdivision_mesh { MESH_IDENTIFIER max_level 0 } takes a mesh declared
    with mesh2 (normals, uvs, texture_list, its transformation) or with mesh
    (smooth_triangle, some with textures): the same picture as the declared
    mesh itself."""
    verts, faces, normals, uvs = icosahedron()
    body = textured_body(verts, faces, uvs, True)
    header = SCENE_HEADER + "#declare M2 = mesh2 { %s rotate <20, 30, 0> }\n" % body
    mods = "pigment { rgb 0.7 } scale 1.2"
    _, _, a, _ = ctx.render("native_decl_mesh2", header + "object { M2 %s }\n" % mods)
    _, _, b, _ = ctx.render("subdiv_decl_mesh2", header + "subdivision_mesh { M2 max_level 0 %s }\n" % mods)
    assert_close("declared mesh2", a, b, SAME_FRACTION, SAME_MEAN)
    # Smooth triangles with the sphere's normals (flat ones would differ:
    # the library's normal scheme computes its own normals).
    tris = []
    for i, (p, q, r) in enumerate(faces):
        tris.append("smooth_triangle { %s, %s, %s, %s, %s, %s %s }" % (
            fmt_vec(verts[p]), fmt_vec(normals[p]), fmt_vec(verts[q]), fmt_vec(normals[q]),
            fmt_vec(verts[r]), fmt_vec(normals[r]), "texture { T%d }" % (i % 3) if i % 2 else ""))
    header = (SCENE_HEADER +
              "#declare T0 = texture { pigment { rgb <1, 0.2, 0.1> } }\n"
              "#declare T1 = texture { pigment { rgb <0.2, 0.9, 0.3> } }\n"
              "#declare T2 = texture { pigment { rgb <0.2, 0.3, 1> } }\n"
              "#declare M1 = mesh { %s inside_vector <0, 0, 1> }\n" % "\n  ".join(tris))
    mods = "pigment { rgb 0.7 } rotate <20, 30, 0> scale 1.2"
    _, _, a, _ = ctx.render("native_decl_mesh", header + "object { M1 %s }\n" % mods)
    _, _, b, _ = ctx.render("subdiv_decl_mesh", header + "subdivision_mesh { M1 max_level 0 %s }\n" % mods)
    assert_close("declared mesh", a, b, SAME_FRACTION, SAME_MEAN)


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if t and t[0] == "v":
                verts.append(tuple(float(x) for x in t[1:4]))
            elif t and t[0] == "f":
                faces.append(tuple(int(x.split("/")[0]) - 1 for x in t[1:4]))
    return verts, faces


def gouraud_normals(verts, faces):
    """Angle-weighted vertex normals (the normal scheme's level-0 normals)."""
    def sub(a, b):
        return (a[0] - b[0], a[1] - b[1], a[2] - b[2])

    def unit(a):
        n = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
        return (a[0] / n, a[1] / n, a[2] / n)
    sums = [[0.0, 0.0, 0.0] for _ in verts]
    for f in faces:
        e1, e2 = sub(verts[f[1]], verts[f[0]]), sub(verts[f[2]], verts[f[0]])
        n = unit((e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]))
        for i in range(3):
            a = unit(sub(verts[f[(i + 1) % 3]], verts[f[i]]))
            b = unit(sub(verts[f[(i + 2) % 3]], verts[f[i]]))
            angle = math.acos(max(-1.0, min(1.0, a[0] * b[0] + a[1] * b[1] + a[2] * b[2])))
            for c in range(3):
                sums[f[i]][c] += angle * n[c]
    return [unit(tuple(s)) if any(s) else (0.0, 0.0, 1.0) for s in sums]  # unused vertices: any


ACNE_SIZE = (320, 240)
ACNE_HEADER = """#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 1.5, -6.5> look_at <0, 0.25, 0> right x*4/3 angle 40 }
#ifndef (No_Light) light_source { <4, 6, -5> rgb 1 } #end
background { rgb <0.15, 0.18, 0.25> }
"""
ACNE_LOOK = "texture { pigment { rgb 0.8 } finish { ambient 0.1 diffuse 0.8 } } rotate y*-30"


def shadow_pixels(ctx, name, obj):
    """Renders obj lit, with no_shadow, and without the light; returns the
    set of pixels darker than the no_shadow render (by > 2/255) and the set
    of 'dark' pixels: those where the shadow removed over half of what the
    light adds (> 10/255) there."""
    images = []
    for tag, flag, extra in (("shadow", "", ()), ("no_shadow", "no_shadow", ()),
                             ("unlit", "", ("Declare=No_Light=1",))):
        scene = ACNE_HEADER + obj.replace("LOOK", ACNE_LOOK + " " + flag) + "\n"
        images.append(ctx.render("%s_%s" % (name, tag), scene, extra=extra, size=ACNE_SIZE)[2])
    lit, free, unlit = [[max(p[i:i + 3]) for i in range(0, len(p), 3)] for _, _, p in images]
    darker = {i for i in range(len(lit)) if free[i] - lit[i] > 2}
    dark = {i for i in darker if free[i] - unlit[i] > 10 and free[i] - lit[i] > 0.5 * (free[i] - unlit[i])}
    print("  %s: %d dark pixels, %d darker than no_shadow" % (name, len(dark), len(darker)))
    return dark, darker


def test_shadow_acne_nonconvex(ctx):
    """Secondary rays ignore the surface they left (within the hit's error
    bound), on a non-convex mesh (data/bunny_lowpoly.obj, 320x240): at
    max_level 0 the shadowed pixels are exactly those of mesh2 with the same
    vertex normals (smooth shading shadows itself at the terminator there,
    in mesh2 too); at max_level 2 with every ray refined to level 2, and
    adaptively at max_level 6, every pixel darker than the no_shadow render
    is also shadowed in the uniform level-2 mesh2 (a 1-pixel margin for the
    adaptive surface, whose silhouette differs): no shadow that the surface
    cannot explain."""
    if not (ctx.cli and os.access(ctx.cli, os.X_OK)):
        raise Skip("subdivtrace CLI not built: %s" % ctx.cli)
    obj = os.path.join(ctx.source_dir or "", "data", "bunny_lowpoly.obj")
    if not os.path.exists(obj):
        raise Skip("no %s" % obj)
    verts, faces = read_obj(obj)
    body = mesh2_body(verts, faces, gouraud_normals(verts, faces))
    inc = ctx.path("bunny_l2.inc")
    proc = subprocess.run([ctx.cli, "export-mesh2", obj, "-o", inc, "--levels", "2", "--name", "Bunny_L2"],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=120)
    if proc.returncode != 0:
        raise Failure("export-mesh2 failed:\n%s" % tail(proc.stdout.decode("utf-8", "replace")))
    subdiv = 'subdivision_mesh { file "%s" %%s LOOK }' % obj

    native0, _ = shadow_pixels(ctx, "mesh2_level0", "mesh2 { %s LOOK }" % body)
    ours0, _ = shadow_pixels(ctx, "subdiv_level0", subdiv % "max_level 0")
    if ours0 != native0:
        raise Failure("max_level 0: %d dark pixels, mesh2 has %d (%d not in mesh2's)"
                      % (len(ours0), len(native0), len(ours0 - native0)))

    _, native2 = shadow_pixels(ctx, "mesh2_level2", '#include "bunny_l2.inc"\nobject { Bunny_L2 LOOK }')
    _, ours2 = shadow_pixels(ctx, "subdiv_level2", subdiv % "max_level 2 tolerance 1e-6")
    unexplained = ours2 - native2
    w = ACNE_SIZE[0]
    margin = {j for i in native2 for j in (i - w - 1, i - w, i - w + 1, i - 1, i, i + 1, i + w - 1, i + w, i + w + 1)}
    _, ours6 = shadow_pixels(ctx, "subdiv_level6", subdiv % "max_level 6 tolerance 1")
    unexplained6 = ours6 - margin
    print("  shadowed where mesh2 of the same surface is not: level 2: %d, adaptive level 6: %d"
          % (len(unexplained), len(unexplained6)))
    if unexplained or unexplained6:
        raise Failure("%d (level 2) and %d (max_level 6) pixels darker than no_shadow without a shadow "
                      "in mesh2" % (len(unexplained), len(unexplained6)))


def patch_split_sphere():
    """An icosphere (the icosahedron split twice, vertices on the unit sphere)
    twice: with shared vertices, and cut into 20 patches (one per icosahedron
    face) each with its own copy of its vertices, as exporters write seams.
    Returns (shared verts, shared faces, split verts, split faces)."""
    verts, faces, _, _ = icosahedron()
    verts = list(verts)
    patch_of = list(range(len(faces)))
    for _ in range(2):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = [(verts[a][c] + verts[b][c]) / 2 for c in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                verts.append(tuple(x / n for x in p))
                mid[key] = len(verts) - 1
            return mid[key]
        new_faces, new_patch = [], []
        for (a, b, c), patch in zip(faces, patch_of):
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new_faces += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
            new_patch += [patch] * 4
        faces, patch_of = new_faces, new_patch
    split_verts, split_faces = [], []
    for patch in range(20):
        local = {}
        for f, p in zip(faces, patch_of):
            if p != patch:
                continue
            for v in f:
                if v not in local:
                    local[v] = len(split_verts)
                    split_verts.append(verts[v])
            split_faces.append(tuple(local[v] for v in f))
    return verts, faces, split_verts, split_faces


def test_weld_patch_split_sphere(ctx):
    """Coincident vertices are welded (issue 11): a sphere cut into patches
    with duplicated seam vertices renders pixel for pixel like the same
    sphere with shared vertices, in every scheme; with no_weld the seams
    tear (the control: pixels differ)."""
    shared_v, shared_f, split_v, split_f = patch_split_sphere()
    print("  shared: %d vertices, split: %d vertices, %d faces" % (len(shared_v), len(split_v), len(split_f)))
    mat = "pigment { rgb <1, 0.55, 0.2> } finish { specular 0.4 roughness 0.02 }"
    for scheme in ("normal", "loop", "butterfly"):
        images = {}
        for tag, v, f, opt in (("shared", shared_v, shared_f, ""), ("split", split_v, split_f, ""),
                               ("no_weld", split_v, split_f, "no_weld")):
            scene = SCENE_HEADER + ("subdivision_mesh { mesh2 { %s } scheme %s max_level 5 tolerance 1 %s %s "
                                    "rotate <20, 30, 0> scale 1.2 }\n" % (mesh2_body(v, f), scheme, opt, mat))
            images[tag] = ctx.render("%s_%s" % (tag, scheme), scene)[2]
        welded = differing_pixels(images["shared"], images["split"])
        torn = differing_pixels(images["shared"], images["no_weld"])
        print("  %s: split vs shared %d pixels differ; with no_weld %d" % (scheme, welded, torn))
        if welded:
            raise Failure("%s: the welded patch-split sphere differs from the shared one in %d pixels"
                          % (scheme, welded))
        if not torn:
            raise Failure("%s: no_weld renders like the shared sphere: the control sees no seams" % scheme)


def uv_seamed_icosahedron():
    """The icosahedron as exporters write a uv-mapped mesh: every face with its
    own three vertices (positions, the sphere's normals), and spherical uvs
    per corner, unwrapped so that faces across the u = 0 / 1 seam do not
    wrap round the texture: the same position carries different uvs in
    different faces."""
    verts, faces, normals, _ = icosahedron()
    split_v, split_n, split_uv, split_f = [], [], [], []
    for f in faces:
        us = [0.5 + math.atan2(verts[v][2], verts[v][0]) / (2 * math.pi) for v in f]
        if max(us) - min(us) > 0.5:
            us = [u + 1.0 if u < 0.5 else u for u in us]
        base = len(split_v)
        for v, u in zip(f, us):
            split_v.append(verts[v])
            split_n.append(normals[v])
            split_uv.append((u, math.acos(max(-1.0, min(1.0, verts[v][1]))) / math.pi))
        split_f.append((base, base + 1, base + 2))
    return split_v, split_f, split_n, split_uv


def test_weld_uv_seams_equal_mesh2(ctx):
    """Welding keeps per-corner uvs (issue 11): the uv-seamed icosahedron
    (every vertex written once per face) at max_level 0 is the same picture
    as native mesh2 with the same arrays, uv-mapped checker and all; the
    surface is one sheet. Control: refined (max_level 3), no_weld makes every
    face its own sheet, which subdivides on its own, and the picture differs
    from the welded one. (At max_level 0 no_weld looks the same: the given
    normals are the level-0 normals either way.)"""
    verts, faces, normals, uvs = uv_seamed_icosahedron()
    body = mesh2_body(verts, faces, normals, uvs)
    mods = "%s rotate <20, 30, 0> scale 1.2" % ico_texture()
    level0_pair(ctx, "uv_seams", body, mods)
    refined = SCENE_HEADER + "subdivision_mesh { mesh2 { %s } max_level 3 tolerance 0.5 %%s %s }\n" % (body, mods)
    _, _, welded, _ = ctx.render("subdiv_uv_seams_welded", refined % "")
    _, _, torn, _ = ctx.render("subdiv_uv_seams_no_weld", refined % "no_weld")
    differ = differing_pixels(welded, torn)
    print("  no_weld: %d pixels differ from the welded surface at max_level 3" % differ)
    if differ == 0:
        raise Failure("no_weld renders like the welded mesh: the control sees no seams")


STOCK_POVRAY = "/usr/bin/povray"
STOCK_INCLUDE = "/usr/share/povray-3.7/include"


def faceted_cube_body():
    """A mesh2 cube with one normal per face (normal_indices): its 12 edges are creases."""
    verts = [(x, y, z) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)]
    quads = [((0, 2, 3, 1), 0), ((4, 5, 7, 6), 1), ((0, 1, 5, 4), 2),
             ((2, 6, 7, 3), 3), ((0, 4, 6, 2), 4), ((1, 3, 7, 5), 5)]
    normals = [(0, 0, -1), (0, 0, 1), (0, -1, 0), (0, 1, 0), (-1, 0, 0), (1, 0, 0)]
    faces, nidx = [], []
    for (a, b, c, d), n in quads:
        faces += [(a, b, c), (a, c, d)]
        nidx += [(n, n, n), (n, n, n)]
    return "\n    ".join([
        "vertex_vectors { 8, %s }" % ", ".join(fmt_vec(v) for v in verts),
        "normal_vectors { 6, %s }" % ", ".join(fmt_vec(v) for v in normals),
        "face_indices { 12, %s }" % ", ".join("<%d, %d, %d>" % f for f in faces),
        "normal_indices { 12, %s }" % ", ".join("<%d, %d, %d>" % f for f in nidx)])


def test_faceted_cube_equals_mesh2(ctx):
    """A cube written with one normal per face stays a cube at every level:
    refined to level 4 (every scheme: their crease rules keep it flat; the
    size rule, since the error rule rightly leaves flat faces whole), the
    same picture as the mesh2 cube, silhouette and shading."""
    mods = "texture { pigment { rgb <0.9, 0.6, 0.3> } finish { specular 0.3 } } rotate <25, 35, 0>"
    native = SCENE_HEADER + "mesh2 { %s %s }\n" % (faceted_cube_body(), mods)
    _, _, a, _ = ctx.render("native_cube", native)
    for scheme in ("normal", "loop", "butterfly"):
        subdiv = SCENE_HEADER + ("subdivision_mesh { mesh2 { %s } scheme %s refine size max_level 4 tolerance 0.25 %s }\n"
                                 % (faceted_cube_body(), scheme, mods))
        rc, err, b, _ = ctx.render("subdiv_cube_" + scheme, subdiv)
        level = deepest_level(err)
        print("  %s: deepest level %s" % (scheme, level))
        if level is None or level < 2:
            raise Failure("%s: the cube was not refined (deepest level %s)" % (scheme, level))
        assert_close("faceted cube, %s level 4 vs mesh2" % scheme, a, b, SAME_FRACTION, SAME_MEAN)


def test_refine_rules(ctx):
    """refine error (the default) and refine size both render the icosahedron
    like each other and like the finest size-rule render; the error rule
    builds fewer nodes, and the render summary names the rule and prints the
    certified error bound (in pixels, not above the largest bound any hit
    may have: the base mesh's own deviation is far larger than a pixel)."""
    verts, faces, normals, uvs = icosahedron()
    body = mesh2_body(verts, faces, None, uvs)
    def scene(setting):
        return SCENE_HEADER + "subdivision_mesh { mesh2 { %s } %s max_level 8 %s scale 1.4 }\n" % (
            body, setting, ico_texture())
    results = {}
    for name, setting in (("default", ""), ("error", "refine error"), ("size", "refine size"),
                          ("finest", "refine size tolerance 0.25")):
        rc, err, image, _ = ctx.render("refine_" + name, scene(setting))
        built = re.search(r"Subdivision nodes built:\s+(\d+)\s+refine rule:\s+(\w+)", err)
        bound = re.search(r"Subdivision error bound px:\s+([\d.]+) max\s+([\d.]+) mean\s+"
                          r"Subdivision bounded hits:\s+(\d+)\s+at max_level:\s+(\d+)", err)
        if not built or not bound:
            raise Failure("%s: the render summary lacks the nodes built, rule or error bound" % name)
        results[name] = (int(built.group(1)), built.group(2), float(bound.group(1)), float(bound.group(2)),
                         int(bound.group(3)), image)
        print("  %s: %s nodes, rule %s, bound max %s px, mean %s px over %s hits, %s at max_level"
              % (name, built.group(1), built.group(2), bound.group(1), bound.group(2), bound.group(3), bound.group(4)))
    if results["default"][1] != "error" or results["error"][1] != "error" or results["size"][1] != "size":
        raise Failure("the summary names the wrong rule")
    if results["default"][0] != results["error"][0]:
        raise Failure("refine error is not the default")
    if not results["error"][0] < results["size"][0]:
        raise Failure("the error rule built %d nodes, the size rule %d" % (results["error"][0], results["size"][0]))
    for name in ("error", "size"):
        built, rule, bmax, bmean, hits, image = results[name]
        if hits <= 0 or not (0.0 < bmean <= bmax):
            raise Failure("%s: implausible bound (max %g, mean %g, %d hits)" % (name, bmax, bmean, hits))
        assert_close("refine %s vs the finest size-rule render" % name, results["finest"][5], image,
                     SAME_FRACTION, SAME_MEAN)


def test_csg_faceted_cube(ctx):
    """CSG with a refined creased surface: the faceted cube at level 4 (its
    subdivided triangles all lie on the cube) in a difference and a
    transparent merge with a sphere gives mesh2's picture, so all-hits and
    the inside test hold on a refined surface with creases."""
    other = "sphere { <0.7, 0.6, -0.8>, 0.9 }"
    xform = "rotate <25, 35, 0>"
    for op, mat in (("difference", "pigment { rgb <0.9, 0.6, 0.3> } finish { specular 0.3 }"),
                    ("merge", "pigment { rgbf <0.9, 0.6, 0.3, 0.6> } finish { specular 0.3 }")):
        native = SCENE_HEADER + "%s { mesh2 { %s inside_vector <0.3, 0.5, 0.81> } %s %s %s }\n" % (
            op, faceted_cube_body(), other, mat, xform)
        _, _, a, _ = ctx.render("native_cube_" + op, native)
        for scheme in ("normal", "loop"):
            subdiv = SCENE_HEADER + ("%s { subdivision_mesh { mesh2 { %s } scheme %s refine size max_level 4 tolerance 0.25 } "
                                     "%s %s %s }\n" % (op, faceted_cube_body(), scheme, other, mat, xform))
            _, err, b, _ = ctx.render("subdiv_cube_%s_%s" % (op, scheme), subdiv)
            print("  %s %s: deepest level %s" % (op, scheme, deepest_level(err)))
            assert_close("faceted cube %s, %s level 4 vs mesh2" % (op, scheme), a, b, SAME_FRACTION, SAME_MEAN)

def test_creased_textured_cylinder(ctx):
    """scenes/creased_mesh2.pov's mesh (creased rims, texture_list blended on
    the sides, one texture per cap face): at max_level 0 the same picture as
    mesh2; refined per ray, it renders (the unit tests check its geometry:
    sharp rims, round sides, flat caps)."""
    with open(os.path.join(ctx.source_dir, "scenes", "creased_mesh2.pov")) as f:
        text = f.read()
    start = text.index("#declare Shine")
    end = text.index("object { Creased")
    declared = SCENE_HEADER + text[start:end]
    mods = "rotate <-25, 10, 0> scale 1.2"
    native = declared + "object { Creased %s }\n" % mods
    subdiv = declared + "subdivision_mesh { Creased max_level 0 %s }\n" % mods
    _, _, a, _ = ctx.render("native_cylinder", native)
    _, _, b, _ = ctx.render("subdiv_cylinder", subdiv)
    assert_close("creased cylinder: level 0 vs mesh2", a, b, SAME_FRACTION, SAME_MEAN)
    refined = declared + "subdivision_mesh { Creased max_level 8 tolerance 1 %s }\n" % mods
    rc, err, c, _ = ctx.render("refined_cylinder", refined)
    level = deepest_level(err)
    print("  refined: deepest level %s" % level)
    if level is None or level < 3:
        raise Failure("the cylinder was not refined (deepest level %s)" % level)


def test_loop_warns_given_normals(ctx):
    """Loop with normal_vectors: POV-Ray warns that the normals do not change
    the surface (and counts the creases they mark); the normal scheme does not."""
    for scheme, expect in (("loop", True), ("normal", False)):
        scene = SCENE_HEADER + ("subdivision_mesh { mesh2 { %s } scheme %s max_level 2 pigment { rgb 1 } "
                                "rotate <25, 35, 0> }\n" % (faceted_cube_body(), scheme))
        rc, err, _, _ = ctx.render("warn_" + scheme, scene)
        joined = err.replace("\n", "")  # POV-Ray wraps messages at 80 columns
        found = "computes its own normals" in joined and "12 crease edges" in joined
        print("  %s: warning %s" % (scheme, "printed" if found else "absent"))
        if found != expect:
            raise Failure("%s: expected the warning %s\n%s" % (scheme, "printed" if expect else "absent", tail(err)))


def run_quiet(cmd, cwd):
    return subprocess.run(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                          timeout=120).returncode


def test_standard_includes_parse(ctx):
    """The new reserved words (file, loop, scheme, ...) break none of POV-Ray's
    own include files: each parses with the patched povray exactly when it
    parses with Debian's stock povray (some need older #version settings and
    fail in both)."""
    if not os.access(STOCK_POVRAY, os.X_OK):
        raise Skip("stock povray not installed (%s)" % STOCK_POVRAY)
    import concurrent.futures
    names = sorted(n for n in os.listdir(ctx.include) if n.endswith(".inc"))

    def check(name):
        pov = ctx.path("inc_%s.pov" % name)
        with open(pov, "w") as f:
            f.write('#version 3.7;\nglobal_settings { assumed_gamma 1 }\n#include "%s"\n' % name)
        common = ["+I" + pov, "-F", "+W8", "+H8", "-D", "-V", "+WT1"]
        patched = run_quiet([ctx.povray] + common + ["+L" + ctx.include], ctx.work)
        stock = run_quiet([STOCK_POVRAY] + common + ["+L" + STOCK_INCLUDE], ctx.work)
        return name, patched, stock

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(check, names))
    differ = [(n, p, s) for n, p, s in results if (p == 0) != (s == 0)]
    print("  %d include files, %d parse with both, %d differ"
          % (len(results), sum(1 for _, p, s in results if p == 0 and s == 0), len(differ)))
    if differ:
        raise Failure("parse results differ from stock povray: %s" % differ)


def test_stock_scene_unchanged(ctx):
    """Scenes without subdivision_mesh render as with Debian's stock povray:
    the distribution's objects/mesh2.pov gives the identical image."""
    if not os.access(STOCK_POVRAY, os.X_OK):
        raise Skip("stock povray not installed (%s)" % STOCK_POVRAY)
    scene_dir = os.path.join(os.path.dirname(ctx.include), "scenes", "objects")
    scene = os.path.join(scene_dir, "mesh2.pov")
    if not os.path.exists(scene):
        raise Skip("no %s in the POV-Ray tree" % scene)
    images = []
    for binary, include, tag in ((ctx.povray, ctx.include, "patched"),
                                 (STOCK_POVRAY, STOCK_INCLUDE, "stock")):
        out = ctx.path("mesh2_%s.ppm" % tag)
        rc = run_quiet([binary, "+I" + scene, "+O" + out, "+FP", "+W%d" % WIDTH, "+H%d" % HEIGHT,
                        "-D", "-V", "+WT1", "+L" + include], scene_dir)
        if rc != 0:
            raise Failure("%s povray failed on %s (exit %d)" % (tag, scene, rc))
        images.append(read_ppm(out))
    if images[0] != images[1]:
        fraction, mean, largest = compare(images[0], images[1])
        raise Failure("objects/mesh2.pov differs from stock: %.3f%% pixels, max %d/255"
                      % (100 * fraction, largest))
    print("  objects/mesh2.pov: identical to stock povray")


# ---------------------------------------------------------------------------
# Scenes shaped like real users' ones (issue 16): a modeller's mesh2 export, a
# cloth, a scene where every kind of ray meets the primitive, a hundred
# objects under one scene budget. Each checks: parses, renders, max_level 0 is
# mesh2's picture, and the adaptive surface adds no holes or acne.


def object_mask(image, background):
    w, h, p = image
    return [max(abs(p[i + c] - background[c]) for c in range(3)) > 2 for i in range(0, len(p), 3)]


def eroded(mask, w, h, r):
    """Pixels whose (2r+1)^2 neighbourhood is all in mask."""
    out = [False] * len(mask)
    for y in range(r, h - r):
        for x in range(r, w - r):
            out[y * w + x] = all(mask[(y + dy) * w + x + dx]
                                 for dy in range(-r, r + 1) for dx in range(-r, r + 1))
    return out


def holes(image, reference, background, r=3):
    """Pixels well inside the reference's object (r pixels from its edge) that
    show the background in `image`: rays that slipped through the surface."""
    w, h, _ = image
    inside = eroded(object_mask(reference, background), w, h, r)
    shown = object_mask(image, background)
    return sum(1 for i in range(len(inside)) if inside[i] and not shown[i])


def speckles(image, mask, jump=40):
    """Object pixels brighter or darker than all four neighbours by more than
    `jump`/255 in every channel sum sense: isolated dots, what self-shadowing
    acne and rays finding the surface they left look like."""
    w, h, p = image
    lum = [p[i] + p[i + 1] + p[i + 2] for i in range(0, len(p), 3)]
    count = 0
    for y in range(1, h - 1):
        for x in range(1, w - 1):
            i = y * w + x
            if not mask[i]:
                continue
            n = [lum[i - 1], lum[i + 1], lum[i - w], lum[i + w]]
            if all(lum[i] - v > 3 * jump for v in n) or all(v - lum[i] > 3 * jump for v in n):
                count += 1
    return count


def check_no_new_holes_or_acne(name, adaptive, native, background):
    w, h, _ = native
    hole_count = holes(adaptive, native, background)
    mask = object_mask(native, background)
    ours, theirs = speckles(adaptive, mask), speckles(native, mask)
    print("  %s: %d holes, %d isolated dots (mesh2: %d)" % (name, hole_count, ours, theirs))
    if hole_count > 0:
        raise Failure("%s: %d pixels inside mesh2's silhouette show the background" % (name, hole_count))
    if ours > theirs + max(2, theirs // 2):
        raise Failure("%s: %d isolated dots against mesh2's %d (acne?)" % (name, ours, theirs))


def lathe_export(segments=24, rings=10):
    """A vase as modellers export mesh2 (Blender's POV-Ray exporter writes
    this shape): unique positions, unique normals and uvs each with their own
    index list, a texture_list and one texture index per face. The side is
    smooth; the flat bottom meets it at a hard edge (the rim's vertices are
    shared, their normals are not); the uv seam duplicates uvs, not vertices."""
    profile = [(0.35 + 0.3 * math.sin(math.pi * (0.15 + 0.85 * k / rings)), -1.0 + 2.0 * k / rings)
               for k in range(rings + 1)]
    verts, normals, uvs = [], [], []
    faces, nidx, uidx, tex = [], [], [], []
    for k, (r, y) in enumerate(profile):
        for s in range(segments):
            a = 2 * math.pi * s / segments
            verts.append((r * math.cos(a), y, r * math.sin(a)))
            # Profile slope dr/dy by central differences, normal (cos a, -dr/dy, sin a).
            k0, k1 = max(k - 1, 0), min(k + 1, rings)
            drdy = (profile[k1][0] - profile[k0][0]) / (profile[k1][1] - profile[k0][1])
            n = (math.cos(a), -drdy, math.sin(a))
            length = math.sqrt(sum(c * c for c in n))
            normals.append(tuple(c / length for c in n))
    for k in range(rings + 1):
        for s in range(segments + 1):
            uvs.append((s / segments, k / rings))
    vid = lambda k, s: k * segments + s % segments
    uid = lambda k, s: k * (segments + 1) + s
    for k in range(rings):
        for s in range(segments):
            a, b, c, d = vid(k, s), vid(k, s + 1), vid(k + 1, s + 1), vid(k + 1, s)
            for tri, uv in (((a, c, b), (uid(k, s), uid(k + 1, s + 1), uid(k, s + 1))),
                            ((a, d, c), (uid(k, s), uid(k + 1, s), uid(k + 1, s + 1)))):
                faces.append(tri)
                nidx.append(tri)
                uidx.append(uv)
                tex.append(0)
    # Bottom cap: a centre vertex, the ring-0 vertices, one normal (hard edge).
    centre = len(verts)
    verts.append((0.0, -1.0, 0.0))
    cap_normal = len(normals)
    normals.append((0.0, -1.0, 0.0))
    cap_uv = len(uvs)
    uvs.append((0.5, 0.5))
    for s in range(segments):
        tri = (centre, vid(0, s), vid(0, s + 1))
        faces.append(tri)
        nidx.append((cap_normal,) * 3)
        uidx.append((cap_uv, uid(0, s), uid(0, s + 1)))
        tex.append(1)
    return verts, normals, uvs, faces, nidx, uidx, tex


def exported_mesh2(verts, normals, uvs, faces, nidx, uidx, tex, textures):
    vec = lambda vs: ", ".join(fmt_vec(v) for v in vs)
    return "\n".join([
        "vertex_vectors { %d, %s }" % (len(verts), vec(verts)),
        "normal_vectors { %d, %s }" % (len(normals), vec(normals)),
        "uv_vectors { %d, %s }" % (len(uvs), vec(uvs)),
        "texture_list { %d, %s }" % (len(textures), ", ".join(textures)),
        "face_indices { %d, %s }" % (len(faces), ", ".join("<%d, %d, %d>, %d" % (f + (t,)) for f, t in zip(faces, tex))),
        "normal_indices { %d, %s }" % (len(nidx), ", ".join("<%d, %d, %d>" % f for f in nidx)),
        "uv_indices { %d, %s }" % (len(uidx), ", ".join("<%d, %d, %d>" % f for f in uidx))])


def test_modeller_export(ctx):
    """A modeller's mesh2 export (#declare'd, own normals with a hard edge,
    uvs with a seam, texture_list with per-face indices, uv-mapped texture):
    max_level 0 is mesh2's picture, whether the body is inline or the
    declared mesh is used; adaptively refined, no holes and no acne."""
    body = exported_mesh2(*lathe_export(), textures=[
        "texture { uv_mapping pigment { checker rgb <0.9, 0.5, 0.2> rgb <0.2, 0.3, 0.8> scale <0.125, 0.25, 1> } "
        "finish { specular 0.5 roughness 0.02 } }",
        "texture { pigment { rgb <0.3, 0.8, 0.3> } }"])
    header = SCENE_HEADER + "#declare Vase = mesh2 {\n%s\n}\n" % body
    xform = "rotate <-25, 20, 0> scale 1.1"
    _, _, native, _ = ctx.render("export_mesh2", header + "object { Vase %s }\n" % xform)
    _, _, inline0, _ = ctx.render("export_inline0", SCENE_HEADER +
                                  "subdivision_mesh { mesh2 {\n%s\n} max_level 0 %s }\n" % (body, xform))
    _, _, declared0, _ = ctx.render("export_declared0", header + "subdivision_mesh { Vase max_level 0 %s }\n" % xform)
    assert_close("inline max_level 0 vs mesh2", inline0, native, SAME_FRACTION, SAME_MEAN)
    assert_close("declared max_level 0 vs mesh2", declared0, native, SAME_FRACTION, SAME_MEAN)
    _, err, adaptive, _ = ctx.render("export_adaptive", header +
                                     "subdivision_mesh { Vase max_level 6 tolerance 1 %s }\n" % xform)
    if deepest_level(err) < 2:
        raise Failure("the export did not refine (deepest level %d)" % deepest_level(err))
    _, _, empty, _ = ctx.render("export_empty", SCENE_HEADER)
    check_no_new_holes_or_acne("adaptive vase", adaptive, native, empty[2][0:3])


def cloth_grid(n=16):
    """An open n x n grid draped over a bump, with normals and uvs per vertex."""
    verts, normals, uvs, faces = [], [], [], []
    height = lambda x, z: 0.6 * math.exp(-3.0 * (x * x + z * z)) + 0.08 * math.sin(5 * x) * math.cos(4 * z)
    for j in range(n + 1):
        for i in range(n + 1):
            x, z = -1.5 + 3.0 * i / n, -1.5 + 3.0 * j / n
            verts.append((x, height(x, z) - 0.5, z))
            e = 1e-4
            dx = (height(x + e, z) - height(x - e, z)) / (2 * e)
            dz = (height(x, z + e) - height(x, z - e)) / (2 * e)
            nl = math.sqrt(dx * dx + 1 + dz * dz)
            normals.append((-dx / nl, 1 / nl, -dz / nl))
            uvs.append((i / n, j / n))
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            faces += [(a, c, b), (a, d, c)]
    return verts, normals, uvs, faces


def test_cloth_uv_normal(ctx):
    """A cloth: an open grid with uv_mapping, a normal pattern and a
    two-sided look; max_level 0 is mesh2's picture, the adaptive cloth has no
    holes or acne, and +WT1 equals +WT2 byte for byte."""
    verts, normals, uvs, faces = cloth_grid()
    body = mesh2_body(verts, faces, normals, uvs)
    look = ("texture { uv_mapping pigment { checker rgb <0.9, 0.2, 0.2> rgb 0.9 scale 0.0625 } "
            "normal { bumps 0.5 scale 0.02 } finish { specular 0.3 } } "
            "interior_texture { pigment { rgb <0.2, 0.6, 0.9> } } rotate <-20, 15, 0>")
    header = SCENE_HEADER.replace("<0, 0.4, -4>", "<0, 1.6, -4>")
    _, _, native, _ = ctx.render("cloth_mesh2", header + "mesh2 { %s %s }\n" % (body, look))
    _, _, level0, _ = ctx.render("cloth_level0", header + "subdivision_mesh { mesh2 { %s } max_level 0 %s }\n" % (body, look))
    assert_close("cloth max_level 0 vs mesh2", level0, native, SAME_FRACTION, SAME_MEAN)
    scene = header + "subdivision_mesh { mesh2 { %s } max_level 6 tolerance 1 %s }\n" % (body, look)
    _, _, wt1, _ = ctx.render("cloth_adaptive_wt1", scene, threads=1)
    _, _, wt2, _ = ctx.render("cloth_adaptive_wt2", scene, threads=2)
    if wt1 != wt2:
        raise Failure("+WT1 and +WT2 differ in %d pixels" % differing_pixels(wt1, wt2))
    _, _, empty, _ = ctx.render("cloth_empty", header)
    check_no_new_holes_or_acne("adaptive cloth", wt1, native, empty[2][0:3])


ALL_RAYS_HEADER = """#version 3.7;
global_settings { assumed_gamma 1.0
  radiosity { pretrace_start 0.08 pretrace_end 0.04 count 35 error_bound 1.8 recursion_limit 1 }
  photons { spacing 0.05 autostop 0 } }
camera { location <0, 1.2, -4.5> look_at <0, 0, 0> angle 45 }
light_source { <3, 5, -4> rgb 1.2 area_light x * 1, z * 1, 3, 3 adaptive 0 photons { refraction on reflection on } }
fog { distance 12 rgb <0.6, 0.65, 0.7> }
background { rgb <0.6, 0.65, 0.7> }
plane { y, -1 pigment { checker rgb 0.8 rgb 0.4 } finish { diffuse 0.7 } }
box { <-3, -1, 2>, <3, 2.5, 2.2> pigment { rgb <0.8, 0.7, 0.5> } }
"""


def test_every_ray_kind(ctx):
    """Radiosity, photons (through and off the objects), an area light, fog,
    a mirror and a glass object: camera, shadow, reflection, refraction,
    radiosity and photon rays all meet subdivision_mesh. Without photons,
    max_level 0 gives mesh2's picture; with them the two render, photon rays
    reach the primitive, and the adaptive scene has no holes or acne against
    mesh2's. (The caustic under the glass is not compared pixel for pixel: a
    caustic focuses the tiny differences between the two intersection tests,
    and at max_level 0 about 8% of the pixels there differ.)"""
    verts, faces, normals, uvs = icosahedron()
    body = mesh2_body(verts, faces, normals, uvs)
    glass = ("material { texture { pigment { rgbf <0.95, 1, 0.95, 0.9> } finish { reflection 0.05 specular 0.6 } } "
             "interior { ior 1.45 } } photons { target refraction on reflection on } translate <-0.9, 0, 0>")
    mirror = ("texture { pigment { rgb 0.3 } finish { reflection 0.7 specular 0.5 } } "
              "photons { target reflection on } translate <0.9, 0, 0.4>")
    photons = "photons { spacing 0.05 autostop 0 }"

    def scene(kind, mods, with_photons=True):
        obj = "mesh2 { %s %s }" if kind == "mesh2" else "subdivision_mesh { mesh2 { %s } " + mods + " %s }"
        header = ALL_RAYS_HEADER if with_photons else ALL_RAYS_HEADER.replace(photons, "")
        return header + (obj % (body, glass)) + "\n" + (obj % (body, mirror)) + "\n"

    def primitive_rays(err):
        m = re.search(r"Subdivision Mesh\s+(\d+)\s+(\d+)", err)
        if not m:
            raise Failure("no Subdivision Mesh row in the summary")
        return int(m.group(1))
    _, _, native_dark, _ = ctx.render("rays_mesh2_no_photons", scene("mesh2", "", False))
    _, err_dark, level0_dark, _ = ctx.render("rays_level0_no_photons", scene("subdiv", "max_level 0", False))
    assert_close("radiosity, area light, fog, mirror, glass: max_level 0 vs mesh2", level0_dark, native_dark,
                 SAME_FRACTION, SAME_MEAN)
    _, _, native, _ = ctx.render("rays_mesh2", scene("mesh2", ""))
    _, err0, _, _ = ctx.render("rays_level0", scene("subdiv", "max_level 0"))
    dark, lit = primitive_rays(err_dark), primitive_rays(err0)
    print("  rays tested against the primitive: %d without photons, %d with" % (dark, lit))
    if dark <= WIDTH * HEIGHT or lit <= dark:
        raise Failure("expected secondary rays (more than %d) and photon rays (more than %d) to meet the primitive"
                      % (WIDTH * HEIGHT, dark))
    _, err, adaptive, _ = ctx.render("rays_adaptive", scene("subdiv", "max_level 6 tolerance 1"))
    if deepest_level(err) < 2:
        raise Failure("no refinement (deepest level %d)" % deepest_level(err))
    # Silhouettes: the two objects flat white on black, seen by the same camera.
    mask = lambda look: ("texture { pigment { rgb 1 } finish { ambient 1 diffuse 0 } } translate" +
                         look.split("translate")[1])
    camera = [line for line in ALL_RAYS_HEADER.splitlines() if line.startswith("camera")][0]
    flat = "#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n%s\nbackground { rgb 0 }\n" % camera

    def silhouette(kind, mods):
        obj = "mesh2 { %s %s }" if kind == "mesh2" else "subdivision_mesh { mesh2 { %s } " + mods + " %s }"
        return flat + (obj % (body, mask(glass))) + "\n" + (obj % (body, mask(mirror))) + "\n"
    _, _, native_mask, _ = ctx.render("rays_mask_mesh2", silhouette("mesh2", ""))
    _, _, adaptive_mask, _ = ctx.render("rays_mask_adaptive", silhouette("subdiv", "max_level 6 tolerance 1"))
    hole_count = holes(adaptive_mask, native_mask, (0, 0, 0))
    ours = speckles(adaptive, object_mask(native_mask, (0, 0, 0)))
    theirs = speckles(native, object_mask(native_mask, (0, 0, 0)))
    print("  adaptive, every ray kind: %d holes, %d isolated dots on the objects (mesh2: %d)"
          % (hole_count, ours, theirs))
    if hole_count > 0:
        raise Failure("%d pixels inside mesh2's silhouettes miss the adaptive objects" % hole_count)
    if ours > theirs + max(2, theirs // 2):
        raise Failure("%d isolated dots on the objects against mesh2's %d (acne?)" % (ours, theirs))


def summary_cache(err):
    m = re.search(r"Subdivision scene cache:\s+([\d.]+) MB budget, ([\d.]+) MB peak, (\d+)\s+evictions", err)
    s = re.search(r"Subdivision mesh surfaces:\s+(\d+)", err)
    if not m or not s:
        raise Failure("render summary lacks the scene cache line:\n%s" % tail(err, 30))
    return int(s.group(1)), float(m.group(1)), float(m.group(2)), int(m.group(3))


def peak_rss_mb(ctx, name, scene, threads=2):
    """Peak RSS of povray rendering `scene` (GNU time's maximum resident set)."""
    pov, out = ctx.path(name + ".pov"), ctx.path(name + ".ppm")
    with open(pov, "w") as f:
        f.write(scene)
    timing = ctx.path(name + ".time")
    cmd = ["/usr/bin/time", "-f", "%M", "-o", timing, ctx.povray, "+I" + pov, "+O" + out, "+FP",
           "+W%d" % WIDTH, "+H%d" % HEIGHT, "-D", "-V", "+WT%d" % threads, "+L" + ctx.include,
           "+L" + ctx.work]
    start = time.monotonic()
    proc = subprocess.run(cmd, cwd=ctx.work, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=300)
    err = proc.stderr.decode("utf-8", "replace") + proc.stdout.decode("utf-8", "replace")
    with open(ctx.path(name + ".log"), "w") as f:
        f.write(" ".join(cmd) + "\n" + err)
    if proc.returncode != 0:
        raise Failure("%s: povray exited %d\n%s" % (name, proc.returncode, tail(err)))
    with open(timing) as f:
        rss = int(f.read().split()[-1]) / 1024.0
    print("  rendered %-28s %6.2f s, peak RSS %.0f MB" % (name, time.monotonic() - start, rss))
    return err, read_ppm(out), rss


def bunny_copies(ctx, prefix, count):
    """Paths of `count` copies of data/bunny_lowpoly.obj in the work
    directory: distinct files, so each object that reads one is its own
    surface (objects that read one file share a surface)."""
    source = os.path.join(ctx.source_dir or "", "data", "bunny_lowpoly.obj")
    if not os.path.exists(source):
        raise Skip("no data/bunny_lowpoly.obj")
    copies = [ctx.path("%s_%d.obj" % (prefix, k)) for k in range(count)]
    for copy in copies:
        shutil.copyfile(source, copy)
    return copies


def test_hundred_objects(ctx):
    """A hundred separate subdivision_mesh objects (each its own surface, read
    from its own copy of data/bunny_lowpoly.obj, since objects that read one
    file share a surface) close to the camera, under one scene budget
    of 8 MB: the summary reports 100 surfaces and one cache within its budget,
    and peak RSS exceeds the same scene at max_level 0 (the same base meshes,
    no tiles) by no more than the budget plus a fixed allowance for the
    threads' fronts and allocator slack, whereas 100 per-object budgets would
    allow 100 times as much. The picture does not depend on the budget."""
    copies = bunny_copies(ctx, "hundred_bunny", 100)
    header = ("#version 3.7;\nglobal_settings { assumed_gamma 1.0 subdivision_cache_mb %s }\n"
              "camera { location <0, 5, -4.5> look_at <0, 0, 0.2> angle 60 }\n"
              "light_source { <4, 8, -5> rgb 1 }\nbackground { rgb <0.15, 0.18, 0.25> }\n")
    objs = []
    for k in range(100):
        x, z = -2.25 + 0.5 * (k % 10), -2.25 + 0.5 * (k // 10)
        objs.append('subdivision_mesh { file "%s" %%s pigment { rgb <%.2f, 0.6, %.2f> } '
                    'rotate y*%d scale 0.45 translate <%g, 0, %g> }' % (copies[k], 0.3 + 0.007 * k, 0.9 - 0.006 * k, 37 * k, x, z))
    body = "\n".join(objs) + "\n"
    err0, _, rss0 = peak_rss_mb(ctx, "hundred_level0", header % 8 + body.replace("%s", "max_level 0"))
    err, small, rss = peak_rss_mb(ctx, "hundred_8mb", header % 8 + body.replace("%s", "max_level 6 tolerance 1"))
    surfaces, budget, peak, evictions = summary_cache(err)
    print("  %d surfaces, scene cache budget %.0f MB, peak %.1f MB, %d evictions; RSS %.0f MB vs %.0f MB at level 0"
          % (surfaces, budget, peak, evictions, rss, rss0))
    if surfaces != 100:
        raise Failure("summary counts %d surfaces, expected 100" % surfaces)
    if budget != 8.0:
        raise Failure("scene cache budget %.1f MB, expected global_settings' 8" % budget)
    if evictions == 0:
        raise Failure("the 8 MB budget never evicted: the test does not exercise it")
    # Each of the cache's 64 shards keeps at least 2 tiles: 128 tiles of at
    # most ~64 kB may exceed the budget.
    if peak > budget + 8.0:
        raise Failure("scene cache peak %.1f MB exceeds its %.0f MB budget" % (peak, budget))
    allowance = 48.0  # two threads' fronts (64 tiles each), per-surface counters, allocator slack
    if rss > rss0 + budget + allowance:
        raise Failure("peak RSS %.0f MB > level-0 scene's %.0f MB + budget %.0f MB + %.0f MB"
                      % (rss, rss0, budget, allowance))
    _, large, _ = peak_rss_mb(ctx, "hundred_256mb", header % 256 + body.replace("%s", "max_level 6 tolerance 1"))
    if small != large:
        raise Failure("8 MB and 256 MB budgets differ in %d pixels" % differing_pixels(small, large))
    print("  8 MB and 256 MB budgets: identical pictures")


def test_objects_share_a_file_surface(ctx):
    """Objects that read the same file with the same settings share one
    surface, as copies of one declared object do: three bunnies from one
    file and one from a copy of it are 2 surfaces, where four copies of the
    file are 4, and both pictures are the same bit for bit (tiles do not
    depend on the object's view or transformation). A different setting
    makes a surface of its own. The same holds for the same arrays (a
    declared mesh2 given twice, an inline mesh2 written twice)."""
    files = bunny_copies(ctx, "shared_bunny", 4)
    header = ("#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n"
              "camera { location <0, 3.5, -4> look_at <0, 0, 0> angle 50 }\n"
              "light_source { <4, 8, -5> rgb 1 }\nbackground { rgb <0.15, 0.18, 0.25> }\n")

    def scene(names, settings=("",) * 4):
        return header + "".join(
            'subdivision_mesh { file "%s" max_level 6 %s pigment { rgb <0.9, %.1f, 0.5> } '
            'rotate y*%d translate <%g, 0, %g> }\n' % (names[k], settings[k], 0.3 + 0.2 * k, 70 * k,
                                                     -1.2 + 2.4 * (k % 2), -0.8 + 1.6 * (k // 2))
            for k in range(4))

    _, err_shared, shared, _ = ctx.render("share_one_file", scene([files[0]] * 3 + [files[1]]), threads=2)
    _, err_apart, apart, _ = ctx.render("share_four_files", scene(files), threads=2)
    _, err_tol, _, _ = ctx.render("share_other_tolerance", scene([files[0]] * 4, ("",) * 3 + ("tolerance 2",)),
                                  threads=2)
    counts = [summary_cache(e)[0] for e in (err_shared, err_apart, err_tol)]
    print("  surfaces: one file x3 + a copy %d, four copies %d, one file with another tolerance once %d"
          % tuple(counts))
    if counts != [2, 4, 2]:
        raise Failure("surfaces %s, expected [2, 4, 2]" % counts)
    if shared != apart:
        raise Failure("shared and separate surfaces differ in %d pixels" % differing_pixels(shared, apart))
    print("  shared and separate surfaces: identical pictures")

    # The same arrays: a declared mesh2 given twice, and an inline mesh2
    # written twice, are one surface each (a declared mesh reaches the
    # library in POV-Ray's single precision, so it is not the inline one);
    # an inline mesh2 with one vertex moved is its own.
    verts, faces, _, _ = icosahedron()
    moved = [tuple(c * 1.1 for c in verts[0])] + verts[1:]
    body, body_moved = mesh2_body(verts, faces), mesh2_body(moved, faces)
    scene_arrays = (SCENE_HEADER + "#declare M = mesh2 { %s }\n" % body + "".join(
        "subdivision_mesh { %s max_level 4 pigment { rgb 1 } translate <%g, %g, 0> }\n" % (mesh, x, y)
        for mesh, x, y in (("M", -2.4, 1.2), ("M", 0, 1.2), ("mesh2 { %s }" % body, 2.4, 1.2),
                           ("mesh2 { %s }" % body, -1.2, -1.2), ("mesh2 { %s }" % body_moved, 1.2, -1.2))))
    _, err_arrays, _, _ = ctx.render("share_arrays", scene_arrays, threads=2)
    count = summary_cache(err_arrays)[0]
    print("  surfaces: a declared mesh2 twice, an inline mesh2 twice, another once: %d" % count)
    if count != 3:
        raise Failure("surfaces %d, expected 3" % count)


def test_scene_cache_settings(ctx):
    """subdivision_cache_mb is read wherever global_settings stands (before or
    after the objects), a bad value is a parse error on its line, and an
    object's own cache_mb is a warning that names the scene setting."""
    verts, faces, normals, uvs = icosahedron()
    obj = "subdivision_mesh { mesh2 { %s } max_level 4 pigment { rgb 1 } }\n" % mesh2_body(verts, faces)
    for where, scene in (("before", "global_settings { subdivision_cache_mb 3 }\n" + SCENE_HEADER + obj),
                         ("after", SCENE_HEADER + obj + "global_settings { subdivision_cache_mb 3 }\n")):
        _, err, _, _ = ctx.render("settings_" + where, scene)
        _, budget, _, _ = summary_cache(err)
        if budget != 3.0:
            raise Failure("global_settings %s the object: budget %.1f MB, expected 3" % (where, budget))
    _, err, _, _ = ctx.render("settings_default", SCENE_HEADER + obj)
    print("  default scene budget: %.0f MB" % summary_cache(err)[1])
    _, err, _, _ = ctx.render("settings_object_cache_mb", SCENE_HEADER + obj.replace("max_level 4", "max_level 4 cache_mb 16"))
    # POV-Ray wraps warnings at 80 columns after the file's path, so where
    # the lines break depends on where the build tree is: compare words.
    words = " ".join(err.split())
    if "cache_mb is ignored" not in words or "subdivision_cache_mb" not in words:
        raise Failure("no warning for an object's cache_mb:\n%s" % tail(err))
    lines = SCENE_HEADER.splitlines() + ["global_settings {", "  subdivision_cache_mb 0", "}"]
    rc, err, _, _ = ctx.render("settings_bad", "\n".join(lines) + "\n", expect_ok=False)
    flat = re.sub(r"\n ", " ", err)
    m = re.search(r"line (\d+): Parse Error: ([^\n]*)", flat)
    if rc == 0 or not m:
        raise Failure("subdivision_cache_mb 0 accepted (exit %d)" % rc)
    print("  line %s: %s" % (m.group(1), m.group(2)))
    if int(m.group(1)) != len(lines) - 1 or "subdivision_cache_mb must be from 1" not in m.group(2):
        raise Failure("expected the error on line %d naming subdivision_cache_mb" % (len(lines) - 1))


TESTS = {
    "level0_equals_mesh2": test_level0_equals_mesh2,
    "threads_identical": test_threads_identical,
    "csg_difference": test_csg_difference,
    "csg_intersection": test_csg_intersection,
    "csg_merge": test_csg_merge,
    "features": test_features,
    "open_mesh": test_open_mesh,
    "loop_converges_to_uniform": test_loop_converges_to_uniform,
    "no_shadow_acne": test_no_shadow_acne,
    "standard_includes_parse": test_standard_includes_parse,
    "stock_scene_unchanged": test_stock_scene_unchanged,
    "copies_own_view_perspective": test_copies_own_view_perspective,
    "copies_own_view_orthographic": test_copies_own_view_orthographic,
    "texture_list_equals_mesh2": test_texture_list_equals_mesh2,
    "mixed_winding": test_mixed_winding,
    "uv_without_uv_vectors_equals_mesh2": test_uv_without_uv_vectors_equals_mesh2,
    "inside_vector_equals_mesh2": test_inside_vector_equals_mesh2,
    "texture_blend_continuous": test_texture_blend_continuous,
    "declared_mesh": test_declared_mesh,
    "shadow_acne_nonconvex": test_shadow_acne_nonconvex,
    "weld_patch_split_sphere": test_weld_patch_split_sphere,
    "weld_uv_seams_equal_mesh2": test_weld_uv_seams_equal_mesh2,
    "faceted_cube_equals_mesh2": test_faceted_cube_equals_mesh2,
    "csg_faceted_cube": test_csg_faceted_cube,
    "refine_rules": test_refine_rules,
    "creased_textured_cylinder": test_creased_textured_cylinder,
    "loop_warns_given_normals": test_loop_warns_given_normals,
    "modeller_export": test_modeller_export,
    "cloth_uv_normal": test_cloth_uv_normal,
    "every_ray_kind": test_every_ray_kind,
    "hundred_objects": test_hundred_objects,
    "objects_share_a_file_surface": test_objects_share_a_file_surface,
    "scene_cache_settings": test_scene_cache_settings,
}
for _name in BAD_CASES:
    TESTS["bad_" + _name] = (lambda n: (lambda ctx: bad_case_test(ctx, n)))(_name)
for _scheme in ("normal", "loop", "butterfly"):
    TESTS["uniform_level2_" + _scheme] = (lambda s: (lambda ctx: uniform_level_test(ctx, s)))(_scheme)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--povray")
    parser.add_argument("--include")
    parser.add_argument("--work", default="integration_work")
    parser.add_argument("--cli")
    parser.add_argument("--source-dir")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("tests", nargs="*")
    args = parser.parse_args()
    if args.list:
        print("\n".join(TESTS))
        return 0
    unknown = [t for t in args.tests if t not in TESTS]
    if unknown or not args.tests:
        parser.error("unknown or no tests: %s (see --list)" % " ".join(unknown))
    status = 0
    for name in args.tests:
        print("%s:" % name)
        try:
            TESTS[name](Context(args, name))
            print("  PASS")
        except Skip as e:
            print("  SKIP: %s" % e)
            status = status or SKIP
        except Failure as e:
            print("  FAIL: %s" % e)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
