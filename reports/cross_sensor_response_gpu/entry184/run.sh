#!/bin/bash
# Research log entry 184: entry 182's L arms asked for the seconds their logs hold (arm W: --ordinary-use set to
# each L calibration's unlabeled_seconds plus 0.001 s) on data/use182, into build/entry182/W<budget>/UNIT, beside
# entry 182's networks. Two units at a time; about 12 minutes.
#   bash reports/cross_sensor_response_gpu/entry184/run.sh > reports/cross_sensor_response_gpu/entry184/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
model=$G/entry147/at120/fleet88_seed0
units=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
half() {  # CORE FIRST STEP
  local core=$1 i b u out held
  for ((i = $2; i < ${#units[@]}; i += $3)); do
    u=${units[$i]}
    for b in 120 60 30; do
      held=$(python -c "import json; print(json.load(open('build/entry182/L$b/$u/calibration.json'))['unlabeled_seconds'] + 0.001)")
      out=build/entry182/W$b/$u
      rm -rf "$out"; mkdir -p "$(dirname "$out")"
      OMP_NUM_THREADS=1 taskset -c "$core" anytip calibrate --model $model --unit "$u" --registry data/use182 \
        --budget-seconds $b --method response --plan-strategy designed --ordinary-use "$held" \
        --use-log build/entry182_logs/"$u"_*.h5 --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
      echo "W$b $u $(sha256sum "$out/model.safetensors" | cut -c1-16)"
    done
  done
}
half 0 0 2 & half 1 1 2
wait
