# The fault tests' shared parts (sourced by fault_matrix.sh and full_disk_files.sh): the failure
# count, the check that what a command wrote is whole, a pool experiment, and an arm service to
# stream to. The sourcing script sets stsim, src and work first.
fails=0
cases=0
pids=()  # processes started in the background, for the script's cleanup

bad() {
  echo "FAIL $*"
  fails=$((fails + 1))
}

# whole DIR WHAT [DEPTH]: every CSV below DIR ends on a whole row (its last byte a newline), every
# JSON parses
whole() {
  local dir=$1 what=$2 depth=${3:-99} f
  [ -d "$dir" ] || return 0
  while IFS= read -r -d '' f; do
    [ -s "$f" ] || continue
    case $f in
      *.csv) [ "$(tail -c 1 "$f" | od -An -c | tr -d ' ')" = '\n' ] || bad "$what: $f ends in a cut row" ;;
      *.json) python3 -m json.tool "$f" >/dev/null 2>&1 || bad "$what: $f is not valid JSON" ;;
    esac
  done < <(find "$dir" -maxdepth "$depth" -type f \( -name '*.csv' -o -name '*.json' \) -print0)
}

# pool_experiment FILE NAME: a two-run pool experiment (the break, two seeds)
pool_experiment() {
  cat >"$1" <<EOT
name: $2
command: pool
base: $src/models/pool/scenarios/break.yaml
sweep:
  until: [5.0]
seeds: 2
EOT
}

# serve OUT [ulimit KiB]: starts `arm serve` in the background, sets $serve_pid and $port (empty,
# and a failure counted, if it did not start listening within 10 s)
serve() {
  local out=$1 lim=${2:-unlimited}
  (ulimit -f "$lim"; trap '' XFSZ; exec timeout 300 "$stsim" arm serve "$src/models/arm/scenarios/two_pandas.yaml" \
    --listen 127.0.0.1:0 --out "$out") >"$work/serve.out" 2>"$work/serve.err" &
  serve_pid=$!
  pids+=("$serve_pid")
  port=
  for _ in $(seq 1 100); do
    port=$(sed -n 's/.*listening on 127.0.0.1:\([0-9]*\).*/\1/p' "$work/serve.out")
    [ -n "$port" ] && break
    sleep 0.1
  done
  [ -n "$port" ] || bad "arm serve did not start: $(cat "$work/serve.err")"
}

# finish WHAT: the verdict line, exit 1 on any failure
finish() {
  if [ "$fails" -gt 0 ]; then
    echo "$1: $fails of $cases cases failed"
    exit 1
  fi
  echo "$1: $cases cases, every one held"
}
