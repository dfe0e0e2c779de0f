#!/usr/bin/env bash
# Rebuilds intersection.net.xml from the plain XML sources (netconvert 1.15.0, its fixed-time
# program for the signal at C).
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files intersection.nod.xml --edge-files intersection.edg.xml --no-turnarounds true \
  --offset.disable-normalization true --output.street-names false --tls.default-type static \
  --output-file intersection.net.xml
