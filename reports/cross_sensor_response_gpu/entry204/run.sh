#!/bin/bash
# Research log entry 204: entry 191's 64 fresh validation units calibrated as entry 196's arm N was (the designed
# plan of 120 s with the unit's session logs, `anytip calibrate`'s defaults), with the current tree, whose unit
# network steps compiled (C). Networks in build/entry204/C-FOLD/UNIT. Two at a time; about 12 minutes.
#   bash reports/cross_sensor_response_gpu/entry204/run.sh > reports/cross_sensor_response_gpu/entry204/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
one() { calibrate_arm "$1" "build/entry204/$2-$3/$4" "$3" "$4" anytip -- --budget-seconds 120; }  # CORE ARM FOLD UNIT
halves C
