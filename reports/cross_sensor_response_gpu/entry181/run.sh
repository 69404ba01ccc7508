#!/bin/bash
# Research log entry 181: other16's 16 units, each under the fold that holds it out (entry 146's at-120 runs,
# start draw 0), on data/other16, cover_informative at 120 s: the plan alone (A) and with its ordinary-use logs
# (L, build/entry181_logs/ from make_logs.py), into build/entry181/. Two units at a time; about 8 minutes.
#   bash reports/cross_sensor_response_gpu/entry181/run.sh > reports/cross_sensor_response_gpu/entry181/logs/run.log
set -euo pipefail
runs=reports/cross_sensor_response_gpu/entry146/at120/other16_severe_d0
folds=("SIM23-000 SIM23-002 SIM23-013 SIM23-014" "SIM23-004 SIM23-008 SIM23-011 SIM23-012"
       "SIM23-001 SIM23-003 SIM23-006 SIM23-007" "SIM23-005 SIM23-009 SIM23-010 SIM23-015")
one() {  # CORE ARM FOLD UNIT [OPTION...]
  local core=$1 arm=$2 fold=$3 unit=$4; shift 4
  local out=build/entry181/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" anytip calibrate --model $runs/other16_seed$fold --unit "$unit" \
    --registry data/other16 --budget-seconds 120 --method response --plan-strategy cover_informative "$@" \
    --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
  echo "$arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FOLDS...
  local core=$1; shift
  for fold in "$@"; do
    for unit in ${folds[$fold]}; do
      one "$core" A "$fold" "$unit"
      one "$core" L "$fold" "$unit" --ordinary-use 600 --use-log build/entry181_logs/"$unit"_o*.h5
    done
  done
}
half 0 0 2 & half 1 1 3
wait
