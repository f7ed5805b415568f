#!/usr/bin/env bash
# Installs every Debian package subdivtrace needs to build, test and render.
# Idempotent: packages already present are skipped. Needs root (or sudo).
set -euo pipefail

packages=(
    # toolchain
    g++ cmake make ccache pkg-config
    # libsubdivtrace
    libopenmesh-dev libglm-dev libopenimageio-dev
    # OpenImageIO's CMake config refers to its tools (Debian bug), and idiff is handy
    openimageio-tools
    # tests and benchmarks
    catch2 libbenchmark-dev
    # compare/: Embree 3, the peer renderer (its BVH and its own subdivision)
    libembree-dev
    # fuzzing (tests/fuzz/run.sh): clang with libFuzzer and its sanitizer runtimes
    clang libclang-rt-dev
    # stock POV-Ray (reference renders of exported mesh2) and the patched build
    povray povray-includes
    autoconf automake dpkg-dev libboost-thread-dev libboost-date-time-dev
    libtiff-dev libpng-dev libjpeg-dev zlib1g-dev libopenexr-dev
    # compare/ report
    python3 python3-numpy python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
        missing+=("$p")
    fi
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "setup: all ${#packages[@]} packages already installed"
    exit 0
fi

echo "setup: installing ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
    sudo_cmd=()
elif command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
else
    echo "setup: these packages are missing and installing them needs root or sudo:" >&2
    echo "  ${missing[*]}" >&2
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
