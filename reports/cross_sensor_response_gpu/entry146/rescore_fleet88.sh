#!/bin/bash
# Research log entry 146: today's recipe on fleet88 (entry 101's driver with the options of entries 143 and 122)
# with the designed plan of budget B read from the design of B x 1.25 (`options.designed_scale`), on
# data/fleet88g, `designed` alone (`cover_informative`'s rows are the base run's: other16's runs of this entry
# reproduce them exactly beside the filled plans), alone and with 600 s of ordinary use.
#   bash reports/cross_sensor_response_gpu/entry146/rescore_fleet88.sh 600 K   # against entry 143
#   bash reports/cross_sensor_response_gpu/entry146/rescore_fleet88.sh 120 K   # against entry 131
# OUT: another directory under cross_sensor_response_gpu/ (entry 173, with entry 101's DRAW passed on).
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
b=$1 k=$2
case $b in
  600) plans=(--added-protocol plan120 --added-protocol plan600 --added-protocol plan750
              --set "data.protocol=[full, short, quick, plan120, plan600, plan750]") ;;
  120) plans=(--added-protocol plan120 --added-protocol plan150
              --set "data.protocol=[full, short, quick, plan120, plan150]") ;;
  *) echo "usage: $0 600|120 FOLD" >&2; exit 2 ;;
esac
REGISTRY=data/fleet88g bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$k" 1 10 \
  "${OUT:-entry146/at$b}" "${plans[@]}" --set "options.plan_strategies=[designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[$b]" \
  --set options.designed_scale=1.25
