#!/usr/bin/env bash
# Regenerates subdivision_mesh.patch (maintainers only).
#
# usage: make_patch.sh BUILD_DIR
#
# Edit copies of the POV-Ray files the patch changes under
# BUILD_DIR/povray/edit/<same path as in the tree> (start from
# BUILD_DIR/povray/pristine/<path>); this script diffs each against the
# pristine tree with `diff -uN` and labels a/ and b/, as `diff -ruN` would.
# New files live under povray_patch/source/ instead and are copied by
# build_povray.sh.
set -euo pipefail

build_dir=$(realpath -m "${1:?usage: $0 BUILD_DIR}")
patch_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
pristine="$build_dir/povray/pristine"
edit="$build_dir/povray/edit"
out="$patch_dir/subdivision_mesh.patch"

[ -d "$pristine" ] || { echo "no pristine tree in $pristine: run build_povray.sh first" >&2; exit 1; }
[ -d "$edit" ] || { echo "no edited files in $edit" >&2; exit 1; }

tmp=$(mktemp)
(cd "$edit" && find . -type f | sed 's|^\./||' | LC_ALL=C sort) | while read -r f; do
    diff -uN --label "a/$f" --label "b/$f" "$pristine/$f" "$edit/$f" || [ $? -eq 1 ]
done > "$tmp"
mv "$tmp" "$out"
echo "wrote $out ($(grep -c '^+++ ' "$out") files)"
