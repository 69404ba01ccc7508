#!/bin/bash
# Research log entry 183: other16's 16 units, each under the fold that holds it out (entry 146's at-120 runs, start
# draw 0), at 120 s: entry 181's arms again on data/other16 as the gate (A: cover_informative alone; L: with its
# ordinary-use logs, build/entry181_logs/ from entry 181's make_logs.py), and the designed plan on data/other16p
# alone (Ad) and with the same logs (Ld), into build/entry183/. Two units at a time; about 15 minutes.
#   bash reports/cross_sensor_response_gpu/entry183/run.sh > reports/cross_sensor_response_gpu/entry183/logs/run.log
set -euo pipefail
runs=reports/cross_sensor_response_gpu/entry146/at120/other16_severe_d0
folds=("SIM23-000 SIM23-002 SIM23-013 SIM23-014" "SIM23-004 SIM23-008 SIM23-011 SIM23-012"
       "SIM23-001 SIM23-003 SIM23-006 SIM23-007" "SIM23-005 SIM23-009 SIM23-010 SIM23-015")
one() {  # CORE ARM FOLD UNIT REGISTRY STRATEGY [OPTION...]
  local core=$1 arm=$2 fold=$3 unit=$4 registry=$5 strategy=$6; shift 6
  local out=build/entry183/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" anytip calibrate --model $runs/other16_seed$fold --unit "$unit" \
    --registry "$registry" --budget-seconds 120 --method response --plan-strategy "$strategy" "$@" \
    --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
  echo "$arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FOLDS...
  local core=$1 logs; shift
  for fold in "$@"; do
    for unit in ${folds[$fold]}; do
      logs=(build/entry181_logs/"$unit"_o*.h5)
      one "$core" A "$fold" "$unit" data/other16 cover_informative
      one "$core" L "$fold" "$unit" data/other16 cover_informative --ordinary-use 600 --use-log "${logs[@]}"
      one "$core" Ad "$fold" "$unit" data/other16p designed
      one "$core" Ld "$fold" "$unit" data/other16p designed --ordinary-use 600 --use-log "${logs[@]}"
    done
  done
}
half 0 0 2 & half 1 1 3
wait
