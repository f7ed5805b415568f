#!/usr/bin/env bash
# Renders the demo scenes with the patched POV-Ray.
#
# usage: scenes/render_demo.sh BUILD_DIR [WIDTH HEIGHT [SCHEME [UNIFORM_LEVEL]]]
#   BUILD_DIR      CMake binary dir with bin/subdivtrace and povray/src/unix/povray
#                  (cmake --build BUILD_DIR --target povray subdivtrace_cli)
#   WIDTH HEIGHT   image size (default 960 360)
#   SCHEME         normal | loop | butterfly (default normal)
#   UNIFORM_LEVEL  level of the uniform mesh2 in the middle (default 2)
# output: BUILD_DIR/scenes/*.png, and each render's summary in *.log
set -euo pipefail

build_dir=$(realpath "${1:?usage: $0 BUILD_DIR [WIDTH HEIGHT [SCHEME [UNIFORM_LEVEL]]]}")
width=${2:-960}
height=${3:-360}
scheme=${4:-normal}
level=${5:-2}
scenes_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
data_dir="$(dirname "$scenes_dir")/data"
povray="$build_dir/povray/src/unix/povray"
cli="$build_dir/bin/subdivtrace"
out_dir="$build_dir/scenes"
mkdir -p "$out_dir"
case "$scheme" in
    normal) scheme_id=0 ;; loop) scheme_id=1 ;; butterfly) scheme_id=2 ;;
    *) echo "unknown scheme $scheme (normal, loop, butterfly)" >&2; exit 2 ;;
esac

for tool in "$povray" "$cli"; do
    [ -x "$tool" ] || { echo "missing $tool: build the povray and subdivtrace_cli targets" >&2; exit 1; }
done

echo "demo: exporting mesh2 includes (base mesh, uniform $scheme level $level)"
"$cli" export-mesh2 "$data_dir/bunny_lowpoly.obj" -o "$out_dir/bunny_base.inc" \
    --scheme "$scheme" --levels 0 --name Bunny_Base
"$cli" export-mesh2 "$data_dir/bunny_lowpoly.obj" -o "$out_dir/bunny_uniform.inc" \
    --scheme "$scheme" --levels "$level" --name Bunny_Uniform

render() {  # scene.pov output-stem
    echo "demo: rendering $1 (${width}x${height})"
    (cd "$scenes_dir" && "$povray" +I"$1" +O"$out_dir/$2.png" +W"$width" +H"$height" \
        -D +A0.1 +L"$out_dir" +L"$build_dir/povray/src/include" \
        Declare=Scheme="$scheme_id" >"$out_dir/$2.log" 2>&1) || {
        tail -n 20 "$out_dir/$2.log" >&2; exit 1; }
    grep -E "Parse Time|Trace Time|Subdivision|Peak memory" "$out_dir/$2.log" | sed 's/^/  /'
}
render icosahedron_side_by_side.pov icosahedron_side_by_side
render subdivision_demo.pov subdivision_demo
render textured_mesh2.pov textured_mesh2
render creased_mesh2.pov creased_mesh2
echo "demo: images in $out_dir"
