#!/bin/bash
# Research log entry 185: entry 178's 16 units, the designed plan of 60 s on data/use182 with logs of ordinary
# use in recorded order: entry 182's session read for 60, 120 and 600 s (U60, U120, U1), and that session then
# entry 185's two more (make_logs.py) read for 600 s (U3), into build/entry185/. Two units at a time; about
# 12 minutes.
#   bash reports/cross_sensor_response_gpu/entry185/run.sh > reports/cross_sensor_response_gpu/entry185/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
model=$G/entry147/at120/fleet88_seed0
units=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
one() {  # CORE ARM UNIT SECONDS LOG...
  local core=$1 arm=$2 unit=$3 seconds=$4; shift 4
  local out=build/entry185/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" anytip calibrate --model $model --unit "$unit" --registry data/use182 \
    --budget-seconds 60 --method response --plan-strategy designed --ordinary-use "$seconds" --use-log "$@" \
    --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
  echo "$arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FIRST STEP
  local i u first
  for ((i = $2; i < ${#units[@]}; i += $3)); do
    u=${units[$i]}
    first=(build/entry182_logs/"$u"_*.h5)
    one "$1" U60 "$u" 60 "${first[@]}"
    one "$1" U120 "$u" 120 "${first[@]}"
    one "$1" U1 "$u" 600 "${first[@]}"
    one "$1" U3 "$u" 600 "${first[@]}" build/entry185_logs/"$u"_s2_*.h5 build/entry185_logs/"$u"_s3_*.h5
  done
}
half 0 0 2 & half 1 1 2
wait
