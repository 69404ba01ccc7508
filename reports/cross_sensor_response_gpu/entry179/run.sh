#!/bin/bash
# Research log entry 179: entry 178's arm C on its 16 units with the trimmed detector (data/use179det): C2,
# into build/entry178/C2/, two units at a time, one per core; about 4 minutes.
#   bash reports/cross_sensor_response_gpu/entry179/run.sh > reports/cross_sensor_response_gpu/entry179/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
model=$G/entry147/at120/fleet88_seed0
units=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
half() {  # CORE FIRST STEP
  for ((i = $2; i < ${#units[@]}; i += $3)); do
    local unit=${units[$i]} out=build/entry178/C2/${units[$i]}
    rm -rf "$out"; mkdir -p "$(dirname "$out")"
    OMP_NUM_THREADS=1 taskset -c "$1" anytip calibrate --model $model --unit "$unit" --registry data/use179det \
      --budget-seconds 120 --method response --plan-strategy designed --ordinary-use 600 --out "$out" \
      > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
    echo "C2 $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
  done
}
half 0 0 2 & half 1 1 2
wait
