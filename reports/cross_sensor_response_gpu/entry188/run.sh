#!/bin/bash
# Research log entry 188: `anytip calibrate --plan-strategy designed` at 120 s without ordinary use, the plan's
# effective rows in the code fit times P (`plan_weight.py`), arms P1, P0.25 and P4. Part A: other16's 16 units under
# the folds that hold them out (entry 146's at-120 runs, start draw 0) on data/other16p (entry 183's Ad). Part B:
# entry 178's 16 units of fleet88 with entry 147's run on data/use182 (entry 182's A120). Networks in
# build/entry188/PART/ARM/UNIT. Two units at a time, one per core; about 15 minutes.
#   bash reports/cross_sensor_response_gpu/entry188/run.sh > reports/cross_sensor_response_gpu/entry188/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
other=(SIM23-000 SIM23-002 SIM23-013 SIM23-014 SIM23-004 SIM23-008 SIM23-011 SIM23-012
       SIM23-001 SIM23-003 SIM23-006 SIM23-007 SIM23-005 SIM23-009 SIM23-010 SIM23-015)
fleet=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
ARMS=("P1 1" "P0.25 0.25" "P4 4")
one() {  # CORE PART ARM P UNIT CALIBRATE-OPTION...
  local core=$1 part=$2 arm=$3 p=$4 unit=$5; shift 5
  local out=build/entry188/$part/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" python $G/entry188/plan_weight.py "$p" calibrate --unit "$unit" \
    --method response --plan-strategy designed --budget-seconds 120 "$@" --out "$out" > "$out.log" 2>&1 \
    || { cat "$out.log"; exit 1; }
  echo "$part $arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP
  local core=$1 i arm
  for ((i = $2; i < 16; i += $3)); do
    for arm in "${ARMS[@]}"; do
      one "$core" A $arm "${other[$i]}" --model $G/entry146/at120/other16_severe_d0/other16_seed$((i / 4)) \
        --registry data/other16p
      one "$core" B $arm "${fleet[$i]}" --model $G/entry147/at120/fleet88_seed0 --registry data/use182
    done
  done
}
half 0 0 2 & half 1 1 2
wait
