#!/bin/bash
# Research log entry 207: the time of the path a lab takes with a new unit (`anytip calibrate --plan-strategy
# designed --budget-seconds 120 --ordinary-use 600 --use-log`, entry 191's calibration) on one core with the other
# idle: units f0 SIM41-000..002 (fleet88's fold 0) and o0 SIM24-000..002 (other16's fold 0), $1 rounds (default
# 3), this tree. Prints 'FOLD UNIT round R wall_s S core_gflops G model H' per calibration.
#   bash reports/cross_sensor_response_gpu/entry207/time_shipped.sh 3 > reports/cross_sensor_response_gpu/entry207/logs/time_shipped.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
for r in $(seq "${1:-3}"); do
  for pair in "f0 SIM41-000" "f0 SIM41-001" "f0 SIM41-002" "o0 SIM24-000" "o0 SIM24-001" "o0 SIM24-002"; do
    set -- $pair
    out=build/entry207/$1/$2_$r
    calibrate_arm 1 "$out" "$1" "$2" anytip -- --budget-seconds 120 > /dev/null
    python -c "import json; c=json.load(open('$out/calibration.json')); print('$1 $2 round $r', 'wall_s %.2f' % c['wall_s'], 'core_gflops %.1f' % c['core_gflops'], end=' ')"
    echo "model $(sha256sum "$out/model.safetensors" | cut -c1-16)"
  done
done
