#!/bin/bash
# Research log entry 188: `anytip calibrate --plan-strategy designed` at 120 s without ordinary use, the plan's
# effective rows in the code fit times P (`plan_weight.py`), arms P1, P0.25 and P4. Part A: other16's 16 units under
# the folds that hold them out (entry 146's at-120 runs, start draw 0) on data/other16p (entry 183's Ad). Part B:
# entry 178's 16 units of fleet88 with entry 147's run on data/use182 (entry 182's A120). Networks in
# build/entry188/PART/ARM/UNIT. Two units at a time, one per core; about 15 minutes.
#   bash reports/cross_sensor_response_gpu/entry188/run.sh > reports/cross_sensor_response_gpu/entry188/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
. $G/entry187/units.sh
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
