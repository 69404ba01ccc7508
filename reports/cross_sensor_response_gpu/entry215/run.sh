#!/bin/bash
# Research log entry 215: entry 191's 64 fresh validation units calibrated on their designed plan of 120 s alone
# (no ordinary use), H on the Halton plan (data/val191d, data/val191o) and R on the plan of random points
# (data/val215d, data/val215o; make_data.py first), today's `anytip calibrate` for both. Units, folds and
# networks as entry 191's calibrate.sh says. Networks in build/entry215/ARM-FOLD/UNIT. Two at a time. Entry 216's
# arm C (`run.sh C`): the plan's cells drawn at random, its loads in turn (data/val216d, data/val216o).
#   bash reports/cross_sensor_response_gpu/entry215/run.sh > reports/cross_sensor_response_gpu/entry215/logs/run.log
#   bash reports/cross_sensor_response_gpu/entry215/run.sh C > reports/cross_sensor_response_gpu/entry215/logs/run216.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
export ALONE=1
one() {  # CORE ARM FOLD UNIT
  local REG_D=data/val191d REG_O=data/val191o
  [ "$2" = R ] && REG_D=data/val215d REG_O=data/val215o
  [ "$2" = C ] && REG_D=data/val216d REG_O=data/val216o
  calibrate_arm "$1" "build/entry215/$2-$3/$4" "$3" "$4" anytip -- --budget-seconds 120
}
halves "${1:-H R}"
