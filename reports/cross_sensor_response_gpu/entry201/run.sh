#!/bin/bash
# Research log entry 201: 64 fresh units (units.py) calibrated as a lab calibrates a new unit with a log since
# entries 198-199: `anytip calibrate --plan-strategy designed --budget-seconds 120 --ordinary-use 600 --use-log`
# with `--factor-from` every fold's run of its registry (the unit's own is skipped), into
# build/entry201/P-FOLD/UNIT. Two at a time; about 10 minutes.
#   bash reports/cross_sensor_response_gpu/entry201/run.sh > reports/cross_sensor_response_gpu/entry201/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
UNITS_PY=$G/entry201/units.py REG_D=data/test201d REG_O=data/test201o USE_LOGS=build/entry201_logs
source $G/entry191/calibrate.sh
one() {  # CORE ARM FOLD UNIT
  local runs
  if [ "${3:0:1}" = f ]; then runs=($G/entry147/at120/fleet88_seed{0,1})
  else runs=($G/entry146/at120/other16_severe_d0/other16_seed{0,1,2,3}); fi
  calibrate_arm "$1" "build/entry201/$2-$3/$4" "$3" "$4" anytip -- --budget-seconds 120 --factor-from "${runs[@]}"
}
halves P
