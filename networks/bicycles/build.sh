#!/usr/bin/env bash
# Rebuilds bicycles.net.xml from the plain XML sources (netconvert 1.15.0): a main road with bike
# lanes crossing a minor road the bicycles share with cars, at a priority junction (no signals).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files bicycles.nod.xml --edge-files bicycles.edg.xml --no-turnarounds true \
  --offset.disable-normalization true --output.street-names false \
  --output-file bicycles.net.xml
