#!/bin/bash
# Research log entry 190: the validation units' designed plan of 120 s with their session logs, weighed as held
# (H, today) and as the 600 s asked (S, as_asked.py). other16: each fold's two validation units under that fold's
# at-120 run of entry 146 (draw 0) on data/other16p with entry 181's logs; fleet88: fold 0's four validation units
# with entry 147's run on data/val190 with build/entry190_logs (make the registry first:
#   python -c 'import runpy, sys; from pathlib import Path; runpy.run_path(sys.argv[1])["main"]("data/fleet88p",
#     "data/val190", ["SIM40-007", "SIM40-009", "SIM40-034", "SIM40-068"], Path("build/entry190_logs"))' \
#     reports/cross_sensor_response_gpu/entry182/make_registry.py
# ). Networks in build/entry190/ARM-FOLD/UNIT (FOLD f: fleet88 fold 0). Two at a time; about 10 minutes.
#   bash reports/cross_sensor_response_gpu/entry190/run.sh > reports/cross_sensor_response_gpu/entry190/logs/run.log
set -euo pipefail
G=reports/cross_sensor_response_gpu
pairs=("0 SIM23-004" "0 SIM23-011" "1 SIM23-010" "1 SIM23-015" "2 SIM23-000" "2 SIM23-004" "3 SIM23-008"
       "3 SIM23-014" "f SIM40-007" "f SIM40-009" "f SIM40-034" "f SIM40-068")
one() {  # CORE ARM FOLD UNIT
  local core=$1 arm=$2 fold=$3 unit=$4 out=build/entry190/$2-$3/$4 run=(anytip) where
  [ "$arm" = S ] && run=(python $G/entry190/as_asked.py 600)
  if [ "$fold" = f ]; then
    where=(--model $G/entry147/at120/fleet88_seed0 --registry data/val190 --use-log build/entry190_logs/"$unit"_*.h5)
  else
    where=(--model $G/entry146/at120/other16_severe_d0/other16_seed$fold --registry data/other16p
           --use-log build/entry181_logs/"$unit"_o*.h5)
  fi
  rm -rf "$out"; mkdir -p "$(dirname "$out")"
  OMP_NUM_THREADS=1 taskset -c "$core" "${run[@]}" calibrate --unit "$unit" --method response \
    --plan-strategy designed --budget-seconds 120 --ordinary-use 600 "${where[@]}" --out "$out" > "$out.log" 2>&1 \
    || { cat "$out.log"; exit 1; }
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
