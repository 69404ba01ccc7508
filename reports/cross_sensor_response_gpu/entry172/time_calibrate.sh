#!/bin/bash
# Research log entry 172 (and part B of entry 171): entry 116's timing of `anytip calibrate` (fleet88 fold 0's CPU
# response model, `cover_informative` at 120 s, the plan alone and with 600 s of ordinary use, units SIM40-000 to
# -002, one core with the other idle), $1 rounds (default 3), each calibration run with entry 171's commit
# (ff2f2ac6, a worktree under build/: "old") and with the current tree ("new") in turn, the order alternating by
# round. Prints 'CODE ARM UNIT round R wall_s S command_s C core_gflops G model H' per calibration (H: the first
# 16 hex digits of its model.safetensors' SHA-256).
#   bash reports/cross_sensor_response_gpu/entry172/time_calibrate.sh 3 > reports/cross_sensor_response_gpu/entry172/logs/time_calibrate.log
# ENTRY and OLD name another entry and its old commit (entry 196's script sets them).
set -euo pipefail
rounds=${1:-3} entry=${ENTRY:-172} commit=${OLD:-ff2f2ac6}
G=reports/cross_sensor_response_gpu old=build/entry${entry}_$commit
[ -d "$old" ] || git worktree add -q "$old" "$commit"
. $G/entry116/time_one.sh
one() {  # CODE ARM UNIT ROUND
  local code=$1 arm=$2 unit=$3 r=$4 run=$G/entry101/fleet88_cpu/fleet88_seed0 use=()
  [ "$arm" = use ] && run=$G/entry106/fleet88_cpu_use/fleet88_seed0 use=(--ordinary-use 600)
  local line
  line=$(CODE=$([ "$code" = old ] && echo "$(pwd)/$old") TIMING_DIR=time_calibrate${entry}_$code \
         time_one "$arm" "$unit" "$r" "$run" "${use[@]}")
  echo "$code $line model $(sha256sum build/time_calibrate${entry}_$code/${arm}_${unit}_$r/model.safetensors | cut -c1-16)"
}
alternated "$rounds" old new
