#!/bin/bash
# Research log entry 174: entry 154's fleet88 rescoring of fold $1 (the designed plan at 30 and 60 s, alone and
# with 600 s of ordinary use, on data/fleet88d) with the pooled start network drawn again (entry 83's draw 1),
# into entry174/fleet88_d1/fleet88_seed$1. Draw 0 is entry 154's run.
#   bash reports/cross_sensor_response_gpu/entry174/rescore_fleet88.sh K
DRAW=1 OUT=entry174/fleet88_d1 bash reports/cross_sensor_response_gpu/entry154/rescore_fleet88.sh "$1"
