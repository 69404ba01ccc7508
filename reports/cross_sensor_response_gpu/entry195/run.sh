#!/bin/bash
# Research log entry 195: entry 191's 32 fresh units of the other elastomer, the designed plan of 60 s with their
# session logs weighed as 600 s (F) and as 2,400 s (X), through entry 190's as_asked.py; folds and networks as
# entry 191's calibrate.sh says (make_data.py first). Networks in build/entry195/ARM-FOLD/UNIT. Two at a time;
# about 10 minutes.
#   bash reports/cross_sensor_response_gpu/entry195/run.sh > reports/cross_sensor_response_gpu/entry195/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
mapfile -t pairs < <(printf '%s\n' "${pairs[@]}" | grep ' SIM24-')
declare -A WEIGHT=([F]=600 [X]=2400)
one() { weighed "$@" entry195 60 "${WEIGHT[$2]}"; }  # CORE ARM FOLD UNIT
halves "F X"
