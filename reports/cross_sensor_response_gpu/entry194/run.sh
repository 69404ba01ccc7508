#!/bin/bash
# Research log entry 194: entry 191's 64 fresh validation units, the designed plan of 120 s with their session
# logs weighed as 1,200 s (D, through entry 190's as_asked.py), beside entry 191's S (as 600 s); units, folds and
# networks as entry 191's calibrate.sh says. Networks in build/entry194/D-FOLD/UNIT. Two at a time; about 12
# minutes.
#   bash reports/cross_sensor_response_gpu/entry194/run.sh > reports/cross_sensor_response_gpu/entry194/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
one() { weighed "$@" entry194 120 1200; }  # CORE ARM FOLD UNIT
halves D
