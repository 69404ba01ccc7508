#!/bin/bash
# Research log entry 197: entry 196's alternated timing (old: eeee16de; new: the current tree) on core 1 while
# core 0 runs entry 196's (a) calibrations with the current tree, one after another, for the whole timing (the
# neighbour (a) had); $1 rounds (default 2). Prints entry 196's lines; the neighbour's own log goes to
# build/entry197_neighbour.log.
#   bash reports/cross_sensor_response_gpu/entry197/time_calibrate.sh 2 > reports/cross_sensor_response_gpu/entry197/logs/time_calibrate.log
set -euo pipefail
source reports/cross_sensor_response_gpu/entry191/calibrate.sh
neighbour() {
  while true; do
    for i in "${!pairs[@]}"; do
      # shellcheck disable=SC2086
      calibrate_arm 0 build/entry197_neighbour/N ${pairs[$i]} anytip -- --budget-seconds 120
    done
  done
}
neighbour > build/entry197_neighbour.log 2>&1 &
load=$!
trap 'kill $load 2>/dev/null; pkill -f "entry197_neighbour" || true' EXIT
sleep 20  # the neighbour's first calibration under way
ENTRY=197 OLD=eeee16de bash reports/cross_sensor_response_gpu/entry172/time_calibrate.sh "${1:-2}"
