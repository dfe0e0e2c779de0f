#!/usr/bin/env bash
# Rebuilds actuated.net.xml from the plain XML sources (netconvert 1.15.0): the intersection of
# networks/intersection with netconvert's actuated program for the signal at C (induction loops
# on the approaches, green extended while they see traffic, 5-50 s per green phase).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files actuated.nod.xml --edge-files actuated.edg.xml --no-turnarounds true \
  --offset.disable-normalization true --output.street-names false --tls.default-type actuated \
  --output-file actuated.net.xml
