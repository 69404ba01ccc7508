#!/bin/bash
# Research log entry 193: entry 191's 64 fresh validation units, the designed plan of 30 s with their session
# logs weighed as 1,200 s (D) and as 2,400 s (X), through entry 190's as_asked.py, beside entry 192's F (as
# 600 s); units, folds and networks as entry 191's calibrate.sh says. Networks in build/entry193/ARM-FOLD/UNIT.
# Two at a time; about 20 minutes.
#   bash reports/cross_sensor_response_gpu/entry193/run.sh > reports/cross_sensor_response_gpu/entry193/logs/run.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
one() {  # CORE ARM FOLD UNIT
  local weight=1200
  [ "$2" = X ] && weight=2400
  calibrate_arm "$1" "build/entry193/$2-$3/$4" "$3" "$4" python $G/entry190/as_asked.py $weight -- \
    --budget-seconds 30
}
halves "D X"
