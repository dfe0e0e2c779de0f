#!/usr/bin/env bash
# Builds the libFuzzer targets with clang into build-fuzz/ and runs each from its seed corpus in
# fuzz/corpus/<target> (new inputs go to build-fuzz/corpus/<target>; findings to build-fuzz/).
#   fuzz/run.sh              short run: FUZZ_RUNS inputs (default 12000) per target (a quarter
#                            for the three costly ones), seed 1, so the same code gives the same
#                            run (what CI runs)
#   fuzz/run.sh --long [S]   S seconds per target (default 3600), random seed, for a real search
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
runs=${FUZZ_RUNS:-12000}
long=""
if [ "${1:-}" = "--long" ]; then long=${2:-3600}; fi
# the targets that set up a service, a connection or a folder of files per input cost 1-2 ms an
# input against 0.1-1 ms for the readers: a quarter of the inputs keeps the CI round about a minute
heavy=" cosim_scenario arm_service stnet_server pool_session "
build=$here/build-fuzz
targets=(pool_yaml pool_session arm_yaml batch_yaml fcd net arm_csv cosim_scenario traci_relay arm_protocol arm_service stnet_server)
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DCMAKE_CXX_COMPILER=clang++ \
  -DSTSIM_FUZZ=ON -DSTSIM_WITH_SUMO=ON -DSTSIM_BUILD_TESTS=OFF -DSTSIM_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j2 --target "${targets[@]/#/fuzz_}"
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$build/findings/$t"
  began=$(date +%s)
  n=$runs
  [[ "$heavy" == *" $t "* ]] && n=$(( runs / 4 ))
  limit=(-runs="$n" -seed=1)
  what="$n inputs"
  if [ -n "$long" ]; then limit=(-max_total_time="$long"); what="$long s"; fi
  (cd "$build/findings/$t" && UBSAN_OPTIONS=halt_on_error=1 ASAN_OPTIONS=detect_leaks=0 \
    "$build/fuzz/fuzz_$t" "${limit[@]}" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=0 "$build/corpus/$t" "$here/fuzz/corpus/$t" 2>"$build/findings/$t/log.txt") ||
    { tail -40 "$build/findings/$t/log.txt"; echo "fuzz: $t found a problem (input in $build/findings/$t)"; exit 1; }
  echo "fuzz: $t, $what, $(( $(date +%s) - began )) s"
done
echo "fuzz: ${#targets[@]} targets, no findings"
