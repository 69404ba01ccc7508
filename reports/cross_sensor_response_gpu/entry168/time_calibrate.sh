#!/bin/bash
# Research log entry 168 (b): entry 134's timing of `anytip calibrate` at 120 s (`cover_informative`, fleet88 fold
# 0's CPU response model of entry 106's run, data/fleet88, one core: taskset -c 1 with the other core idle), the
# plan alone and with 600 s of ordinary use, on entry 116's three units, $1 rounds (default 3). Each calibration
# runs with today's code and with entry 134's commit (c401b544, a worktree under build/) in turn, the order
# alternating by round (entry 116's `time_one` and `alternated`). Prints 'ARM CODE UNIT round R wall_s S command_s C'
# per calibration (wall_s: fit and fold; today's code adds its core_gflops since entry 171).
#   bash reports/cross_sensor_response_gpu/entry168/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry168/logs/time_calibrate.log
set -euo pipefail
rounds=${1:-3}
G=reports/cross_sensor_response_gpu old=$(pwd)/build/entry168_c401b544
run=$G/entry106/fleet88_cpu_use/fleet88_seed0
[ -d "$old" ] || git worktree add -q "$old" c401b544
. $G/entry116/time_one.sh
one() {  # CODE ARM UNIT ROUND: entry 116's time_one, its line with CODE after ARM
  local code=$1 arm=$2 unit=$3 r=$4 use=() line
  [ "$arm" = use ] && use=(--ordinary-use 600)
  line=$(CODE=$([ "$code" = entry134 ] && echo "$old") TIMING_DIR=time_calibrate168_$code \
         time_one "$arm" "$unit" "$r" "$run" "${use[@]}")
  echo "$arm $code ${line#"$arm "}"
}
alternated "$rounds" today entry134
