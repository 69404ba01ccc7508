#!/bin/bash
# Research log entry 173: entry 146's fleet88 rescoring of fold $1 at 120 s (today's recipe on the CPU's response
# models; the designed plan read from the design of 150 s, `designed_scale: 1.25`; alone and with 600 s of ordinary
# use; on data/fleet88g) with the pooled start network drawn again (entry 83's draw 1: the run's seed plus 1000, 40
# epochs), into entry173/fleet88_d1/fleet88_seed$1. Draw 0 is entry 146's run (entry146/at120).
#   bash reports/cross_sensor_response_gpu/entry173/rescore_fleet88.sh K
DRAW=1 OUT=entry173/fleet88_d1 bash reports/cross_sensor_response_gpu/entry146/rescore_fleet88.sh 120 "$1"
