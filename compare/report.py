#!/usr/bin/python3
"""Report for compare/run.sh: image errors, plots, side-by-side images, tables.

usage: /usr/bin/python3 compare/report.py BUILD_DIR/compare

Reads <view>/{ref,adaptive_t*,size_t*,lowmem_t*,uniform_l*,embree_*}.{png,json}
(and levels_t1, error_t1 .png/.txt, povray/*.png, *.log if present), writes
diff_*.png heat maps next to the renders, plot_*.png, results.csv, report.md and
report.html into the same directory. adaptive_t* are the error rule (render
--refine error), size_t* the paper's size rule (--refine size); the tables that
compare "adaptive" with uniform and Embree use the error rule's renders.

Image error: RGB in [0, 1]; RMSE over all pixels and channels; max = the
largest per-pixel difference (max over channels). Heat maps show the per-pixel
max-channel |difference| on a fixed scale 0..HEAT_MAX (brighter = larger).
"""

import csv
import glob
import html
import json
import math
import os
import re
import sys

import numpy as np
from PIL import Image
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HEAT_MAX = 0.05
VIEW_TITLES = {
    "far": "far view (whole mesh in frame)",
    "close": "close-up (mesh fills the frame, silhouette crosses it)",
    "fine": "already-fine mesh (a modeller-style export, triangles 1-3 px wide)",
}
VIEWS = ("far", "close", "fine")
RULE_NAMES = {"error": "error rule", "size": "size rule (paper)"}


def load_rgb(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0


def image_error(img, ref):
    d = np.abs(img - ref)
    return float(np.sqrt(np.mean(d * d))), float(d.max()), d.max(axis=2)


def heat_map(diff, path):
    cmap = matplotlib.colormaps["inferno"]
    rgba = cmap(np.clip(diff / HEAT_MAX, 0.0, 1.0))
    Image.fromarray((rgba[:, :, :3] * 255).astype(np.uint8)).save(path)


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if isinstance(x, int):
        return "{:,}".format(x)
    if abs(x) >= 100:
        return "%.0f" % x
    return ("%%.%dg" % digits) % x


def ratio(a, b):
    return a / b if b else float("nan")


class Run:
    def __init__(self, view, name, directory):
        self.view, self.name = view, name
        self.png = os.path.join(directory, name + ".png")
        with open(os.path.join(directory, name + ".json")) as f:
            self.s = json.load(f)
        self.rule = self.s.get("refine", "") if self.s.get("mode") != "uniform" else ""
        if name.startswith("adaptive_t"):
            self.kind, self.param = "adaptive", float(name[len("adaptive_t"):])
            self.label = "tol %g" % self.param
        elif name.startswith("size_t"):
            self.kind, self.param = "size", float(name[len("size_t"):])
            self.label = "size rule, tol %g" % self.param
        elif name.startswith("lowmem_t"):
            self.kind, self.param = "lowmem", float(name[len("lowmem_t"):])
            self.label = "tol %g, cache %d MB" % (self.param, self.s.get("cache_mb", 16))
        elif name.startswith("uniform_l"):
            self.kind, self.param = "uniform", int(name[len("uniform_l"):])
            self.label = "level %d" % self.param
        elif name.startswith("embree_uniform_l"):
            self.kind, self.param = "embree_uniform", int(name[len("embree_uniform_l"):])
            self.label = "Embree BVH, level %d" % self.param
        elif name.startswith("embree_subdiv_p"):
            self.kind, self.param = "embree_subdiv", float(name[len("embree_subdiv_p"):])
            self.label = "Embree Catmull-Clark, %g px" % self.param
        else:
            self.kind, self.param = "ref", self.s.get("tolerance")
            self.label = "reference (%s, tol %g, max level %d)" % (
                RULE_NAMES.get(self.rule, self.rule or "?"), self.s["tolerance"], self.s["max_level"])
        self.rmse = self.maxdiff = float("nan")
        self.rmse_own = float("nan")  # Embree subdivision: against its own finest render
        self.diff_png = None

    def __getattr__(self, key):
        s = self.__dict__.get("s", {})
        if key in s:
            return s[key]
        raise AttributeError(key)

    def stat(self, key):
        """A --stats-json field, NaN when absent (older CLI, uniform mode)."""
        v = self.s.get(key)
        return float("nan") if v is None else v

    @property
    def work(self):
        """Nodes built (adaptive) or uniform triangles (uniform)."""
        if self.kind in ("uniform", "embree_uniform"):
            return int(self.s.get("uniform_triangles_at_deepest_level") or 0)
        return int(self.s.get("nodes_built") or 0)


def load_view(out, view):
    d = os.path.join(out, view)
    if not os.path.exists(os.path.join(d, "ref.json")):
        return None
    ref = Run(view, "ref", d)
    ref_img = load_rgb(ref.png)
    runs = []
    for j in sorted(glob.glob(os.path.join(d, "adaptive_t*.json"))) + sorted(
            glob.glob(os.path.join(d, "size_t*.json"))) + sorted(
            glob.glob(os.path.join(d, "lowmem_t*.json"))) + sorted(
            glob.glob(os.path.join(d, "uniform_l*.json"))) + sorted(
            glob.glob(os.path.join(d, "embree_*.json"))):
        name = os.path.basename(j)[:-5]
        if not os.path.exists(os.path.join(d, name + ".png")):
            continue
        r = Run(view, name, d)
        r.rmse, r.maxdiff, diff = image_error(load_rgb(r.png), ref_img)
        r.diff_png = os.path.join(d, "diff_" + name + ".png")
        heat_map(diff, r.diff_png)
        runs.append(r)
    adaptive = sorted([r for r in runs if r.kind == "adaptive"], key=lambda r: -r.param)
    size = sorted([r for r in runs if r.kind == "size"], key=lambda r: -r.param)
    uniform = sorted([r for r in runs if r.kind == "uniform"], key=lambda r: r.param)
    lowmem = [r for r in runs if r.kind == "lowmem"]
    e_uniform = sorted([r for r in runs if r.kind == "embree_uniform"], key=lambda r: r.param)
    e_subdiv = sorted([r for r in runs if r.kind == "embree_subdiv"], key=lambda r: -r.param)
    # Embree's Catmull-Clark is another surface: its error is measured against
    # its own finest render (the last one), not against our reference.
    if e_subdiv:
        own_ref = load_rgb(e_subdiv[-1].png)
        for r in e_subdiv:
            r.rmse_own = image_error(load_rgb(r.png), own_ref)[0]
    return ref, adaptive, size, uniform, lowmem, e_uniform, e_subdiv


def closest(uniform, a):
    """Uniform run whose RMSE is closest to a's (in log scale)."""
    ok = [u for u in uniform if u.rmse > 0]
    if not ok or a.rmse <= 0:
        return None
    return min(ok, key=lambda u: abs(math.log(u.rmse) - math.log(a.rmse)))


def cheapest_at_most(uniform, a):
    """Lowest uniform level whose RMSE is <= a's (None if none reaches it)."""
    for u in uniform:
        if u.rmse <= a.rmse:
            return u
    return None


def plot_view(out, view, adaptive, uniform, lowmem, x_key, x_label, path, e_uniform=(), e_subdiv=(),
              size=()):
    fig, ax = plt.subplots(figsize=(6.4, 4.6), dpi=100)
    own = [r for r in e_subdiv if r.rmse_own > 0]
    for runs, style, name, err in (
            (adaptive, "o-", "error rule (tolerance, px)", "rmse"),
            (size, "v-", "size rule (paper) (tolerance, px)", "rmse"),
            (uniform, "s--", "uniform subdivision + BVH (level)", "rmse"),
            (e_uniform, "^-.", "uniform level in Embree's BVH (level)", "rmse"),
            (own, "D:", "Embree Catmull-Clark (px/segment; RMSE vs its own finest)", "rmse_own")):
        if not runs:
            continue
        xs = [getattr(r, x_key) for r in runs]
        ys = [getattr(r, err) for r in runs]
        ax.plot(xs, ys, style, label=name)
        for r, x, y in zip(runs, xs, ys):
            ax.annotate(("%g" % r.param), (x, y), textcoords="offset points", xytext=(5, 4), fontsize=8)
    for r in lowmem:
        ax.plot([getattr(r, x_key)], [r.rmse], "*", markersize=11, label="error rule, " + r.label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(x_label)
    ax.set_ylabel("image RMSE vs reference (RGB in [0,1])")
    ax.set_title("%s view: error vs %s" % (view, x_label.split(" (")[0]))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def at_least_as_good_rows(adaptive, uniform, baseline):
    """For each uniform level, the fastest adaptive render (tolerance sweep)
    whose RMSE is <= the uniform's: the comparison at equal-or-better error."""
    rows = []
    for u in uniform:
        ok = [a for a in adaptive if a.rmse <= u.rmse]
        if not ok:
            rows.append({"u": u, "a": None})
            continue
        a = min(ok, key=lambda a: a.total_seconds)
        rows.append({
            "a": a, "u": u,
            "total": ratio(a.total_seconds, u.total_seconds),
            "trace": ratio(a.trace_seconds, u.trace_seconds),
            "rays_s": ratio(a.rays_per_second, u.rays_per_second),
            "mem": ratio(a.peak_rss_mb, u.peak_rss_mb),
            "mem_above": (ratio(a.peak_rss_mb - baseline, u.peak_rss_mb - baseline)
                          if u.peak_rss_mb - baseline >= 50 else float("nan")),
            "nodes": ratio(a.work, u.work),
        })
    return rows


def match_rows(adaptive, uniform):
    rows = []
    for a in adaptive:
        u = closest(uniform, a)
        if u is None:
            continue
        le = cheapest_at_most(uniform, a)
        rows.append({
            "a": a, "u": u, "le": le,
            "total": ratio(a.total_seconds, u.total_seconds),
            "trace": ratio(a.trace_seconds, u.trace_seconds),
            "rays_s": ratio(a.rays_per_second, u.rays_per_second),
            "mem": ratio(a.peak_rss_mb, u.peak_rss_mb),
            "nodes": ratio(a.work, u.work),
        })
    return rows


def embree_tables(view, adaptive, uniform, e_uniform, e_subdiv, para, table, size=()):
    """Embree beside ours: the same uniform mesh in both BVHs, and Embree's own
    subdivision against the adaptive tracer at equal tolerance (the size
    rule's runs, where there are, at equal edge length)."""
    if e_uniform:
        para("Same uniform mesh (our subdivision, same level), our BVH vs Embree's: ratios "
             "ours / Embree. Both start the clock before the mesh is read, so build includes "
             "the uniform subdivision itself. Memory above baseline: each process's peak RSS "
             "minus its RSS before the mesh was read.")
        rows = []
        for e in e_uniform:
            u = [u for u in uniform if u.param == e.param]
            if not u:
                continue
            u = u[0]
            rows.append([u.label, fmt(u.rmse), fmt(e.rmse), fmt(u.total_seconds), fmt(e.total_seconds),
                         fmt(ratio(u.total_seconds, e.total_seconds)),
                         fmt(ratio(u.trace_seconds, e.trace_seconds)),
                         fmt(u.s.get("peak_rss_above_baseline_mb")),
                         fmt(e.s.get("peak_rss_above_baseline_mb"))])
        table(["level", "RMSE ours", "RMSE Embree", "total s ours", "total s Embree",
               "total ratio", "trace ratio", "MB above baseline ours", "MB above baseline Embree"], rows)
    if e_subdiv:
        para("At equal tolerance: the adaptive tracer (error rule) at tolerance T against "
             "Embree's Catmull-Clark subdivision with every base edge cut into segments of at "
             "most T pixels (edge levels from the distance to the camera, the whole mesh "
             "tessellated, no view culling); the last columns give the size rule at T, which "
             "refines while an edge is longer than T pixels, so it is the comparison at equal "
             "edge length ('-' where the sweep has no size-rule render at T). The surfaces differ "
             "(Embree's is Catmull-Clark's limit surface, ours the normal scheme's), so this "
             "compares cost, not error. Ratios ours / Embree; 'uniform level as fine' is the "
             "lowest uniform level whose edges are as short (the error-rule render's deepest "
             "level), for scale.")
        rows, classes = [], []
        for e in e_subdiv:
            a = [a for a in adaptive if a.param == e.param]
            if not a:
                continue
            a = a[0]
            ua = a.s.get("peak_rss_above_baseline_mb") or 0.0
            ea = e.s.get("peak_rss_above_baseline_mb") or 0.0
            deepest = a.s.get("deepest_level")
            ul = [u for u in uniform if u.param == deepest]
            t_ratio = ratio(a.total_seconds, e.total_seconds)
            m_ratio = ratio(ua, ea)
            z = [z for z in size if z.param == e.param]
            z = z[0] if z else None
            z_ratio = ratio(z.total_seconds, e.total_seconds) if z else float("nan")
            rows.append(["%g px" % e.param, fmt(a.total_seconds), fmt(e.total_seconds), fmt(t_ratio),
                         fmt(ratio(a.trace_seconds, e.trace_seconds)),
                         fmt(ua), fmt(ea), fmt(m_ratio),
                         "%s, mean %s max %s" % (fmt(e.s.get("embree_peak_bytes", 0) / 1048576.0),
                                                 fmt(e.s.get("mean_edge_level")),
                                                 fmt(e.s.get("max_edge_level"))),
                         ("level %s: %s s" % (deepest, fmt(ul[0].total_seconds))) if ul else "-",
                         fmt(z.total_seconds) if z else "-", fmt(z_ratio),
                         fmt(ratio(z.s.get("peak_rss_above_baseline_mb") or 0.0, ea)) if z else "-"])
            classes.append(["", "", "", "good" if t_ratio <= 1 else "bad", "", "", "",
                            "good" if m_ratio <= 1 else "bad", "", "", "",
                            "" if math.isnan(z_ratio) else "good" if z_ratio <= 1 else "bad", ""])
        table(["segment / tolerance", "adaptive total s", "Embree total s", "total ratio",
               "trace ratio", "adaptive MB above baseline", "Embree MB above baseline",
               "memory ratio", "Embree MB (its allocator), edge levels", "uniform level as fine",
               "size rule total s", "size rule total ratio", "size rule memory ratio"],
              rows, classes)


# --- POV-Ray ------------------------------------------------------------------

def pov_seconds(text, label):
    m = re.search(label + r":.*?\(([\d.]+) seconds\)", text)
    return float(m.group(1)) if m else float("nan")


def load_povray(out):
    d = os.path.join(out, "povray")
    if not os.path.exists(os.path.join(d, "ref.png")):
        return None
    ref_img = load_rgb(os.path.join(d, "ref.png"))
    runs = []
    for log in sorted(glob.glob(os.path.join(d, "*.log"))):
        name = os.path.basename(log)[:-4]
        png = os.path.join(d, name + ".png")
        if not os.path.exists(png):
            continue
        text = open(log, errors="replace").read()
        m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
        r = {
            "name": name, "png": png,
            "parse": pov_seconds(text, "Parse Time"),
            "trace": pov_seconds(text, "Trace Time"),
            "peak_mb": int(m.group(1)) / 1024.0 if m else float("nan"),
            "nodes": None, "deepest": None,
        }
        m = re.search(r"Subdivision nodes built:\s+(\d+)", text)
        if m:
            r["nodes"] = int(m.group(1))
        m = re.search(r"deepest level reached:\s+(\d+)", text)
        if m:
            r["deepest"] = int(m.group(1))
        r["total"] = r["parse"] + r["trace"]
        if name == "ref":
            r["kind"], r["param"], r["rmse"], r["maxdiff"] = "ref", None, 0.0, 0.0
        else:
            if name.startswith("sdm_t"):
                r["kind"], r["param"] = "subdivision_mesh", float(name[5:])
            elif name.startswith("mesh2_l"):
                r["kind"], r["param"] = "mesh2", int(name[7:])
            else:
                continue
            r["rmse"], r["maxdiff"], diff = image_error(load_rgb(png), ref_img)
            r["diff_png"] = os.path.join(d, "diff_" + name + ".png")
            heat_map(diff, r["diff_png"])
        runs.append(r)
    return runs


def plot_povray(runs, path):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), dpi=100)
    for ax, key, label in ((axes[0], "total", "parse + trace seconds"),
                           (axes[1], "peak_mb", "peak RSS (MB)")):
        for kind, style in (("subdivision_mesh", "o-"), ("mesh2", "s--")):
            rs = sorted([r for r in runs if r["kind"] == kind], key=lambda r: r["param"],
                        reverse=(kind == "subdivision_mesh"))
            ax.plot([r[key] for r in rs], [max(r["rmse"], 1e-6) for r in rs], style, label=kind)
            for r in rs:
                ax.annotate("%g" % r["param"], (r[key], max(r["rmse"], 1e-6)),
                            textcoords="offset points", xytext=(5, 4), fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.set_ylabel("image RMSE vs finest subdivision_mesh")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("POV-Ray: subdivision_mesh (tolerance) vs mesh2 of uniform levels")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# --- output -------------------------------------------------------------------

def rel(out, path):
    return os.path.relpath(path, out)


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    out = os.path.abspath(sys.argv[1])
    info = {}
    if os.path.exists(os.path.join(out, "run_info.txt")):
        for line in open(os.path.join(out, "run_info.txt")):
            if "=" in line:
                k, v = line.rstrip("\n").split("=", 1)
                info[k] = v

    md = ["# Adaptive tracer vs uniform subdivision and Embree", ""]
    h = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>subdivtrace compare</title>",
         "<style>body{font-family:sans-serif;max-width:1400px;margin:1em auto;padding:0 1em}"
         "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:2px 6px;"
         "text-align:right}th{background:#eee}img{border:1px solid #888;margin:2px}"
         "figure{display:inline-block;margin:4px}figcaption{font-size:small}"
         ".good{background:#dfd}.bad{background:#fdd}</style></head><body>",
         "<h1>Adaptive tracer vs uniform subdivision and Embree</h1>"]

    def para(text):
        md.extend([text, ""])
        h.append("<p>%s</p>" % html.escape(text))

    def table(header, rows, classes=None):
        md.append("| " + " | ".join(header) + " |")
        md.append("|" + "---|" * len(header))
        for row in rows:
            md.append("| " + " | ".join(row) + " |")
        md.append("")
        h.append("<table><tr>" + "".join("<th>%s</th>" % html.escape(c) for c in header) + "</tr>")
        for i, row in enumerate(rows):
            cls = classes[i] if classes else [""] * len(row)
            h.append("<tr>" + "".join(
                "<td%s>%s</td>" % ((" class='%s'" % c) if c else "", html.escape(x))
                for x, c in zip(row, cls)) + "</tr>")
        h.append("</table>")

    def images(items):
        for path, caption in items:
            md.append("![%s](%s)" % (caption, rel(out, path)))
        md.append("")
        md.append(" / ".join(c for _, c in items))
        md.append("")
        h.append("<div>" + "".join(
            "<figure><img src='%s'><figcaption>%s</figcaption></figure>"
            % (html.escape(rel(out, p)), html.escape(c)) for p, c in items) + "</div>")

    meshes = ", ".join("%s: %s" % (v, os.path.basename(info["mesh_" + v])) for v in VIEWS
                       if info.get("mesh_" + v)) or os.path.basename(info.get("mesh", "?"))
    para("Meshes: %s. Image %s. Machine: %s; %s. Load average before/after: %s / %s "
         "(the machine is shared: absolute times are noisy, compare ratios). Commit %s, %s."
         % (meshes, info.get("size", "?"), info.get("host", "?"),
            info.get("cpu", "?"), info.get("load_before", "?"), info.get("load_after", "?"),
            info.get("commit", "?"), info.get("date", "?")))
    para("Image error: RGB in [0,1] against the reference render; RMSE over all pixels and "
         "channels, max = largest per-pixel difference. Heat maps: per-pixel max-channel "
         "|difference|, inferno colour map, black = 0, yellow = %g or more. Ratios are "
         "adaptive / uniform (below 1 = the adaptive tracer uses less)." % HEAT_MAX)
    para("Two refinement rules: the error rule (render --refine error, the default: refine "
         "while the surface may lie farther than the tolerance in pixels from what is drawn) "
         "and the paper's size rule (--refine size: refine while an edge is longer than the "
         "tolerance in pixels). 'adaptive' below means the error rule. The reference is the "
         "size rule at tolerance 0.25, max level 10, whichever rule is under test.")

    csv_rows = []
    summary = {}
    rule_summary = []
    for view in VIEWS:
        loaded = load_view(out, view)
        if loaded is None:
            continue
        ref, adaptive, size, uniform, lowmem, e_uniform, e_subdiv = loaded
        title = VIEW_TITLES.get(view, view)
        md.extend(["## %s" % title, ""])
        h.append("<h2>%s</h2>" % html.escape(title))
        para("Mesh: %s. Camera: %s. Reference: %s, %s s total, %s MB peak, %s nodes built, deepest level %s."
             % (os.path.basename(info.get("mesh_" + view) or info.get("mesh", "?")),
                info.get("camera_" + view) or "default (frames the whole mesh)", ref.label,
                fmt(ref.total_seconds), fmt(ref.peak_rss_mb), fmt(ref.work), ref.s.get("deepest_level")))

        p_time = os.path.join(out, "plot_%s_time.png" % view)
        p_mem = os.path.join(out, "plot_%s_memory.png" % view)
        plot_view(out, view, adaptive, uniform, lowmem, "total_seconds", "total seconds (build + trace)",
                  p_time, e_uniform, e_subdiv, size)
        plot_view(out, view, adaptive, uniform, lowmem, "peak_rss_mb", "peak RSS (MB)", p_mem,
                  e_uniform, e_subdiv, size)
        images([(p_time, "RMSE vs total time"), (p_mem, "RMSE vs peak memory")])

        # Both rules side by side, with each render's certified bound.
        md.extend(["### Error rule vs size rule", ""])
        h.append("<h3>Error rule vs size rule</h3>")
        para("Each rule at each tolerance: work, time, memory and image error against the "
             "reference, and beside the measured error the certified bound the render reports "
             "(error_bound_px_max / error_bound_px_mean in --stats-json: every hit's bound on its "
             "distance to the subdivision surface, in pixels; max over hits, mean over hits). "
             "The bound is geometric (pixels of distance), the measured error photometric (RGB "
             "difference, which also includes shading-normal error), so they are shown side "
             "by side, not as the same quantity. 'hits at max level': hits whose leaf is at the "
             "max level (10), where the rule stopped refining, not the tolerance.")
        rows = []
        for r in adaptive + size:
            rows.append([RULE_NAMES.get(r.rule, r.rule), "%g" % r.param, fmt(r.work),
                         fmt(r.total_seconds), fmt(r.peak_rss_mb), fmt(r.rmse), fmt(r.maxdiff),
                         fmt(r.stat("error_bound_px_max")), fmt(r.stat("error_bound_px_mean")),
                         str(r.s.get("deepest_level", "-")), fmt(r.s.get("hits_at_max_level"))])
        table(["rule", "tolerance (px)", "nodes built", "total s", "peak MB", "RMSE vs reference",
               "measured max per-pixel error", "certified bound max (px)",
               "certified bound mean (px)", "deepest level", "hits at max level"], rows)
        e1 = [r for r in adaptive if r.param == 1.0]
        s1 = [r for r in size if r.param == 1.0]
        if e1 and s1:
            e1, s1 = e1[0], s1[0]
            para("Tolerance 1, error rule / size rule: nodes built %s / %s = %s, total time "
                 "%s s / %s s = %s; RMSE %s (error rule) vs %s (size rule); certified bound max "
                 "%s px vs %s px."
                 % (fmt(e1.work), fmt(s1.work), fmt(ratio(e1.work, s1.work)),
                    fmt(e1.total_seconds), fmt(s1.total_seconds),
                    fmt(ratio(e1.total_seconds, s1.total_seconds)), fmt(e1.rmse), fmt(s1.rmse),
                    fmt(e1.stat("error_bound_px_max")), fmt(s1.stat("error_bound_px_max"))))
            rule_summary.append((view, e1, s1))

        md.extend(["### All renders", ""])
        h.append("<h3>All renders</h3>")
        rows = []
        for r in [ref] + adaptive + size + lowmem + uniform + e_uniform + e_subdiv:
            rmse = fmt(r.rmse, 3) if r.kind != "ref" else "0"
            if r.kind == "embree_subdiv":
                rmse = "%s (own: %s)" % (rmse, fmt(r.rmse_own, 3))
            rows.append([r.kind, r.rule or "-", r.label if r.kind != "ref" else "reference",
                         rmse, fmt(r.maxdiff, 3) if r.kind != "ref" else "0",
                         fmt(r.total_seconds), fmt(r.build_seconds), fmt(r.trace_seconds),
                         fmt(r.rays_per_second / 1e6, 3), fmt(r.peak_rss_mb),
                         fmt(r.work), fmt(r.s.get("nodes_visited_per_ray")),
                         str(r.s.get("deepest_level", r.param))])
            csv_rows.append({"view": view, "kind": r.kind, "rule": r.rule, "param": r.param,
                             "rmse": r.rmse,
                             "max_diff": r.maxdiff, "total_s": r.total_seconds,
                             "build_s": r.build_seconds, "trace_s": r.trace_seconds,
                             "rays_per_s": r.rays_per_second, "peak_rss_mb": r.peak_rss_mb,
                             "nodes_or_triangles": r.work, "rays": r.rays,
                             "deepest_level": r.s.get("deepest_level"),
                             "peak_above_baseline_mb": r.s.get("peak_rss_above_baseline_mb"),
                             "rmse_own_surface": r.rmse_own,
                             "error_bound_px_max": r.s.get("error_bound_px_max"),
                             "error_bound_px_mean": r.s.get("error_bound_px_mean"),
                             "hits_at_max_level": r.s.get("hits_at_max_level")})
        table(["kind", "rule", "setting", "RMSE", "max diff", "total s", "build s", "trace s", "Mrays/s",
               "peak MB", "nodes built / uniform tris", "nodes visited/ray", "deepest level"], rows)
        if e_subdiv:
            para("Embree Catmull-Clark renders: RMSE against our reference measures mostly the "
                 "difference between the two surfaces (Catmull-Clark's limit surface is not the "
                 "normal scheme's); 'own' is against Embree's own finest render (%s)."
                 % e_subdiv[-1].label)
        if e_uniform or e_subdiv:
            embree_tables(view, adaptive, uniform, e_uniform, e_subdiv, para, table, size)

        md.extend(["### Adaptive vs uniform at matching image error", ""])
        h.append("<h3>Adaptive vs uniform at matching image error</h3>")
        para("For each tolerance, the uniform level whose RMSE is closest (log scale); ratios are "
             "adaptive / uniform. 'uniform <= err' is the lowest uniform level at least as accurate "
             "as the adaptive render. Targets (close-up): memory <= 0.1, total time <= 1, "
             "nodes built <= 0.1.")
        mrows = match_rows(adaptive + lowmem, uniform)
        rows, classes = [], []
        for m in mrows:
            a, u, le = m["a"], m["u"], m["le"]
            rows.append([a.label, fmt(a.rmse), u.label, fmt(u.rmse),
                         le.label if le else "none",
                         fmt(m["total"]), fmt(m["trace"]), fmt(m["rays_s"]), fmt(m["mem"]),
                         "%s / %s = %s" % (fmt(a.work), fmt(u.work), fmt(m["nodes"]))])
            classes.append(["", "", "", "", "",
                            "good" if m["total"] <= 1 else "bad",
                            "good" if m["trace"] <= 1 else "bad",
                            "good" if m["rays_s"] >= 1 else "bad",
                            "good" if m["mem"] <= 0.1 else ("" if m["mem"] <= 1 else "bad"),
                            "good" if m["nodes"] <= 0.1 else ("" if m["nodes"] <= 1 else "bad")])
        table(["adaptive", "RMSE", "closest uniform", "RMSE", "uniform <= err",
               "total time ratio", "trace time ratio", "rays/s ratio", "peak memory ratio",
               "nodes built vs uniform triangles"], rows, classes)
        baseline = min(r.peak_rss_mb for r in [ref] + adaptive + size + lowmem + uniform)
        md.extend(["### Uniform level vs the fastest adaptive render at least as accurate", ""])
        h.append("<h3>Uniform level vs the fastest adaptive render at least as accurate</h3>")
        para("For each uniform level, the adaptive render (tolerance sweep) with the smallest total "
             "time among those whose RMSE is <= the uniform's: the comparison at equal or better "
             "error. Ratios adaptive / uniform. 'above baseline' subtracts the smallest peak RSS of "
             "any render here (%s MB, the CLI process itself) from both; '-' where the uniform is within "
             "50 MB of it." % fmt(baseline))
        erows = at_least_as_good_rows(adaptive, uniform, baseline)
        rows, classes = [], []
        for m in erows:
            u, a = m["u"], m["a"]
            if a is None:
                rows.append([u.label, fmt(u.rmse), "none as accurate"] + ["-"] * 8)
                classes.append([""] * 11)
                continue
            rows.append([u.label, fmt(u.rmse), a.label, fmt(a.rmse),
                         fmt(m["total"]), fmt(m["trace"]), fmt(m["rays_s"]), fmt(m["mem"]),
                         fmt(m["mem_above"]),
                         "%s / %s = %s" % (fmt(a.work), fmt(u.work), fmt(m["nodes"])),
                         "%s s / %s s" % (fmt(a.total_seconds), fmt(u.total_seconds))])
            classes.append(["", "", "", "",
                            "good" if m["total"] <= 1 else "bad",
                            "good" if m["trace"] <= 1 else "bad",
                            "good" if m["rays_s"] >= 1 else "bad",
                            "good" if m["mem"] <= 0.1 else ("" if m["mem"] <= 1 else "bad"),
                            "" if math.isnan(m["mem_above"]) else
                            "good" if m["mem_above"] <= 0.1 else ("" if m["mem_above"] <= 1 else "bad"),
                            "good" if m["nodes"] <= 0.1 else ("" if m["nodes"] <= 1 else "bad"), ""])
        table(["uniform", "RMSE", "fastest adaptive with RMSE <=", "RMSE", "total time ratio",
               "trace time ratio", "rays/s ratio", "peak memory ratio", "memory above baseline",
               "nodes built vs uniform triangles", "total seconds"], rows, classes)
        summary[view] = (mrows, erows)

        # The paper's Fig. 2 (which level each pixel's leaf came from) and the
        # certified bound per pixel, each a false-colour image with its legend.
        def false_colour_section(stem, title, text, caption):
            png = os.path.join(out, view, stem + ".png")
            txt = os.path.join(out, view, stem + ".txt")
            if not (os.path.exists(png) and os.path.exists(txt)):
                return
            md.extend(["### " + title, ""])
            h.append("<h3>%s</h3>" % title)
            para(text)
            legend_text = open(txt).read()
            md.extend(["```", legend_text.rstrip("\n"), "```", ""])
            h.append("<pre>%s</pre>" % html.escape(legend_text))
            images([(png, caption)])

        false_colour_section(
            "levels_t1", "Levels used at tolerance 1",
            "False colours by the subdivision level of the leaf each camera ray hit "
            "(subdivtrace render --color-by level, headlight shading only); legend:",
            "leaf level per pixel, tolerance 1")
        false_colour_section(
            "error_t1", "Certified error bound at tolerance 1",
            "False colours by each camera ray's hit's certified bound on its distance to "
            "the subdivision surface, in pixels (error rule, tolerance 1; subdivtrace render "
            "--color-by error); legend:",
            "certified error bound per pixel, error rule, tolerance 1")

        # Side by side: reference, adaptive tol 1, closest uniform; diff maps.
        a1 = [a for a in adaptive if a.param == 1.0] or adaptive[len(adaptive) // 2:][:1]
        if a1:
            a1 = a1[0]
            u1 = closest(uniform, a1)
            md.extend(["### Images", ""])
            h.append("<h3>Images</h3>")
            items = [(ref.png, "reference"), (a1.png, "error rule %s (RMSE %s, %s s, %s MB)"
                                              % (a1.label, fmt(a1.rmse), fmt(a1.total_seconds), fmt(a1.peak_rss_mb)))]
            s1 = [r for r in size if r.param == a1.param]
            if s1:
                items.append((s1[0].png, "%s (RMSE %s, %s s, %s MB)" % (
                    s1[0].label, fmt(s1[0].rmse), fmt(s1[0].total_seconds), fmt(s1[0].peak_rss_mb))))
            if u1:
                items.append((u1.png, "uniform %s (RMSE %s, %s s, %s MB)"
                              % (u1.label, fmt(u1.rmse), fmt(u1.total_seconds), fmt(u1.peak_rss_mb))))
            e1 = [e for e in e_subdiv if e.param == a1.param]
            if e1:
                items.append((e1[0].png, "%s (Catmull-Clark, %s s, %s MB)"
                              % (e1[0].label, fmt(e1[0].total_seconds), fmt(e1[0].peak_rss_mb))))
            images(items)
            items = [(a1.diff_png, "|error rule %s - reference|, max %s" % (a1.label, fmt(a1.maxdiff)))]
            if s1:
                items.append((s1[0].diff_png, "|%s - reference|, max %s" % (s1[0].label, fmt(s1[0].maxdiff))))
            if u1:
                items.append((u1.diff_png, "|uniform %s - reference|, max %s" % (u1.label, fmt(u1.maxdiff))))
            images(items)
            coarse = [u for u in uniform if u.param <= 1]
            if coarse:
                images([(u.diff_png, "|uniform %s - reference| (RMSE %s)" % (u.label, fmt(u.rmse)))
                        for u in coarse] +
                       [(a.diff_png, "|adaptive %s - reference| (RMSE %s)" % (a.label, fmt(a.rmse)))
                        for a in adaptive if a.param >= 4])

    # Summary table across views.
    if summary:
        md.extend(["## Summary", ""])
        h.append("<h2>Summary</h2>")
        if rule_summary:
            para("Error rule against the paper's size rule, both at tolerance 1. Ratios error "
                 "rule / size rule.")
            table(["view", "nodes error", "nodes size", "nodes ratio", "total s error",
                   "total s size", "time ratio", "RMSE error", "RMSE size",
                   "bound max px error", "bound max px size"],
                  [[v, fmt(e.work), fmt(z.work), fmt(ratio(e.work, z.work)), fmt(e.total_seconds),
                    fmt(z.total_seconds), fmt(ratio(e.total_seconds, z.total_seconds)), fmt(e.rmse),
                    fmt(z.rmse), fmt(e.stat("error_bound_px_max")), fmt(z.stat("error_bound_px_max"))]
                   for v, e, z in rule_summary])
        para("Adaptive (error rule) at tolerance 1 against the uniform level of closest error, and "
             "each uniform level from 3 (the fine view: from its second-finest level) against the "
             "fastest adaptive render at least as accurate. Ratios adaptive / uniform.")
        rows = []
        for view, (mrows, erows) in summary.items():
            finest = max([m["u"].param for m in erows] or [0])
            from_level = min(3, max(finest - 1, 0))
            for m in mrows:
                if m["a"].param == 1.0:
                    rows.append([view, "closest error", m["a"].label, m["u"].label, fmt(m["a"].rmse),
                                 fmt(m["u"].rmse), fmt(m["total"]), fmt(m["trace"]), fmt(m["rays_s"]),
                                 fmt(m["mem"]), fmt(m["nodes"])])
            for m in erows:
                if m["a"] is not None and m["u"].param >= from_level:
                    rows.append([view, "adaptive <= error", m["a"].label, m["u"].label, fmt(m["a"].rmse),
                                 fmt(m["u"].rmse), fmt(m["total"]), fmt(m["trace"]), fmt(m["rays_s"]),
                                 fmt(m["mem"]), fmt(m["nodes"])])
        table(["view", "match", "adaptive", "uniform", "RMSE adaptive", "RMSE uniform", "total time",
               "trace time", "rays/s", "peak memory", "nodes/triangles"], rows)

    pov = load_povray(out)
    if pov:
        md.extend(["## POV-Ray: subdivision_mesh vs mesh2", ""])
        h.append("<h2>POV-Ray: subdivision_mesh vs mesh2</h2>")
        para("Same scene (shadows, ground plane, no anti-aliasing, 2 threads) with either a "
             "subdivision_mesh of the mesh at a tolerance or a mesh2 include of a uniform level "
             "(subdivtrace export-mesh2). Error against the finest subdivision_mesh render. Parse "
             "and trace time from POV-Ray's summary, peak RSS from /usr/bin/time -v (the whole "
             "povray process, so parse memory included).")
        p = os.path.join(out, "plot_povray.png")
        plot_povray(pov, p)
        images([(p, "POV-Ray: RMSE vs time and memory")])
        rows = []
        for r in sorted(pov, key=lambda r: (r["kind"], -(r["param"] or 0) if r["kind"] != "mesh2" else r["param"])):
            rows.append([r["kind"], "-" if r["param"] is None else "%g" % r["param"], fmt(r["rmse"]),
                         fmt(r["maxdiff"]), fmt(r["parse"]), fmt(r["trace"]), fmt(r["total"]),
                         fmt(r["peak_mb"]), fmt(r["nodes"]) if r["nodes"] is not None else "-"])
            csv_rows.append({"view": "povray", "kind": r["kind"], "param": r["param"], "rmse": r["rmse"],
                             "max_diff": r["maxdiff"], "total_s": r["total"], "build_s": r["parse"],
                             "trace_s": r["trace"], "rays_per_s": "", "peak_rss_mb": r["peak_mb"],
                             "nodes_or_triangles": r["nodes"], "rays": "", "deepest_level": r["deepest"]})
        table(["object", "tolerance / level", "RMSE", "max diff", "parse s", "trace s", "total s",
               "peak MB", "nodes built"], rows)
        ref = [r for r in pov if r["kind"] == "ref"]
        a = [r for r in pov if r["kind"] == "subdivision_mesh"]
        m2 = sorted([r for r in pov if r["kind"] == "mesh2"], key=lambda r: r["param"])
        items = [(r["png"], "%s %s" % (r["kind"], "" if r["param"] is None else "%g" % r["param"]))
                 for r in ref + a[-1:] + m2[-2:]]
        images(items)
        images([(r["diff_png"], "|%s %g - ref| (RMSE %s)" % (r["kind"], r["param"], fmt(r["rmse"])))
                for r in a + m2])

    with open(os.path.join(out, "results.csv"), "w", newline="") as f:
        if csv_rows:
            w = csv.DictWriter(f, fieldnames=list(csv_rows[0].keys()))
            w.writeheader()
            w.writerows(csv_rows)
    h.append("</body></html>")
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    with open(os.path.join(out, "report.html"), "w") as f:
        f.write("\n".join(h) + "\n")
    print("report: %s (and report.md, results.csv)" % os.path.join(out, "report.html"))


if __name__ == "__main__":
    main()
