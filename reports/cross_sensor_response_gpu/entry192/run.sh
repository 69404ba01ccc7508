#!/bin/bash
# Research log entry 192: entry 191's 64 fresh validation units, the designed plan of 30 s with their session
# logs weighed as 600 s (F, the benchmark's weight) and as 150 s (Q: to a 30 s plan what 600 s is to 120 s),
# both through entry 190's as_asked.py; units, folds and networks as entry 191's calibrate.sh says (make_data.py
# first). Networks in build/entry192/ARM-FOLD/UNIT. Two at a time; about 20 minutes.
#   bash reports/cross_sensor_response_gpu/entry192/run.sh > reports/cross_sensor_response_gpu/entry192/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
declare -A WEIGHT=([F]=600 [Q]=150)
one() { weighed "$@" entry192 30 "${WEIGHT[$2]}"; }  # CORE ARM FOLD UNIT
halves "F Q"
