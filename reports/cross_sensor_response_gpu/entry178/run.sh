#!/bin/bash
# Research log entry 178: `anytip calibrate --plan-strategy designed` at 120 s on 16 held-out units of fleet88
# fold 0 (entry 147's run): the plan alone on data/use178 (A) and data/use178det (A2, the gate), and with
# 600 s of ordinary use read through the force flag (B, data/use178) or through a detector on pressures
# (C, data/use178det). Two units at a time, one per core; about 12 minutes. Networks in build/entry178/.
#   bash reports/cross_sensor_response_gpu/entry178/run.sh > reports/cross_sensor_response_gpu/entry178/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
model=$G/entry147/at120/fleet88_seed0
units=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
one() {  # CORE ARM REGISTRY UNIT [OPTION...]
  local core=$1 arm=$2 registry=$3 unit=$4; shift 4
  local out=build/entry178/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" anytip calibrate --model $model --unit "$unit" --registry "$registry" \
    --budget-seconds 120 --method response --plan-strategy designed "$@" --out "$out" > "$out.log" 2>&1 \
    || { cat "$out.log"; exit 1; }
  echo "$arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP
  for ((i = $2; i < ${#units[@]}; i += $3)); do
    u=${units[$i]}
    one "$1" A data/use178 "$u"
    one "$1" A2 data/use178det "$u"
    one "$1" B data/use178 "$u" --ordinary-use 600
    one "$1" C data/use178det "$u" --ordinary-use 600
  done
}
half 0 0 2 & half 1 1 2
wait
