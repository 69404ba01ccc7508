#!/bin/bash
# Research log entry 187: `anytip calibrate --plan-strategy designed --ordinary-use 600 --use-log` with the joint
# fit's use weight times U and plan weight times P (`weighted_calibrate.py`), arms U1P1, U4P1, U1P4 and U4P4.
# Part A: other16's 16 units under the folds that hold them out (entry 146's at-120 runs, start draw 0), 120 s on
# data/other16p with entry 181's session logs (entry 186's D1). Part B: entry 178's 16 units of fleet88 with entry
# 147's run, 60 s on data/use182 with entry 182's logs (entry 184's W60). Networks in build/entry187/PART/ARM/UNIT.
# Two units at a time, one per core; about 25 minutes.
#   bash reports/cross_sensor_response_gpu/entry187/run.sh > reports/cross_sensor_response_gpu/entry187/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
. $G/entry187/units.sh
ARMS=("U1P1 1 1" "U4P1 4 1" "U1P4 1 4" "U4P4 4 4")
one() {  # CORE PART ARM U P UNIT CALIBRATE-OPTION...
  local core=$1 part=$2 arm=$3 u=$4 p=$5 unit=$6; shift 6
  local out=build/entry187/$part/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" python $G/entry187/weighted_calibrate.py "$u" "$p" calibrate --unit "$unit" \
    --method response --plan-strategy designed --ordinary-use 600 "$@" --out "$out" > "$out.log" 2>&1 \
    || { cat "$out.log"; exit 1; }
  echo "$part $arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP
  local core=$1 i unit arm
  for ((i = $2; i < 16; i += $3)); do
    for arm in "${ARMS[@]}"; do
      unit=${other[$i]}
      one "$core" A $arm "$unit" --model $G/entry146/at120/other16_severe_d0/other16_seed$((i / 4)) \
        --registry data/other16p --budget-seconds 120 --use-log build/entry181_logs/"$unit"_o*.h5
      unit=${fleet[$i]}
      one "$core" B $arm "$unit" --model $G/entry147/at120/fleet88_seed0 --registry data/use182 \
        --budget-seconds 60 --use-log build/entry182_logs/"$unit"_*.h5
    done
  done
}
half 0 0 2 & half 1 1 2
wait
