#!/usr/bin/env bash
# Installs what is missing, configures and builds stsim into ./build (or $STSIM_BUILD_DIR).
# Extra arguments go to CMake, e.g. tools/build.sh -DSTSIM_SANITIZE=ON
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
"$here/tools/install-deps.sh"
build=${STSIM_BUILD_DIR:-$here/build}
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE:-Release} "$@" >/dev/null
cmake --build "$build" -j "$(nproc)"
