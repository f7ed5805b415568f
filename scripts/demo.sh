#!/usr/bin/env bash
# Builds everything (library, CLI, patched POV-Ray) and renders the demo
# comparison: the demo scene through subdivision_mesh and through mesh2, the
# standalone renderer's adaptive image beside the base mesh, and the compare/
# report (side-by-side images, diff maps, error against time and memory).
#   bash scripts/demo.sh
# Output: build/demo/ (standalone renders), build/scenes/ (POV-Ray renders),
# build/compare/report.html.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=2

step() { printf '\n== %s ==\n' "$*"; }

step "installing packages"
bash scripts/setup.sh

step "building (Release)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$jobs"

step "building the patched POV-Ray"
cmake --build build --target povray

step "rendering the demo scene through subdivision_mesh and mesh2"
bash scenes/render_demo.sh build

step "standalone renders: base mesh, uniform level 3, adaptive"
mkdir -p build/demo
cli=build/bin/subdivtrace
mesh=data/bunny_lowpoly.obj
"$cli" render "$mesh" -o build/demo/base_mesh.png --uniform 0 --quiet
"$cli" render "$mesh" -o build/demo/uniform_level3.png --uniform 3 --quiet \
    --stats-json build/demo/uniform_level3.json
"$cli" render "$mesh" -o build/demo/adaptive.png --stats-json build/demo/adaptive.json

if [ -f compare/run.sh ]; then
    step "compare/: error against run time and memory"
    bash compare/run.sh build --quick
fi

step "done"
echo "standalone renders: build/demo/*.png"
echo "POV-Ray renders:    build/scenes/*.png"
[ -f build/compare/report.html ] && echo "comparison report:  build/compare/report.html"
exit 0
