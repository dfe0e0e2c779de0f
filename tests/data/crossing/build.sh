#!/usr/bin/env bash
# Rebuilds crossing.net.xml from the plain XML sources. The committed .net.xml was built with exactly this
# command (netconvert 1.15.0).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files crossing.nod.xml --edge-files crossing.edg.xml --connection-files crossing.con.xml \
  --no-turnarounds true --output-file crossing.net.xml
