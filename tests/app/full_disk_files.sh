#!/usr/bin/env bash
# Every file every command writes, each in turn on a full disk (docs/bad_input.md): a reference
# run lists the files a command writes; then, for each, the command runs again with that one file
# on /dev/full (io's test seam STSIM_TEST_FULL_FILE=NAME: every output named NAME is opened as
# /dev/full, so a file in a folder the command empties or creates first fails too). Each must exit
# non-zero, its last line on stderr (a batch: its run's line on stdout) naming the file, and what
# it wrote before stays whole: CSV files end on a complete row, JSON files parse.
#   usage: full_disk_files.sh STSIM SOURCE_DIR
# Files other programs write are left out, each with the test that covers it: SUMO's (ssm.xml,
# sumo.log), matplotlib's (conflict_map.png/.svg and its log: tests/app/hostile_input_test.cpp
# AMapThatCannotBeWrittenFailsTheRun), and a batch run's log.txt (the run's own stdout); and the
# batch's .batch.lock, a lock held on its descriptor (its pid written with a checked pwrite,
# batch/src/runner.cpp). Empty files are left out too: writing nothing to /dev/full cannot fail.
set -uo pipefail
stsim=$1
src=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/stsim_full_files.XXXXXX")
trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; rm -rf "$work"' EXIT
. "$(dirname "$0")/fault_lib.sh"
others='^(ssm\.xml|sumo\.log|sumo_collisions\.xml|conflict_map\..*|log\.txt|\.batch\.lock)$'

# each NAME LINE [FILES]: LINE is the command line with OUT for its output folder; FILES, when
# given, the files it writes (for a run too long to make twice: no reference run)
each() {
  local name=$1 line=$2 ref=$work/ref_$1 f out code files=${3:-}
  # the folder exists: a file named inside it (arm's --record-trace) opens before the command makes it
  mkdir -p "$ref"
  if [ -z "$files" ]; then
    if ! timeout 600 "$stsim" ${line//OUT/$ref} >"$work/out" 2>"$work/err"; then
      bad "$name: the reference run failed: $(tail -n 1 "$work/err")"
      return
    fi
    files=$(find "$ref" -type f -size +0 -printf '%f\n' | sort -u)
  fi
  [ -n "$files" ] || bad "$name: the reference run wrote nothing"
  for f in $files; do
    [[ $f =~ $others ]] && continue
    out=$work/full_${name}_$f
    mkdir -p "$out"
    STSIM_TEST_FULL_FILE=$f timeout 600 "$stsim" ${line//OUT/$out} >"$work/out" 2>"$work/err"
    code=$?
    cases=$((cases + 1))
    if [ "$code" -eq 0 ] || [ "$code" -eq 124 ]; then
      bad "$name with $f on a full disk: exit $code"
      continue
    fi
    if [[ $name == batch* ]]; then
      # a run's failure is its line in the batch's list (stdout); the batch's own files its stderr
      grep -qE "(write failed|cannot write).*/$f" "$work/out" "$work/err" ||
        bad "$name with $f on a full disk: no line names it: $(tail -n 1 "$work/err")"
    else
      tail -n 1 "$work/err" | grep -qE "(write failed|cannot write).*/$f" ||
        bad "$name with $f on a full disk: the last line does not name it: $(tail -n 1 "$work/err")"
    fi
    whole "$out" "$name with $f on a full disk"
    echo "$name, $f on a full disk: exit $code, $(tail -n 1 "$work/err")"
  done
}

pool_experiment "$work/batch.yaml" full_files

each pool "pool $src/models/pool/scenarios/break.yaml --out OUT"
each arm "arm $src/models/arm/scenarios/two_pandas.yaml --out OUT --record-trace OUT/sensors.csv"
each pool_study "pool --study fig13 --out OUT"
each arm_study "arm --study stopping --courses 4 --no-shipped --out OUT"
# a minute of study: opened as it starts, so its failing run is short
each arm_coexistence "arm --study coexistence $src/models/arm/scenarios/person_walkpast.yaml --out OUT" coexistence.csv
each highway_replay "highway --fcd $src/tests/data/highway/motorway_merge.fcd.xml --net $src/networks/motorway/motorway.net.xml --trajectories --out OUT"
if command -v sumo >/dev/null; then
  each highway "highway $src/networks/motorway/scenario.yaml --end 40 --validate-ssm --trajectories --out OUT"
else
  echo "SKIP highway: no SUMO"
fi
each batch "batch $work/batch.yaml --jobs 1 --no-plots --out OUT"
# a merge copies the runs' folders through the same writer
each batch_merge "batch merge $work/ref_batch --no-plots --out OUT"

# the arm service's logs, and its client's: a service to stream to (recorded sensors from the
# arm's reference run above)
serve "$work/ref_serve"
if [ -n "$port" ]; then
  each arm_stream "arm stream --connect 127.0.0.1:$port $work/ref_arm/sensors.csv --out OUT"
  kill -TERM "$serve_pid"
  wait "$serve_pid"
  # the service opens its logs as it starts: one on a full disk stops it there
  for f in $(find "$work/ref_serve" -type f -size +0 -printf '%f\n' | sort -u); do
    out=$work/full_serve_$f
    STSIM_TEST_FULL_FILE=$f timeout 20 "$stsim" arm serve "$src/models/arm/scenarios/two_pandas.yaml" \
      --listen 127.0.0.1:0 --out "$out" >/dev/null 2>"$work/err"
    code=$?
    cases=$((cases + 1))
    if [ "$code" -eq 0 ] || [ "$code" -eq 124 ]; then
      bad "arm serve with $f on a full disk: exit $code"
      continue
    fi
    tail -n 1 "$work/err" | grep -qE "(write failed|cannot write).*/$f" ||
      bad "arm serve with $f on a full disk: the last line does not name it: $(tail -n 1 "$work/err")"
    echo "arm serve, $f on a full disk: exit $code, $(tail -n 1 "$work/err")"
  done
fi

finish "full disk, file by file"
