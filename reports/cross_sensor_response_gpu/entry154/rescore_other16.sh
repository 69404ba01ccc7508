#!/bin/bash
# Research log entry 154: entry 146's other16 rescoring (entry 121's driver: today's recipe, start draw $2,
# `designed` alone and with 600 s of ordinary use, `designed_scale: 1.25`) at 30 and 60 s on data/other16d,
# fold $1, into entry154/other16_severe_d$2/other16_seed$1.
#   bash reports/cross_sensor_response_gpu/entry154/rescore_other16.sh K D
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
REGISTRY=data/other16d bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$1" "$2" \
  entry154 --added-protocol plan37.5 --added-protocol plan75 \
  --set "data.protocol=[full, short, quick, plan120, plan37.5, plan75]" --set "options.plan_strategies=[designed]" \
  --set "options.budgets=[30, 60]" --set options.designed_scale=1.25
