#!/bin/bash
# Research log entry 186: other16's 16 units, each under the fold that holds it out (entry 146's at-120 runs, start
# draw 0), the designed plan of 120 s on data/other16p with entry 181's session's logs (D1) and with that session
# then entry 186's two more (D3, make_logs.py), --ordinary-use 600, into build/entry186/. Two units at a time;
# about 8 minutes.
#   bash reports/cross_sensor_response_gpu/entry186/run.sh > reports/cross_sensor_response_gpu/entry186/logs/run.log
set -euo pipefail
runs=reports/cross_sensor_response_gpu/entry146/at120/other16_severe_d0
folds=("SIM23-000 SIM23-002 SIM23-013 SIM23-014" "SIM23-004 SIM23-008 SIM23-011 SIM23-012"
       "SIM23-001 SIM23-003 SIM23-006 SIM23-007" "SIM23-005 SIM23-009 SIM23-010 SIM23-015")
one() {  # CORE ARM FOLD UNIT LOG...
  local core=$1 arm=$2 fold=$3 unit=$4; shift 4
  local out=build/entry186/$arm/$unit
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" anytip calibrate --model $runs/other16_seed$fold --unit "$unit" \
    --registry data/other16p --budget-seconds 120 --method response --plan-strategy designed \
    --ordinary-use 600 --use-log "$@" --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
  echo "$arm $unit $(sha256sum "$out/model.safetensors" | cut -c1-16)"
}
half() {  # CORE FOLDS...
  local core=$1 first; shift
  for fold in "$@"; do
    for unit in ${folds[$fold]}; do
      first=(build/entry181_logs/"$unit"_o*.h5)
      one "$core" D1 "$fold" "$unit" "${first[@]}"
      one "$core" D3 "$fold" "$unit" "${first[@]}" build/entry186_logs/"$unit"_s2_*.h5 build/entry186_logs/"$unit"_s3_*.h5
    done
  done
}
half 0 0 2 & half 1 1 3
wait
