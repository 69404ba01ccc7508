#!/bin/bash
# Research log entry 182: `anytip calibrate --plan-strategy designed` on entry 178's 16 units of data/use182
# (`make_registry.py`) with entry 147's run: the gate A_120 (the plan alone at 120 s), then per budget of 60 and
# 30 s the plan alone (A), with the session through the force flag (B) and with its ordinary-use logs (L); and
# L_120 (entry 180's arm) as a second gate.
# Two units at a time, one per core; about 25 minutes. Networks in build/entry182/ARM/UNIT.
#   bash reports/cross_sensor_response_gpu/entry182/run.sh > reports/cross_sensor_response_gpu/entry182/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
model=$G/entry147/at120/fleet88_seed0
units=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
one() {  # CORE ARM BUDGET UNIT [OPTION...]
  local core=$1 arm=$2 budget=$3 unit=$4; shift 4
  local out=build/entry182/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" anytip calibrate --model $model --unit "$unit" --registry data/use182 \
    --budget-seconds "$budget" --method response --plan-strategy designed "$@" --out "$out" > "$out.log" 2>&1 \
    || { cat "$out.log"; exit 1; }
  echo "$arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP
  for ((i = $2; i < ${#units[@]}; i += $3)); do
    u=${units[$i]}
    one "$1" A120 120 "$u"
    one "$1" L120 120 "$u" --ordinary-use 600 --use-log build/entry182_logs/"$u"_*.h5
    for b in 60 30; do
      one "$1" A$b $b "$u"
      one "$1" B$b $b "$u" --ordinary-use 600
      one "$1" L$b $b "$u" --ordinary-use 600 --use-log build/entry182_logs/"$u"_*.h5
    done
  done
}
half 0 0 2 & half 1 1 2
wait
