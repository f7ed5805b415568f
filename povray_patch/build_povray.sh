#!/usr/bin/env bash
# Builds POV-Ray 3.7.0.10 (Debian's povray_3.7.0.10-2 source package) with the
# subdivision_mesh primitive, linked against libsubdivtrace.
#
# usage: build_povray.sh BUILD_DIR [LIBSUBDIVTRACE_A]
#   BUILD_DIR         the CMake binary directory; everything goes to BUILD_DIR/povray
#   LIBSUBDIVTRACE_A  the static library (default BUILD_DIR/libsubdivtrace/libsubdivtrace.a)
# output: BUILD_DIR/povray/src/unix/povray
#
# Steps, each done once and remembered by a stamp file in BUILD_DIR/povray/stamps:
#   fetch      apt-get source --download-only povray, through a private deb-src
#              config whose mirror is read from this machine's apt sources
#   unpack     dpkg-source -x (Debian's patches applied), libraries/ moved aside,
#              a pristine copy kept in BUILD_DIR/povray/pristine
#   configure  unix/prebuild.sh and ./configure (CXX="ccache g++", -O2)
# and on every run:
#   patch      subdivision_mesh.patch applied to copies of the pristine files it
#              touches, plus the new files under povray_patch/source/; only files
#              whose content differs are written into the tree, so make rebuilds
#              only what changed
#   make -j2   (POVRAY_JOBS overrides), linking libsubdivtrace
set -euo pipefail

if [ $# -lt 1 ]; then
    echo "usage: $0 BUILD_DIR [LIBSUBDIVTRACE_A]" >&2
    exit 2
fi
build_dir=$(realpath -m "$1")
patch_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
project_dir=$(dirname "$patch_dir")
lib_a=$(realpath -m "${2:-$build_dir/libsubdivtrace/libsubdivtrace.a}")
lib_include="$project_dir/libsubdivtrace/include"
jobs=${POVRAY_JOBS:-2}

pov_dir="$build_dir/povray"
apt_dir="$pov_dir/apt"
dl_dir="$pov_dir/download"
src_dir="$pov_dir/src"
pristine_dir="$pov_dir/pristine"
stamp_dir="$pov_dir/stamps"
mkdir -p "$pov_dir" "$stamp_dir"

say() { echo "povray: $*"; }

# --- fetch ------------------------------------------------------------------
# The first deb URI of the machine's own Debian mirror (deb822 or one-line form).
debian_mirror() {
    local uri=""
    if compgen -G "/etc/apt/sources.list.d/*.sources" >/dev/null; then
        uri=$(awk '
            /^Types:/ { deb = ($0 ~ /[ \t]deb([ \t]|$)/) }
            /^URIs:/ && deb { for (i = 2; i <= NF; i++) if ($i !~ /security/) { print $i; exit } }
        ' /etc/apt/sources.list.d/*.sources)
    fi
    if [ -z "$uri" ] && [ -f /etc/apt/sources.list ]; then
        uri=$(awk '$1 == "deb" {
                for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) { if ($i !~ /security/) { print $i; exit } break }
            }' /etc/apt/sources.list)
    fi
    echo "$uri"
}

if [ ! -f "$stamp_dir/fetch" ]; then
    say "fetching source (apt-get source povray)"
    mirror=$(debian_mirror)
    if [ -z "$mirror" ]; then
        echo "povray: no Debian mirror found in /etc/apt/sources.list.d/*.sources or /etc/apt/sources.list" >&2
        exit 1
    fi
    suite=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")
    mkdir -p "$apt_dir/parts" "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" "$dl_dir"
    cat > "$apt_dir/parts/src.sources" <<EOF
Types: deb-src
URIs: $mirror
Suites: $suite
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    # Lists and caches stay private too: the system's apt state is not touched.
    apt_opts=(-o "Dir::Etc::SourceList=/dev/null" -o "Dir::Etc::SourceParts=$apt_dir/parts"
              -o "Dir::State::Lists=$apt_dir/lists" -o "Dir::Cache=$apt_dir/cache")
    if [ "$(id -u)" -eq 0 ]; then
        # root downloads into a directory the _apt sandbox user may not write
        apt_opts+=(-o "APT::Sandbox::User=root")
    fi
    say "  mirror $mirror ($suite)"
    apt-get "${apt_opts[@]}" -qq update
    (cd "$dl_dir" && apt-get "${apt_opts[@]}" -qq source --download-only povray)
    touch "$stamp_dir/fetch"
fi

# --- unpack -----------------------------------------------------------------
if [ ! -f "$stamp_dir/unpack" ]; then
    say "unpacking source"
    dsc=$(ls "$dl_dir"/povray_*.dsc | head -n 1)
    rm -rf "$src_dir" "$pristine_dir" "$stamp_dir/configure" "$stamp_dir/applied"
    dpkg-source --no-check -x "$dsc" "$src_dir" >/dev/null
    # The bundled zlib/png/jpeg/tiff/openexr are old; use the system's.
    mv "$src_dir/libraries" "$src_dir/libraries.donotuse"
    cp -a "$src_dir" "$pristine_dir"
    touch "$stamp_dir/unpack"
fi

# --- patch ------------------------------------------------------------------
# Files the patch creates or modifies (paths relative to the tree).
patch_file="$patch_dir/subdivision_mesh.patch"
new_src_dir="$patch_dir/source"
touched_files() {
    if [ -f "$patch_file" ]; then
        sed -n 's/^+++ [^/]*\/\([^\t]*\).*/\1/p' "$patch_file"
    fi
    if [ -d "$new_src_dir" ]; then
        (cd "$patch_dir" && find source -type f)
    fi
}

apply_patch() {
    local stage="$pov_dir/stage" f
    rm -rf "$stage"
    mkdir -p "$stage"
    # The union of what the previous and the current patch touch, so that a
    # file dropped from the patch goes back to its pristine content.
    local files
    files=$( { touched_files; cat "$stamp_dir/applied_files" 2>/dev/null || true; } | sort -u)
    for f in $files; do
        if [ -f "$pristine_dir/$f" ]; then
            mkdir -p "$stage/$(dirname "$f")"
            cp -p "$pristine_dir/$f" "$stage/$f"
        fi
    done
    if [ -f "$patch_file" ]; then
        patch -s -p1 -d "$stage" --no-backup-if-mismatch < "$patch_file"
    fi
    if [ -d "$new_src_dir" ]; then
        cp -r "$new_src_dir" "$stage/"
    fi
    local changed=0
    for f in $files; do
        if [ -f "$stage/$f" ]; then
            if ! cmp -s "$stage/$f" "$src_dir/$f"; then
                mkdir -p "$src_dir/$(dirname "$f")"
                cp "$stage/$f" "$src_dir/$f"
                say "  updated $f"
                changed=1
            fi
        elif [ -e "$src_dir/$f" ]; then
            rm -f "$src_dir/$f"
            say "  removed $f"
            changed=1
        fi
    done
    touched_files | sort -u > "$stamp_dir/applied_files"
    rm -rf "$stage"
    return 0
}

patch_hash=$( { cat "$patch_file" 2>/dev/null || true; [ -d "$new_src_dir" ] && (cd "$patch_dir" && find source -type f | sort | xargs cat) || true; } | sha256sum | cut -d' ' -f1)
if [ "$(cat "$stamp_dir/applied" 2>/dev/null || true)" != "$patch_hash" ]; then
    say "applying subdivision_mesh.patch"
    apply_patch
    echo "$patch_hash" > "$stamp_dir/applied"
fi

# --- configure --------------------------------------------------------------
# prebuild.sh lists the source files into the Makefile.am files, so adding or
# removing a file under povray_patch/source/ means prebuild + configure again.
new_files=$(touched_files | while read -r f; do [ -f "$pristine_dir/$f" ] || echo "$f"; done | sort -u)
configure_key="include $lib_include
$new_files"
if [ "$(cat "$stamp_dir/configure" 2>/dev/null || echo none)" != "$configure_key" ]; then
    say "configuring (prebuild.sh + configure)"
    (cd "$src_dir/unix" && ./prebuild.sh >"$pov_dir/prebuild.log" 2>&1) || {
        echo "povray: prebuild.sh failed, see $pov_dir/prebuild.log" >&2; exit 1; }
    # g++ 12 defaults to gnu++17, the library's standard, so POV-Ray and the
    # adapter compile in the same mode; only the include path is added here.
    (cd "$src_dir" && ./configure COMPILED_BY="subdivtrace build_povray.sh" \
        --with-boost-thread=boost_thread --disable-optimiz --disable-strip \
        CXX="ccache g++" CXXFLAGS="-O2" CPPFLAGS="-I$lib_include" \
        >"$pov_dir/configure.log" 2>&1) || {
        echo "povray: configure failed, see $pov_dir/configure.log" >&2; exit 1; }
    echo "$configure_key" > "$stamp_dir/configure"
fi

# --- build ------------------------------------------------------------------
# The library is linked through LIBS on make's command line: configure's own
# link tests must not depend on it, and the value is recomputed on every run.
# libsubdivtrace.a comes after libpovray.a (LDADD) and before the system libs.
configured_libs=$(sed -n 's/^LIBS = //p' "$src_dir/unix/Makefile")
link_libs=""
if [ -f "$lib_a" ]; then
    link_libs="$lib_a -lpthread"
    # make does not know the binary depends on the library.
    if [ "$src_dir/unix/povray" -ot "$lib_a" ]; then
        rm -f "$src_dir/unix/povray"
    fi
elif grep -q SUBDIVISION_MESH_TOKEN "$src_dir/source/backend/parser/reswords.h"; then
    echo "povray: $lib_a is missing: build the subdivtrace target first" >&2
    exit 1
fi
say "building (ccache, make -j$jobs)"
start=$(date +%s)
cd "$src_dir"
make -j"$jobs" LIBS="$link_libs $configured_libs" >"$pov_dir/make.log" 2>&1 || {
    grep -E "error|Error" "$pov_dir/make.log" | head -n 40 >&2
    echo "povray: make failed, see $pov_dir/make.log" >&2
    exit 1
}
say "built $src_dir/unix/povray in $(( $(date +%s) - start )) s"
