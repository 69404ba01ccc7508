#!/bin/bash
# Research log entry 196: entry 191's 64 fresh validation units calibrated as its arm H was (the designed plan of
# 120 s with the unit's session logs, `anytip calibrate`'s defaults), with the current tree, whose unit network
# steps in numpy (N). Units, folds and networks as entry 191's calibrate.sh says. Networks in
# build/entry196/N-FOLD/UNIT. Two at a time; about 12 minutes.
#   bash reports/cross_sensor_response_gpu/entry196/run.sh > reports/cross_sensor_response_gpu/entry196/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
one() { calibrate_arm "$1" "build/entry196/$2-$3/$4" "$3" "$4" anytip -- --budget-seconds 120; }  # CORE ARM FOLD UNIT
halves N
