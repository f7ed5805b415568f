#!/usr/bin/env python3
"""Writes the big-input scenes of docs/povray.md ("What a declared mesh costs").

    python3 scripts/big_mesh2_scenes.py OUT_DIR [--around N] [--subdivtrace PATH]

The mesh is data/make_fine_mesh.py's vase (a modeller-style export with
per-vertex normals, uvs and a uv seam): --around 735 (the default) gives
472,103 vertices and 943,469 triangles. OUT_DIR receives

- vase.obj, vase.ply (binary PLY, written by `subdivtrace subdivide --levels 0`),
- vase_body.inc: the body of a mesh2 (vertex_vectors, normal_vectors,
  uv_vectors, face_indices, normal_indices, uv_indices), as an exporter writes it,
- one scene per way of handing the mesh to POV-Ray, each at max_level 0:
  mesh2.pov (the native mesh2 alone), declared.pov (#declare M = mesh2 {...},
  then subdivision_mesh { M }), declared_undef.pov (the same, #undef M right
  after), inline.pov (subdivision_mesh { mesh2 {...} }) and file.pov
  (subdivision_mesh { file "vase.ply" }).

Render each from OUT_DIR, e.g.
`/usr/bin/time -v povray +Imesh2.pov +W320 +H240 -D -V +L<povray>/include`;
the parse time is in POV-Ray's summary. Nothing here is committed: the files
take about 265 MB at the default size (the mesh2 body alone 130 MB).
"""

import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

SCENE_HEAD = """// %s (scripts/big_mesh2_scenes.py)
camera { location <0, 1.6, -4.2> look_at <0, 0.9, 0> angle 40 }
light_source { <-4, 6, -5> rgb 1 }
background { rgb <0.2, 0.3, 0.4> }
#declare Tex = texture { pigment { rgb <0.85, 0.6, 0.4> } finish { specular 0.3 } }
"""

SCENES = {
    "mesh2.pov": "mesh2 {\n#include \"vase_body.inc\"\n texture { Tex } }\n",
    "declared.pov": "#declare M = mesh2 {\n#include \"vase_body.inc\"\n}\n"
                    "subdivision_mesh { M max_level 0 texture { Tex } }\n",
    "declared_undef.pov": "#declare M = mesh2 {\n#include \"vase_body.inc\"\n}\n"
                          "#declare S = subdivision_mesh { M max_level 0 texture { Tex } }\n"
                          "#undef M\nobject { S }\n",
    "inline.pov": "subdivision_mesh { mesh2 {\n#include \"vase_body.inc\"\n}\n"
                  " max_level 0 texture { Tex } }\n",
    "file.pov": "subdivision_mesh { file \"vase.ply\" max_level 0 texture { Tex } }\n",
}


def read_obj(path):
    v, vt, vn, faces = [], [], [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                v.append(line[2:].split())
            elif line.startswith("vt "):
                vt.append(line[3:].split())
            elif line.startswith("vn "):
                vn.append(line[3:].split())
            elif line.startswith("f "):
                faces.append([[int(i) - 1 for i in c.split("/")] for c in line[2:].split()])
    return v, vt, vn, faces


def write_body(path, v, vt, vn, faces):
    with open(path, "w") as f:
        def block(name, rows):
            f.write("  %s {\n    %d,\n" % (name, len(rows)))
            f.write(",\n".join("    " + r for r in rows))
            f.write("\n  }\n")
        block("vertex_vectors", ["<%s, %s, %s>" % tuple(p) for p in v])
        block("normal_vectors", ["<%s, %s, %s>" % tuple(n) for n in vn])
        block("uv_vectors", ["<%s, %s>" % (t[0], t[1]) for t in vt])
        block("face_indices", ["<%d, %d, %d>" % tuple(c[0] for c in fc) for fc in faces])
        block("normal_indices", ["<%d, %d, %d>" % tuple(c[2] for c in fc) for fc in faces])
        block("uv_indices", ["<%d, %d, %d>" % tuple(c[1] for c in fc) for fc in faces])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("--around", type=int, default=735)
    ap.add_argument("--subdivtrace", default=os.path.join(ROOT, "build", "bin", "subdivtrace"))
    args = ap.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    obj = os.path.join(args.out_dir, "vase.obj")
    subprocess.run([sys.executable, os.path.join(ROOT, "data", "make_fine_mesh.py"), obj,
                    "--around", str(args.around)], check=True)
    subprocess.run([args.subdivtrace, "subdivide", obj, "-o",
                    os.path.join(args.out_dir, "vase.ply"), "--levels", "0"], check=True)
    v, vt, vn, faces = read_obj(obj)
    write_body(os.path.join(args.out_dir, "vase_body.inc"), v, vt, vn, faces)
    for name, body in SCENES.items():
        with open(os.path.join(args.out_dir, name), "w") as f:
            f.write(SCENE_HEAD % name + body)
    print("%s: %d vertices, %d triangles" % (args.out_dir, len(v), len(faces)), file=sys.stderr)


if __name__ == "__main__":
    main()
