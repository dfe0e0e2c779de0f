#!/usr/bin/env bash
# Rebuilds sublane.net.xml from the plain XML sources; the committed .net.xml was built with exactly
# this command (netconvert 1.15.0). The sublane resolution is a simulation option (sumocfg), not a
# network property.
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
netconvert --node-files sublane.nod.xml --edge-files sublane.edg.xml --connection-files sublane.con.xml \
  --no-turnarounds true --offset.disable-normalization true --output-file sublane.net.xml
