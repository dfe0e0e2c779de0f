#!/usr/bin/env bash
# Rebuilds lanedrop.net.xml from the plain XML sources; the committed .net.xml was built with exactly this
# command (netconvert 1.15.0).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files lanedrop.nod.xml --edge-files lanedrop.edg.xml --connection-files lanedrop.con.xml \
  --no-turnarounds true --geometry.remove false --offset.disable-normalization true \
  --output.street-names false --no-internal-links false \
  --output-file lanedrop.net.xml --no-warnings false
