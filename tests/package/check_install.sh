#!/usr/bin/env bash
# Installs a build into a scratch prefix and uses it from outside the tree, as a user would:
# `stsim --version`, a replay with the installed tool, a tiny program built with pkg-config,
# examples/own_loop built with find_package(stsim) and run on a shipped network (it must warn),
# and `import stsim` from the installed Python module when it was built.
# usage: tests/package/check_install.sh [BUILD_DIR]   (run from anywhere; ~1 min)
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$src/build}" && pwd)
work=$(mktemp -d /tmp/stsim-install.XXXXXX)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
fail() { echo "check_install: FAIL: $*" >&2; exit 1; }

version=$(sed -n 's/^project(stsim VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
cmake --install "$build" --prefix "$prefix" >/dev/null

# the tool
got=$("$prefix/bin/stsim" --version)
[ "$got" = "stsim $version" ] || fail "stsim --version printed '$got', expected 'stsim $version'"
"$prefix/bin/stsim" highway --fcd "$src/tests/data/highway/lanedrop.fcd.xml" \
  --net "$src/tests/data/highway/lanedrop.net.xml" --out "$work/replay" >/dev/null
[ "$(wc -l < "$work/replay/warnings.csv")" -gt 1 ] || fail "the installed stsim replay wrote no warnings"

# headers and libraries through pkg-config
libdir=$(dirname "$(find "$prefix" -name stsim.pc -print -quit)")
g++ -O1 -o "$work/tiny" "$src/tests/package/tiny.cpp" \
  $(PKG_CONFIG_PATH=$libdir pkg-config --cflags --libs stsim) || fail "tiny.cpp does not build with pkg-config"
"$work/tiny" >/dev/null || fail "tiny program: no warning"

# the example with find_package(stsim), on the installed copy of a shipped network
cmake -S "$src/examples/own_loop" -B "$work/own_loop" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/own_loop" >/dev/null || fail "examples/own_loop does not build against the installed tree"
(cd "$work" && timeout 300 "$work/own_loop/own_loop" "$prefix/share/stsim/networks/motorway/motorway.sumocfg" 60) \
  > "$work/own_loop.txt" || fail "own_loop failed: $(tail -1 "$work/own_loop.txt")"
line=$(grep '^own_loop (stsim' "$work/own_loop.txt") || fail "own_loop printed no summary"
n=$(echo "$line" | sed -n 's/.* \([0-9][0-9]*\) warnings in .*/\1/p')
[ -n "$n" ] && [ "$n" -gt 0 ] || fail "own_loop gave no warnings: $line"
[ "$(grep -c ' min TTC ' "$work/own_loop.txt")" -eq "$n" ] || fail "own_loop: warning lines and count differ"

# the Python module, if this build has it
pydir=$(find "$prefix" -type d -path '*-packages/stsim' -print -quit)
if [ -n "$pydir" ]; then
  pyver=$(cd "$work" && PYTHONPATH=$(dirname "$pydir") python3 -c "import stsim; print(stsim.__version__)") \
    || fail "import stsim from $(dirname "$pydir") failed"
  [ "$pyver" = "$version" ] || fail "stsim.__version__ is '$pyver', expected '$version'"
fi
echo "check_install: ok (stsim $version; own_loop: $line)"
