#!/usr/bin/env bash
# Rebuilds motorway.net.xml from the plain XML sources. The committed .net.xml was built with exactly this
# command (netconvert 1.15.0); rerun after editing motorway.{nod,edg,con}.xml.
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files motorway.nod.xml --edge-files motorway.edg.xml --connection-files motorway.con.xml \
  --no-turnarounds true --geometry.remove false --offset.disable-normalization true \
  --output.street-names false --no-internal-links false \
  --output-file motorway.net.xml --no-warnings false
