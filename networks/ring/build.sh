#!/usr/bin/env bash
# Rebuilds ring.net.xml and ring.rou.xml: make_sources.py writes the plain XML sources (circle
# geometry), make_routes.py the 60 vehicles, netconvert
# builds the network; the committed ring.net.xml was built with exactly these commands (1.15.0).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
python3 make_sources.py
python3 make_routes.py 60
netconvert --node-files ring.nod.xml --edge-files ring.edg.xml --no-turnarounds true \
  --offset.disable-normalization true --junctions.corner-detail 0 --output-file ring.net.xml
