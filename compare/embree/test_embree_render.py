#!/usr/bin/python3
"""ctest: embree_render draws what `subdivtrace render` draws.

usage: test_embree_render.py EMBREE_RENDER SUBDIVTRACE_CLI MESH WORK_DIR

The same uniform level-2 mesh through our BVH and through Embree's, same
camera and light: the images must agree (float vs double hits: at most 1% of
pixels more than 3/255 apart, none of them in background/object disagreement
beyond the silhouette). Embree's Catmull-Clark render must cover about the
same pixels, and both stats JSONs must carry the fields compare/report.py reads.
"""
import json
import os
import subprocess
import sys


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(maxsplit=4)
    assert parts[0] == b"P6", path
    w, h, maxval = int(parts[1]), int(parts[2]), int(parts[3])
    assert maxval == 255
    pixels = parts[4]
    assert len(pixels) == w * h * 3, path
    return w, h, pixels


def run(args):
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (r.returncode, " ".join(args), r.stderr))


def main():
    embree, cli, mesh, work = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    view = ["--width", "64", "--height", "48", "--look-from", "2.2,1.6,3.1", "--look-at",
            "0,0.1,0", "--fov", "40", "--quiet", "--threads", "2"]
    out = {name: os.path.join(work, name) for name in ("ours", "embree", "cc")}
    run([cli, "render", mesh, "-o", out["ours"] + ".ppm", "--uniform", "2",
         "--stats-json", out["ours"] + ".json"] + view)
    run([embree, mesh, "-o", out["embree"] + ".ppm", "--uniform", "2",
         "--stats-json", out["embree"] + ".json"] + view)
    run([embree, mesh, "-o", out["cc"] + ".ppm", "--subdiv-pixels", "1",
         "--stats-json", out["cc"] + ".json"] + view)

    w, h, ours = read_ppm(out["ours"] + ".ppm")
    _, _, theirs = read_ppm(out["embree"] + ".ppm")
    _, _, cc = read_ppm(out["cc"] + ".ppm")
    background = ours[0:3]
    far_apart = sum(1 for p in range(0, len(ours), 3)
                    if max(abs(ours[p + c] - theirs[p + c]) for c in range(3)) > 3)
    covered = lambda img: sum(1 for p in range(0, len(img), 3) if img[p:p + 3] != background)
    print("pixels > 3/255 apart: %d of %d; covered: ours %d, Embree %d, Catmull-Clark %d"
          % (far_apart, w * h, covered(ours), covered(theirs), covered(cc)))
    assert covered(ours) > w * h // 10, "the mesh is barely in view"
    assert far_apart <= w * h // 100, "Embree's image of the same mesh differs from ours"
    # Catmull-Clark shrinks the control mesh a little: similar, not equal, coverage.
    assert 0.7 * covered(ours) < covered(cc) < 1.3 * covered(ours), "Catmull-Clark render off"

    for name in out:
        s = json.load(open(out[name] + ".json"))
        for key in ("build_seconds", "trace_seconds", "total_seconds", "peak_rss_mb",
                    "peak_rss_above_baseline_mb", "rays", "rays_per_second"):
            assert key in s, "%s.json lacks %s" % (name, key)
    cc_stats = json.load(open(out["cc"] + ".json"))
    assert cc_stats["mode"] == "embree_subdiv" and cc_stats["mean_edge_level"] >= 1
    print("ok")


if __name__ == "__main__":
    main()
