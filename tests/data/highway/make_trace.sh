#!/bin/sh
# Rebuilds the shipped trace from its plain XML sources (SUMO 1.15, deterministic for the seed).
set -e
cd "$(dirname "$0")"
netconvert --node-files lanedrop.nod.xml --edge-files lanedrop.edg.xml --output-file lanedrop.net.xml \
  --no-turnarounds true
sumo --net-file lanedrop.net.xml --route-files lanedrop.rou.xml --begin 0 --end 90 --step-length 0.5 \
  --seed 7 --lateral-resolution 0.64 --fcd-output lanedrop.fcd.xml --fcd-output.signals true \
  --fcd-output.acceleration true --collision.action warn --no-step-log true
