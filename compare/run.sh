#!/usr/bin/env bash
# Adaptive tracer vs uniform subdivision: error against time and memory.
#
#   compare/run.sh BUILD_DIR [--quick] [--reuse] [--no-povray]
#
# Renders three views, one render at a time: data/blob5k.obj from far (the
# whole mesh) and close (the mesh fills the frame and a silhouette crosses
# it), and "fine": an already-fine mesh, a modeller-style export of a vase
# whose triangles are 1-3 px wide in its camera (data/make_fine_mesh.py,
# generated into BUILD_DIR/compare/meshes/; --quick: a coarser one for the
# smaller image). Per view:
#   ref       the paper's size rule at tolerance 0.25, max level 10 (the
#             reference image, the same whichever rule is under test)
#   adaptive  the error rule (--refine error, the default) at tolerance
#             8 4 2 1 0.5 (--quick: 4 2 1 0.5), node cache $CACHE_MB (32 MB),
#             and tolerance 1 with a 16 MB cache (lowmem_t1)
#   size      the size rule (--refine size) at the same tolerances (--quick:
#             2 1)
#   uniform   levels 0..6 (--quick: 0..4; fine: 0..2); a level whose memory,
#             extrapolated from the level before (x4), would exceed ~6 GB is
#             skipped
#   levels_t1 error rule at tolerance 1 in false colours by leaf level (render
#             --color-by level), legend in levels_t1.txt
#   error_t1  error rule at tolerance 1 in false colours by each hit's
#             certified error bound in pixels (--color-by error), legend in
#             error_t1.txt
#   embree    if BUILD_DIR/bin/embree_render exists (Embree 3 found at build
#             time): the uniform levels in Embree's BVH (embree_uniform_l*),
#             and Embree's Catmull-Clark subdivision of the base mesh with
#             edges cut into 4 2 1 0.5 px segments (embree_subdiv_p*; 0.5 px
#             is its own reference)
# Shadows on, default light, same camera for all. Every render writes a PNG and
# its --stats-json next to it in BUILD_DIR/compare/<view>/. Then, if the
# patched POV-Ray exists (BUILD_DIR/povray/src/unix/povray, or $POVRAY), a
# smaller sweep through it into BUILD_DIR/compare/povray/. Finally
# compare/report.py measures the image errors and writes
# BUILD_DIR/compare/report.html and report.md.
#
# --reuse   keep renders whose JSON already exists (re-run the report only)
# --no-povray  skip the POV-Ray sweep
# Environment: SUBDIVTRACE_CLI (default BUILD_DIR/bin/subdivtrace), POVRAY
# (default BUILD_DIR/povray/src/unix/povray), EMBREE_RENDER (default
# BUILD_DIR/bin/embree_render).
set -euo pipefail

usage() { echo "usage: compare/run.sh BUILD_DIR [--quick] [--reuse] [--no-povray]" >&2; exit 2; }
[[ $# -ge 1 ]] || usage
build=$(cd "$1" && pwd)
shift
quick=0 reuse=0 povray_on=1
for a in "$@"; do
    case "$a" in
        --quick) quick=1 ;;
        --reuse) reuse=1 ;;
        --no-povray) povray_on=0 ;;
        *) usage ;;
    esac
done

here=$(cd "$(dirname "$0")" && pwd)
repo=$(dirname "$here")
cli="${SUBDIVTRACE_CLI:-$build/bin/subdivtrace}"
[[ -x "$cli" ]] || { echo "no CLI at $cli (build the subdivtrace_cli target)" >&2; exit 1; }
embree="${EMBREE_RENDER:-$build/bin/embree_render}"
[[ -x "$embree" ]] || embree=""
py=/usr/bin/python3
mesh="$repo/data/blob5k.obj"  # far, close and the POV-Ray sweep
out="$build/compare"
mkdir -p "$out"
# A fresh run starts from no renders: a view's directory left by the other
# mode (--quick renders 320x240, the full run 640x480) would mix sizes.
if [[ $reuse == 0 ]]; then
    rm -rf "$out/far" "$out/close" "$out/fine" "$out/povray" "$out/meshes"
fi

if [[ $quick == 1 ]]; then
    size=(--width 320 --height 240)
    ref_tol=0.25 ref_level=10
    tolerances=(4 2 1 0.5)
    size_tolerances=(2 1)
    levels=(0 1 2 3 4)
    fine_around=90
    pov_size=(+W240 +H180)
    pov_tols=(2 1)
    pov_levels=(0 1 2 3)
    pov_ref_tol=0.5
else
    size=(--width 640 --height 480)
    ref_tol=0.25 ref_level=10
    tolerances=(8 4 2 1 0.5)
    size_tolerances=(8 4 2 1 0.5)
    levels=(0 1 2 3 4 5 6)
    fine_around=180
    pov_size=(+W320 +H240)
    pov_tols=(4 2 1)
    pov_levels=(0 1 2 3 4)
    pov_ref_tol=0.5
fi
# Embree's subdivision: pixels per tessellated segment of a base edge (the
# finest is its own reference image).
embree_pixels=(4 2 1 0.5)
mem_limit_mb=6000
# Node cache budget of the adaptive renders (MB), the CLI's default: a
# ceiling, as the cache keeps only what the picture comes back to below it.
# One extra render per view at tolerance 1 with a 16 MB budget shows how
# little a smaller ceiling changes.
cache_mb=${CACHE_MB:-32}
lowmem_cache_mb=16

# view name -> camera options. Both explicit: the CLI's default camera frames
# the bounding box of the mesh it renders, which for --uniform K is the level-K
# mesh's (slightly smaller), so default framing would differ between renders.
views=(far close fine)
declare -A camera=(
    [far]="--look-from 5.1,3.5,7.3 --look-at 0.02,0.15,-0.07 --fov 40"
    [close]="--look-from 3.0,1.2,1.4 --look-at 0.7,0.5,0.0 --fov 35"
    [fine]="--look-from 0,3.53,6.95 --look-at 0,0.95,0 --fov 40"
)
# view name -> mesh. The fine view's mesh is generated here (5.3 MB at
# 640x480, so not in the repository): 180 vertices around at 640x480, 90 at
# 320x240, so its triangles are 1-3 px wide either way.
fine_mesh="$out/meshes/vase_a$fine_around.obj"
declare -A view_mesh=(
    [far]="$mesh"
    [close]="$mesh"
    [fine]="$fine_mesh"
)
# view name -> uniform levels (the fine mesh is already fine: 0..2)
declare -A view_levels=(
    [far]="${levels[*]}"
    [close]="${levels[*]}"
    [fine]="0 1 2"
)
if [[ ! -s "$fine_mesh" ]]; then
    mkdir -p "$out/meshes"
    "$py" "$repo/data/make_fine_mesh.py" "$fine_mesh" --around "$fine_around"
fi

{
    echo "mesh=$mesh"
    for v in "${views[@]}"; do echo "mesh_$v=${view_mesh[$v]}"; done
    echo "size=${size[*]}"
    echo "quick=$quick"
    echo "date=$(date -Is)"
    echo "host=$(uname -srm), $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GB", $2/1048576}' /proc/meminfo)"
    echo "cpu=$(awk -F': ' '/model name/ {print $2; exit}' /proc/cpuinfo)"
    echo "load_before=$(cut -d' ' -f1-3 /proc/loadavg)"
    echo "commit=$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)$(
        [[ -n $(git -C "$repo" status --porcelain libsubdivtrace 2>/dev/null) ]] && echo " (library sources modified)")"
    echo "cli=$cli"
    for v in "${views[@]}"; do echo "camera_$v=${camera[$v]}"; done
    echo "cache_mb=$cache_mb (lowmem_t1: $lowmem_cache_mb)"
    echo "embree=${embree:-none} ($(dpkg-query -W -f='libembree-dev ${Version}' libembree-dev 2>/dev/null || echo 'libembree-dev not installed'))"
} > "$out/run_info.txt"

start=$(date +%s)
elapsed() { echo $(( $(date +%s) - start ))s; }

# render VIEW NAME ARGS...: one render with retries (the tracer may be rebuilt
# under us); skips if --reuse and the JSON exists. Names embree_* go through
# embree_render, the others through `subdivtrace render`.
render() {
    local view=$1 name=$2
    shift 2
    local program=("$cli" render)
    if [[ $name == embree_* ]]; then program=("$embree"); fi
    local dir="$out/$view"
    mkdir -p "$dir"
    if [[ $reuse == 1 && -s "$dir/$name.json" && -s "$dir/$name.png" ]]; then
        echo "[$(elapsed)] $view/$name: reused"
        return 0
    fi
    local try
    for try in 1 2 3; do
        # shellcheck disable=SC2086
        if "${program[@]}" "${view_mesh[$view]}" -o "$dir/$name.png" "${size[@]}" ${camera[$view]} "$@" \
            --stats-json "$dir/$name.json" --quiet 2> "$dir/$name.log"; then
            "$py" - "$dir/$name.json" "$view/$name" "$(elapsed)" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
print("[%s] %-16s total %7.2fs (build %6.2fs, trace %7.2fs)  peak %7.1f MB  nodes %s" % (
    sys.argv[3], sys.argv[2], s["total_seconds"], s["build_seconds"], s["trace_seconds"],
    s["peak_rss_mb"], s.get("nodes_built", "-")))
EOF
            return 0
        fi
        echo "[$(elapsed)] $view/$name failed (try $try): $(tail -n 2 "$dir/$name.log" | tr '\n' ' ')" >&2
        rm -f "$dir/$name.json"
        [[ $try == 3 ]] || sleep 60
    done
    return 1
}

# false_colour VIEW NAME WHAT: the error rule at tolerance 1 in false colours
# (render --color-by WHAT), legend in NAME.txt. levels_t1 (WHAT level) is the
# paper's Fig. 2, the level of the leaf each pixel hit; error_t1 (WHAT error)
# each hit's certified bound on its distance to the surface, in pixels.
false_colour() {
    local view=$1 name=$2 what=$3 dir="$out/$1"
    mkdir -p "$dir"
    if [[ $reuse == 1 && -s "$dir/$name.png" && -s "$dir/$name.txt" ]]; then
        echo "[$(elapsed)] $view/$name: reused"
        return 0
    fi
    # shellcheck disable=SC2086
    "$cli" render "${view_mesh[$view]}" -o "$dir/$name.png" "${size[@]}" ${camera[$view]} \
        --refine error --tolerance 1 --max-level "$ref_level" --cache-mb "$cache_mb" \
        --color-by "$what" --quiet > "$dir/$name.txt" 2> "$dir/$name.log"
    echo "[$(elapsed)] $view/$name: $(tail -n 1 "$dir/$name.txt" | sed 's/^ *//')"
}

# uniform_level VIEW PREFIX K: the level-K mesh (PREFIX uniform_l: our BVH,
# embree_uniform_l: Embree's), skipped when level K-1 peaked at more than a
# quarter of the memory limit.
uniform_level() {
    local view=$1 prefix=$2 k=$3
    if [[ $k -gt 0 && -s "$out/$view/$prefix$((k - 1)).json" ]]; then
        prev=$("$py" -c 'import json,sys; print(json.load(open(sys.argv[1]))["peak_rss_mb"])' \
            "$out/$view/$prefix$((k - 1)).json")
        if "$py" -c 'import sys; sys.exit(0 if 4 * float(sys.argv[1]) > float(sys.argv[2]) else 1)' \
            "$prev" "$mem_limit_mb"; then
            echo "[$(elapsed)] $view/$prefix$k: skipped (level $((k - 1)) peaked at $prev MB, x4 > $mem_limit_mb MB)"
            rm -f "$out/$view/$prefix$k.json" "$out/$view/$prefix$k.png"
            return 0
        fi
    fi
    render "$view" "$prefix$k" --uniform "$k"
}

for view in "${views[@]}"; do
    echo "== view $view (${camera[$view]:-default camera})"
    render "$view" ref --refine size --tolerance "$ref_tol" --max-level "$ref_level" --cache-mb "$cache_mb"
    false_colour "$view" levels_t1 level
    false_colour "$view" error_t1 error
    for t in "${tolerances[@]}"; do
        render "$view" "adaptive_t$t" --refine error --tolerance "$t" --max-level "$ref_level" \
            --cache-mb "$cache_mb"
    done
    for t in "${size_tolerances[@]}"; do
        render "$view" "size_t$t" --refine size --tolerance "$t" --max-level "$ref_level" \
            --cache-mb "$cache_mb"
    done
    render "$view" lowmem_t1 --refine error --tolerance 1 --max-level "$ref_level" \
        --cache-mb "$lowmem_cache_mb"
    for k in ${view_levels[$view]}; do
        uniform_level "$view" uniform_l "$k"
        if [[ -n $embree ]]; then uniform_level "$view" embree_uniform_l "$k"; fi
    done
    if [[ -n $embree ]]; then
        for p in "${embree_pixels[@]}"; do
            render "$view" "embree_subdiv_p$p" --subdiv-pixels "$p" || true
        done
    fi
done

# --- POV-Ray (optional) -------------------------------------------------------
pov="${POVRAY:-$build/povray/src/unix/povray}"
if [[ $povray_on == 1 && -x "$pov" ]]; then
    echo "== POV-Ray sweep ($pov)"
    pdir="$out/povray"
    mkdir -p "$pdir"
    cp "$mesh" "$pdir/blob5k.obj"
    # pov_render NAME OBJECT_SDL: one scene, stats from the render summary on stderr
    pov_render() {
        local name=$1 object=$2
        if [[ $reuse == 1 && -s "$pdir/$name.png" && -s "$pdir/$name.log" ]]; then
            echo "[$(elapsed)] povray/$name: reused"
            return 0
        fi
        cat > "$pdir/$name.pov" <<EOF
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <3.6, 2.2, 4.2> look_at <0, 0.1, 0> angle 40 }
light_source { <6, 8, 6> color rgb 1 }
light_source { <-5, 3, 4> color rgb 0.3 shadowless }
background { color rgb <0.3, 0.33, 0.38> }
plane { y, -1.05 pigment { color rgb 0.7 } }
$object
EOF
        local try
        for try in 1 2 3; do
            if (cd "$pdir" && /usr/bin/time -v "$pov" +I"$name.pov" +O"$name.png" "${pov_size[@]}" \
                -D +FN +A0.0 -V +WT2 > "$name.out" 2> "$name.log"); then
                echo "[$(elapsed)] povray/$name: $(grep -E 'Elapsed \(wall' "$pdir/$name.log" | sed 's/.*: //') wall, peak $(awk '/Maximum resident/ {printf "%.0f MB", $NF/1024}' "$pdir/$name.log")"
                return 0
            fi
            echo "[$(elapsed)] povray/$name failed (try $try): $(tail -n 3 "$pdir/$name.log" | tr '\n' ' ')" >&2
            [[ $try == 3 ]] || sleep 60
        done
        return 1
    }
    material='texture { pigment { color rgb <0.92, 0.88, 0.8> } finish { diffuse 0.8 specular 0.2 } }'
    pov_render "ref" "subdivision_mesh { file \"blob5k.obj\" scheme normal tolerance $pov_ref_tol max_level 10 cache_mb $cache_mb $material }" || true
    for t in "${pov_tols[@]}"; do
        pov_render "sdm_t$t" "subdivision_mesh { file \"blob5k.obj\" scheme normal tolerance $t max_level 10 cache_mb $cache_mb $material }" || true
    done
    for k in "${pov_levels[@]}"; do
        if [[ $reuse == 0 || ! -s "$pdir/mesh2_l$k.inc" ]]; then
            "$cli" export-mesh2 "$mesh" -o "$pdir/mesh2_l$k.inc" --levels "$k" --name "Blob_l$k" > /dev/null 2>&1
        fi
        pov_render "mesh2_l$k" "#include \"mesh2_l$k.inc\" object { Blob_l$k $material }" || true
    done
elif [[ $povray_on == 0 ]]; then
    echo "== POV-Ray sweep skipped (--no-povray)"
else
    echo "== POV-Ray sweep skipped (no executable at $pov)"
fi

echo "load_after=$(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/run_info.txt"
echo "== report"
"$py" "$here/report.py" "$out"
echo "[$(elapsed)] done: $out/report.html"
