#!/bin/bash
# Research log entry 191: 64 fresh validation units' designed plan of 120 s with their session logs, weighed as
# held (H, today) and as the 600 s asked (S, entry 190's as_asked.py). Units and folds from units.py (fFOLD:
# fleet88's fold under entry 147's run, on data/val191d; oFOLD: other16's under entry 146's at-120 run, draw 0,
# on data/val191o); logs in build/entry191_logs (make_data.py first). Networks in build/entry191/ARM-FOLD/UNIT.
# Two at a time; about 20 minutes.
#   bash reports/cross_sensor_response_gpu/entry191/run.sh > reports/cross_sensor_response_gpu/entry191/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
mapfile -t pairs < <(python $G/entry191/units.py)
one() {  # CORE ARM FOLD UNIT
  local core=$1 arm=$2 fold=$3 unit=$4 out=build/entry191/$2-$3/$4 run=(anytip) where
  [ "$arm" = S ] && run=(python $G/entry190/as_asked.py 600)
  if [ "${fold:0:1}" = f ]; then
    where=(--model $G/entry147/at120/fleet88_seed${fold:1} --registry data/val191d)
  else
    where=(--model $G/entry146/at120/other16_severe_d0/other16_seed${fold:1} --registry data/val191o)
  fi
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" "${run[@]}" calibrate --unit "$unit" --method response \
    --plan-strategy designed --budget-seconds 120 --ordinary-use 600 "${where[@]}" \
    --use-log build/entry191_logs/"$unit"_o*.h5 --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
  echo "$arm-$fold $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP
  local i
  for ((i = $2; i < ${#pairs[@]}; i += $3)); do
    one "$1" H ${pairs[$i]}
    one "$1" S ${pairs[$i]}
  done
}
half 0 0 2 & half 1 1 2
wait
