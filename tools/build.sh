#!/usr/bin/env bash
# Installs what is missing, configures and builds stsim into ./build (or $STSIM_BUILD_DIR).
# Extra arguments go to CMake, e.g. tools/build.sh -DSTSIM_SANITIZE=ON
# STSIM_CMAKE_ARGS: more CMake arguments from the environment, split on spaces, given before the
# command line's (CI sets STSIM_CMAKE_ARGS=-DSTSIM_WERROR=ON: a compiler warning fails its build).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
"$here/tools/install-deps.sh"
build=${STSIM_BUILD_DIR:-$here/build}
read -r -a env_args <<<"${STSIM_CMAKE_ARGS:-}"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE:-Release} "${env_args[@]}" "$@" >/dev/null
cmake --build "$build" -j "$(nproc)"
