#!/bin/bash
# Research log entry 191: 64 fresh validation units' designed plan of 120 s with their session logs, weighed as
# held (H, today) and as the 600 s asked (S, entry 190's as_asked.py). Units, folds and networks as calibrate.sh
# says; logs in build/entry191_logs (make_data.py first). Networks in build/entry191/ARM-FOLD/UNIT. Two at a
# time; about 20 minutes.
#   bash reports/cross_sensor_response_gpu/entry191/run.sh > reports/cross_sensor_response_gpu/entry191/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
one() {  # CORE ARM FOLD UNIT
  local run=(anytip)
  [ "$2" = S ] && run=(python $G/entry190/as_asked.py 600)
  calibrate_arm "$1" "build/entry191/$2-$3/$4" "$3" "$4" "${run[@]}" -- --budget-seconds 120
}
halves "H S"
