#!/usr/bin/env bash
# Rebuilds short.net.xml and long.net.xml from the plain XML sources. The committed nets were built with
# exactly this command (netconvert 1.15.0); rerun after editing {short,long}.nod.xml or onramp.{edg,con}.xml.
# The junctions' turn-speed limit is off: the ramp's nose is drawn as a bend (a real one is a long taper
# driven at speed), and netconvert would otherwise slow the ramp to 11 m/s there.
set -euo pipefail
cd "$(dirname "$0")"
export SUMO_HOME="${SUMO_HOME:-/usr/share/sumo}"
for design in short long; do
  netconvert --node-files "$design.nod.xml" --edge-files onramp.edg.xml --connection-files onramp.con.xml \
    --no-turnarounds true --geometry.remove false --offset.disable-normalization true \
    --output.street-names false --no-internal-links false --junctions.limit-turn-speed -1 \
    --output-file "$design.net.xml" --no-warnings false
done
