#!/bin/sh
# Rebuilds the shipped trace from its plain XML sources (SUMO 1.15, deterministic for the seed).
set -e
cd "$(dirname "$0")"
netconvert --node-files lanedrop.nod.xml --edge-files lanedrop.edg.xml --output-file lanedrop.net.xml \
  --no-turnarounds true
sumo --net-file lanedrop.net.xml --route-files lanedrop.rou.xml --begin 0 --end 90 --step-length 0.5 \
  --seed 7 --lateral-resolution 0.64 --fcd-output lanedrop.fcd.xml --fcd-output.signals true \
  --fcd-output.acceleration true --collision.action warn --no-step-log true
# the trace from the shipped motorway (networks/motorway): 15 s around its first rear-end collision
sumo -c ../../../networks/motorway/motorway.sumocfg --seed 42 --end 225 --fcd-output motorway_merge.fcd.xml \
  --fcd-output.signals true --fcd-output.acceleration true --device.fcd.begin 210 --device.fcd.period 0.5 \
  --no-step-log true --no-warnings true --duration-log.statistics false
