#!/bin/bash
# Research log entry 154: entry 146's fleet88 rescoring (today's recipe, `designed` alone and with 600 s of
# ordinary use, `designed_scale: 1.25`) at 30 and 60 s on data/fleet88d, fold $1, into entry154/fleet88_seed$1 (or
# $OUT/fleet88_seed$1, with entry 101's DRAW passed on: entry 174).
#   bash reports/cross_sensor_response_gpu/entry154/rescore_fleet88.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
REGISTRY=data/fleet88d bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" 1 10 "${OUT:-entry154}" \
  --added-protocol plan37.5 --added-protocol plan75 --set "data.protocol=[full, short, quick, plan37.5, plan75]" \
  --set "options.plan_strategies=[designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[30, 60]" \
  --set options.designed_scale=1.25
