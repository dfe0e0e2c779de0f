#!/usr/bin/env bash
# The fault matrix: every command run with its output on a full file system, into a
# read-only folder, and stopped by SIGINT / SIGTERM / SIGHUP while it writes. Each must exit non-zero; on
# a full or read-only disk its last line on stderr names the file or folder; what it wrote is
# whole: CSV files end on a complete row, JSON files parse.
#   usage: fault_matrix.sh STSIM SOURCE_DIR
# A full file system is a file-size limit (ulimit -f: write() fails with EFBIG past it, as with
# ENOSPC on a full disk; no root needed). A read-only folder is a read-only tmpfs when root may
# mount one, else a folder without write permission (which root would ignore). Bounded: every
# command under `timeout`, every wait polled with a deadline.
set -uo pipefail
# 128 + the signal: every command stops the same way (app/src/stop_signals.hpp)
exit_code() { case $1 in INT) echo 130 ;; TERM) echo 143 ;; HUP) echo 129 ;; esac; }
stsim=$1
src=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/stsim_faults.XXXXXX")
ro=$work/ro
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  mountpoint -q "$ro" 2>/dev/null && umount "$ro"
  chmod -R u+w "$work" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
. "$(dirname "$0")/fault_lib.sh"

# expect_named WHAT CODE ERRFILE PATH: exit non-zero, the last line of stderr names PATH
expect_named() {
  local what=$1 code=$2 err=$3 path=$4
  cases=$((cases + 1))
  [ "$code" -ne 0 ] || bad "$what: exit 0"
  [ "$code" -ne 124 ] || bad "$what: timed out"
  tail -n 1 "$err" | grep -qF "$path" || bad "$what: the last line does not name $path: $(tail -n 1 "$err")"
}

# the read-only folder
mkdir -p "$ro"
if ! mount -t tmpfs -o ro,size=64k tmpfs "$ro" 2>/dev/null; then
  chmod 555 "$ro"
  if [ "$(id -u)" = 0 ]; then echo "SKIP read-only cases: root cannot mount a read-only tmpfs here"; ro=; fi
fi

# inputs: a long arm course (3000 s of cycles), a recorded sensor trace, a pool experiment
sed 's/^duration: 3.0/duration: 3000/' "$src/models/arm/scenarios/two_pandas.yaml" >"$work/arm_long.yaml"
"$stsim" arm "$src/models/arm/scenarios/two_pandas.yaml" --out "$work/rec" --record-trace "$work/sensors.csv" >/dev/null ||
  bad "recording the sensor trace"
pool_experiment "$work/batch.yaml" faults
fcd="--fcd $src/tests/data/highway/motorway_merge.fcd.xml --net $src/networks/motorway/motorway.net.xml"

# name -> command line with OUT for its output folder; LONG: the same, running long enough to be
# stopped mid-way
declare -A cmd long
cmd[pool]="pool $src/models/pool/scenarios/break.yaml --out OUT"
long[pool]="pool $src/models/pool/scenarios/box100.yaml --until 1e12 --max-events 2000000 --out OUT"
cmd[arm]="arm $src/models/arm/scenarios/two_pandas.yaml --out OUT"
long[arm]="arm $work/arm_long.yaml --out OUT"
cmd[highway_replay]="highway $fcd --out OUT"
long[highway_replay]=
cmd[highway_live]="highway $src/networks/motorway/scenario.yaml --end 60 --no-map --out OUT"
long[highway_live]="highway $src/networks/motorway/scenario.yaml --end 36000 --no-map --out OUT"
cmd[batch]="batch $work/batch.yaml --jobs 1 --no-plots --out OUT"
long[batch]=
have_sumo=1
command -v sumo >/dev/null || have_sumo=0

for name in pool arm highway_replay highway_live batch; do
  if [ "$name" = highway_live ] && [ $have_sumo = 0 ]; then echo "SKIP highway_live: no SUMO"; continue; fi
  # full: 2 KiB per file (bash counts ulimit -f in KiB)
  out=$work/full_$name
  mkdir -p "$out"
  (ulimit -f 2; trap '' XFSZ; exec timeout 120 "$stsim" ${cmd[$name]//OUT/$out}) >/dev/null 2>"$work/err"
  code=$?
  if [ "$name" = batch ]; then
    # the runs fail on their writes; the batch says so and exits 1
    cases=$((cases + 1))
    [ "$code" -ne 0 ] || bad "batch full: exit 0"
    grep -qE "write failed|failed writing" "$work/err" "$out/runs.csv" 2>/dev/null || bad "batch full: no write failure named"
  else
    expect_named "$name full" "$code" "$work/err" "$out/"
  fi
  # every file whole, the batch's run folders (stsim pool runs) too
  whole "$out" "$name full"
  # read-only
  if [ -n "$ro" ]; then
    timeout 120 "$stsim" ${cmd[$name]//OUT/$ro/out} >/dev/null 2>"$work/err"
    expect_named "$name read-only" $? "$work/err" "$ro/out"
  fi
  # SIGINT, SIGTERM and SIGHUP once it has begun to write
  [ -n "${long[$name]}" ] || continue
  for sig in INT TERM HUP; do
    out=$work/${sig}_$name
    timeout 300 "$stsim" ${long[$name]//OUT/$out} >/dev/null 2>"$work/err" &
    pid=$!
    pids+=("$pid")
    # the others write as they go: a file begun, or 2 s. pool writes at the end and its long run
    # ends at its event cap within about 2.5 s on a fast tree: signalled mid-run, after 0.5 s
    if [ "$name" != pool ]; then
      for _ in $(seq 1 20); do
        [ -n "$(find "$out" -type f -size +0 2>/dev/null | head -n 1)" ] && break
        sleep 0.1
      done
    fi
    sleep 0.5
    # timeout passes the signal on to stsim
    kill -s "$sig" "$pid"
    wait "$pid"
    code=$?
    want=$(exit_code $sig)
    cases=$((cases + 1))
    [ "$code" = "$want" ] || bad "$name SIG$sig: exit $code, expected $want ($(tail -n 1 "$work/err"))"
    whole "$out" "$name SIG$sig"
  done
done

# the arm service and its client: a service to stream to, the client on a full disk; then the
# service on a full disk, and stopped by a signal while it logs
stream() {  # stream OUT [ulimit KiB] [rate]
  local out=$1 lim=${2:-unlimited} rate=${3:-0}
  (ulimit -f "$lim"; trap '' XFSZ; exec timeout 120 "$stsim" arm stream --connect "127.0.0.1:$port" "$work/sensors.csv" \
    --rate "$rate" --out "$out") >/dev/null 2>"$work/err"
}

serve "$work/serve_ok"
stream "$work/full_stream" 2
expect_named "arm stream full" $? "$work/err" "$work/full_stream/"
whole "$work/full_stream" "arm stream full"
if [ -n "$ro" ]; then
  stream "$ro/out"
  expect_named "arm stream read-only" $? "$work/err" "$ro/out"
fi
for sig in INT TERM HUP; do
  # real time: 3 s of trace, stopped after 1
  (exec timeout 60 "$stsim" arm stream --connect "127.0.0.1:$port" "$work/sensors.csv" --rate 1 \
    --out "$work/${sig}_stream") >/dev/null 2>"$work/err" &
  pid=$!
  sleep 1
  kill -s "$sig" "$pid"
  wait "$pid"
  code=$?
  want=$(exit_code $sig)
  cases=$((cases + 1))
  [ "$code" = "$want" ] || bad "arm stream SIG$sig: exit $code, expected $want"
  whole "$work/${sig}_stream" "arm stream SIG$sig"
done
kill -TERM "$serve_pid"
wait "$serve_pid"

serve "$work/full_serve" 8
stream "$work/serve_client"
wait "$serve_pid"
expect_named "arm serve full" $? "$work/serve.err" "$work/full_serve/verdicts.csv"
whole "$work/full_serve" "arm serve full"
if [ -n "$ro" ]; then
  timeout 20 "$stsim" arm serve "$src/models/arm/scenarios/two_pandas.yaml" --out "$ro/out" >/dev/null 2>"$work/err"
  expect_named "arm serve read-only" $? "$work/err" "$ro/out"
fi
for sig in INT TERM HUP; do
  serve "$work/${sig}_serve"
  stream "$work/${sig}_client" unlimited 1 &
  client=$!
  sleep 1
  kill -s "$sig" "$serve_pid"
  wait "$serve_pid"
  code=$?
  wait "$client"
  want=$(exit_code $sig)
  cases=$((cases + 1))
  [ "$code" = "$want" ] || bad "arm serve SIG$sig: exit $code, expected $want"
  whole "$work/${sig}_serve" "arm serve SIG$sig"
done

finish "fault matrix"
