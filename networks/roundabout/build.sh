#!/usr/bin/env bash
# Rebuilds roundabout.net.xml from the plain XML sources (netconvert 1.15.0): a single-lane
# roundabout, no signals, the ring with right of way (netconvert's roundabout element).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files roundabout.nod.xml --edge-files roundabout.edg.xml --no-turnarounds true \
  --offset.disable-normalization true --output.street-names false \
  --output-file roundabout.net.xml
