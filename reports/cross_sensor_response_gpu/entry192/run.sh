#!/bin/bash
# Research log entry 192: entry 191's 64 fresh validation units, the designed plan of 30 s with their session
# logs weighed as 600 s (F, the benchmark's weight) and as 150 s (Q: to a 30 s plan what 600 s is to 120 s),
# both through entry 190's as_asked.py; units, folds and models as entry 191's run.sh (make_data.py first).
# Networks in build/entry192/ARM-FOLD/UNIT. Two at a time; about 20 minutes.
#   bash reports/cross_sensor_response_gpu/entry192/run.sh > reports/cross_sensor_response_gpu/entry192/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
mapfile -t pairs < <(python $G/entry191/units.py)
one() {  # CORE ARM FOLD UNIT
  local core=$1 arm=$2 fold=$3 unit=$4 out=build/entry192/$2-$3/$4 weight=600 where
  [ "$arm" = Q ] && weight=150
  if [ "${fold:0:1}" = f ]; then
    where=(--model $G/entry147/at120/fleet88_seed${fold:1} --registry data/val191d)
  else
    where=(--model $G/entry146/at120/other16_severe_d0/other16_seed${fold:1} --registry data/val191o)
  fi
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" python $G/entry190/as_asked.py $weight calibrate --unit "$unit" \
    --method response --plan-strategy designed --budget-seconds 30 --ordinary-use 600 "${where[@]}" \
    --use-log build/entry191_logs/"$unit"_o*.h5 --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
  echo "$arm-$fold $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP
  local i
  for ((i = $2; i < ${#pairs[@]}; i += $3)); do
    one "$1" F ${pairs[$i]}
    one "$1" Q ${pairs[$i]}
  done
}
half 0 0 2 & half 1 1 2
wait
