#!/bin/bash
# Research log entry 196: entry 172's timing of `anytip calibrate` (fleet88 fold 0's CPU response model,
# `cover_informative` at 120 s, the plan alone and with 600 s of ordinary use, units SIM40-000 to -002, one core
# with the other idle), $1 rounds (default 3), each calibration run with the code before the unit network's numpy
# step (eeee16de, a worktree under build/: "old") and with the current tree ("new") in turn, the order alternating
# by round. Prints 'CODE ARM UNIT round R wall_s S command_s C core_gflops G model H' per calibration.
#   bash reports/cross_sensor_response_gpu/entry196/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry196/logs/time_calibrate.log
# (b2, the same again: > .../logs/time_calibrate_b2.log)
set -euo pipefail
rounds=${1:-3}
G=reports/cross_sensor_response_gpu old=build/entry196_eeee16de
[ -d "$old" ] || git worktree add -q "$old" eeee16de
. $G/entry116/time_one.sh
one() {  # CODE ARM UNIT ROUND
  local code=$1 arm=$2 unit=$3 r=$4 run=$G/entry101/fleet88_cpu/fleet88_seed0 use=()
  [ "$arm" = use ] && run=$G/entry106/fleet88_cpu_use/fleet88_seed0 use=(--ordinary-use 600)
  local line
  line=$(CODE=$([ "$code" = old ] && echo "$(pwd)/$old") TIMING_DIR=time_calibrate196_$code \
         time_one "$arm" "$unit" "$r" "$run" "${use[@]}")
  echo "$code $line model $(sha256sum build/time_calibrate196_$code/${arm}_${unit}_$r/model.safetensors | cut -c1-16)"
}
alternated "$rounds" old new
