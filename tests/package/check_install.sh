#!/usr/bin/env bash
# Uses a build from outside the tree, as a user would, twice: installed with
# `cmake --install --prefix`, and from the .deb (`cpack -G DEB`, its Depends and contents checked,
# unpacked with dpkg-deb). In each: `stsim --version`, a replay with its conflict map and a batch
# with its plots by the installed tool with the source tree hidden (unshare -m), a tiny
# program built with pkg-config, examples/own_loop built with find_package(stsim) and run on the
# installed copy of a shipped network (it must warn), examples/arm_loop built with
# find_package(stsim COMPONENTS arm) where SUMO cannot be found, and `import stsim` when the
# module was built.
# usage: tests/package/check_install.sh [BUILD_DIR]   (run from anywhere; about a minute)
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$src/build}" && pwd)
work=$(mktemp -d /tmp/stsim-install.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "check_install: FAIL: $*" >&2; exit 1; }
version=$(sed -n 's/^project(stsim VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
python=/usr/bin/python3

# Runs a command with the source tree (and the build in it) hidden under an empty tmpfs, in a
# mount namespace of its own: what it finds, it found in the install.
without_tree() {
  local ns=(unshare -m)
  [ "$(id -u)" -eq 0 ] || ns=(unshare -rm)  # not root: a user namespace may mount too
  "${ns[@]}" /bin/sh -c 'mount -t tmpfs -o size=1m stsim-hidden "$0" && [ ! -e "$0/CMakeLists.txt" ] && exec "$@"' \
    "$src" "$@"
}
unshare -m true 2>/dev/null || unshare -rm true 2>/dev/null \
  || fail "needs unshare -m (root, or user namespaces) to hide the source tree from the installed stsim"

check_prefix() {  # PREFIX NAME
  local prefix=$1 out=$work/$2
  mkdir -p "$out"
  local got
  got=$("$prefix/bin/stsim" --version)
  [ "$got" = "stsim $version" ] || fail "$2: stsim --version printed '$got', expected 'stsim $version'"
  # from outside the tree, with the tree itself hidden (the build inside it too): the installed
  # stsim finds its plot scripts in share/stsim, so the replay draws its conflict map and a batch
  # draws its plots and per-combination maps
  local data=$out/data
  mkdir -p "$data"
  cp "$src/tests/data/highway/lanedrop.fcd.xml" "$src/tests/data/highway/lanedrop.net.xml" "$data/"
  without_tree "$prefix/bin/stsim" highway --fcd "$data/lanedrop.fcd.xml" --net "$data/lanedrop.net.xml" \
    --out "$out/replay" > "$out/replay.txt" 2>&1 || fail "$2: the installed stsim replay failed: $(tail -1 "$out/replay.txt")"
  [ "$(wc -l < "$out/replay/warnings.csv")" -gt 1 ] || fail "$2: the installed stsim replay wrote no warnings"
  [ -s "$out/replay/conflict_map.png" ] && [ -s "$out/replay/conflict_map.svg" ] \
    || fail "$2: the installed stsim highway drew no conflict map: $(grep -m1 'conflict map' "$out/replay.txt")"
  cat > "$data/plots.yaml" <<EOF
name: installed_plots
command: highway
base: $prefix/share/stsim/networks/ring/scenario.yaml
sweep: {detector: [five, box]}
fixed: {end: 40, action: none}
seeds: [1]
EOF
  without_tree "$prefix/bin/stsim" batch "$data/plots.yaml" --out "$out/batch" --jobs 2 > "$out/batch.txt" 2>&1 \
    || fail "$2: the installed stsim batch failed: $(tail -1 "$out/batch.txt")"
  ! grep -q 'plots skipped' "$out/batch.txt" || fail "$2: installed stsim batch: $(grep -m1 'plots skipped' "$out/batch.txt")"
  local f
  for f in report.md min_ttc_distribution.png conflict_map_five.png conflict_map_box.svg; do
    [ -s "$out/batch/$f" ] || fail "$2: the installed stsim batch wrote no $f"
  done
  grep -q '(conflict_map_five.png)' "$out/batch/report.md" || fail "$2: report.md does not show the conflict maps"

  # headers and libraries through pkg-config
  local pcdir
  pcdir=$(dirname "$(find "$prefix" -name stsim.pc -print -quit)")
  g++ -O1 -o "$out/tiny" "$src/tests/package/tiny.cpp" $(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs stsim) \
    || fail "$2: tiny.cpp does not build with pkg-config"
  "$out/tiny" >/dev/null || fail "$2: tiny program: no warning"

  # the example with find_package(stsim), on the installed copy of a shipped network
  cmake -S "$src/examples/own_loop" -B "$out/own_loop" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
  cmake --build "$out/own_loop" >/dev/null || fail "$2: examples/own_loop does not build against the installed tree"
  (cd "$out" && timeout 300 "$out/own_loop/own_loop" "$prefix/share/stsim/networks/motorway/motorway.sumocfg" 60) \
    > "$out/own_loop.txt" || fail "$2: own_loop failed: $(tail -1 "$out/own_loop.txt")"
  local line n
  line=$(grep '^own_loop (stsim' "$out/own_loop.txt") || fail "$2: own_loop printed no summary"
  n=$(echo "$line" | sed -n 's/.* \([0-9][0-9]*\) warnings in .*/\1/p')
  [ -n "$n" ] && [ "$n" -gt 0 ] || fail "$2: own_loop gave no warnings: $line"
  [ "$(grep -c ' min TTC ' "$out/own_loop.txt")" -eq "$n" ] || fail "$2: own_loop: warning lines and count differ"

  # examples/arm_loop: the arm monitor in a program's own loop, with find_package(stsim COMPONENTS
  # arm) where CMake cannot find SUMO (an arm-only user's machine); two_pandas STOPs both at 1.071 s
  cmake -S "$src/examples/arm_loop" -B "$out/arm_loop" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_DISABLE_FIND_PACKAGE_SUMO=ON >/dev/null || fail "$2: examples/arm_loop does not configure without SUMO"
  cmake --build "$out/arm_loop" >/dev/null || fail "$2: examples/arm_loop does not build against the installed tree"
  "$out/arm_loop/arm_loop" "$prefix/share/stsim/arm/two_pandas.yaml" > "$out/arm_loop.txt" \
    || fail "$2: arm_loop failed: $(tail -1 "$out/arm_loop.txt")"
  grep -q '^1.071 s: STOP left' "$out/arm_loop.txt" && grep -q '^1.071 s: STOP right' "$out/arm_loop.txt" \
    || fail "$2: arm_loop did not STOP both arms at 1.071 s: $(head -3 "$out/arm_loop.txt")"

  # the Python module, if this build has it
  local pydir pyver
  pydir=$(find "$prefix" -type d -path '*-packages/stsim' -print -quit)
  if [ -n "$pydir" ]; then
    pyver=$(cd "$out" && PYTHONPATH=$(dirname "$pydir") $python -c "import stsim; print(stsim.__version__)") \
      || fail "$2: import stsim from $(dirname "$pydir") failed"
    [ "$pyver" = "$version" ] || fail "$2: stsim.__version__ is '$pyver', expected '$version'"
  fi
  echo "check_install: $2 ok ($line)"
}

# 1. cmake --install into a scratch prefix
cmake --install "$build" --prefix "$work/prefix" >/dev/null
check_prefix "$work/prefix" install

# 2. the .deb: built, its metadata, then its contents unpacked (the paths are relative to the
#    package, so the unpacked /usr works from anywhere)
(cd "$build" && rm -f stsim_*.deb && cpack -G DEB > "$work/cpack.log" 2>&1) || fail "cpack -G DEB: $(tail -3 "$work/cpack.log")"
deb=$(ls "$build"/stsim_"$version"_*.deb)
depends=$(dpkg-deb -f "$deb" Depends)
for dep in "sumo (>= 1.15)" libeigen3-dev libyaml-cpp-dev libboost1.74-dev libyaml-cpp0.7 libstdc++6 libc6; do
  [[ ", $depends," == *", $dep"[\ ,]* ]] || fail "$(basename "$deb"): Depends lacks $dep: $depends"
done
contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/stsim ./usr/lib/cmake/stsim/stsimConfig.cmake ./usr/include/sthighway/monitor.hpp \
         ./usr/include/stsim/version.hpp ./usr/share/stsim/networks/motorway/motorway.sumocfg \
         ./usr/share/stsim/plots.py ./usr/share/stsim/conflict_map.py ./usr/share/stsim/arm/two_pandas.yaml \
         ./usr/lib/cmake/stsim/stsimCosimTargets.cmake ./usr/include/starm/service.hpp; do
  grep -q " $f\$" <<< "$contents" || fail "$(basename "$deb") lacks $f"
done
grep -q 'pkgconfig/stsim.pc$' <<< "$contents" || fail "$(basename "$deb") lacks stsim.pc"
if [ -d "$build/python/stsim" ]; then
  grep -q 'dist-packages/stsim/_stsim\..*\.so$' <<< "$contents" || fail "$(basename "$deb") lacks the Python module"
  [[ "$depends" == *python3-numpy* ]] || fail "$(basename "$deb"): Depends lacks python3-numpy"
fi
dpkg-deb -x "$deb" "$work/deb"
check_prefix "$work/deb/usr" deb
echo "check_install: ok, stsim $version, $(basename "$deb") ($(du -k "$deb" | cut -f1) kB)"
