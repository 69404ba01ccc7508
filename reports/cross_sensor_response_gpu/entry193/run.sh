#!/bin/bash
# Research log entry 193: entry 191's 64 fresh validation units, the designed plan of 30 s with their session
# logs weighed as 1,200 s (D) and as 2,400 s (X), through entry 190's as_asked.py, beside entry 192's F (as
# 600 s); units, folds and networks as entry 191's calibrate.sh says. Networks in build/entry193/ARM-FOLD/UNIT.
# Two at a time; about 20 minutes.
#   bash reports/cross_sensor_response_gpu/entry193/run.sh > reports/cross_sensor_response_gpu/entry193/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
declare -A WEIGHT=([D]=1200 [X]=2400)
one() { weighed "$@" entry193 30 "${WEIGHT[$2]}"; }  # CORE ARM FOLD UNIT
halves "D X"
