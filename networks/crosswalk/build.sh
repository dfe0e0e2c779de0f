#!/usr/bin/env bash
# Rebuilds crosswalk.net.xml from the plain XML sources (netconvert 1.15.0): the intersection of
# networks/intersection with sidewalks on every arm and a signalised crosswalk across each; corners
# of 9 m radius (netconvert's default 4 m puts the crosswalks where turning cars cut the corners'
# walking areas, which SUMO does not check for vehicle-person contact).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files crosswalk.nod.xml --edge-files crosswalk.edg.xml --no-turnarounds true \
  --offset.disable-normalization true --output.street-names false --tls.default-type static \
  --sidewalks.guess true --crossings.guess true --default.junctions.radius 9 --output-file crosswalk.net.xml
