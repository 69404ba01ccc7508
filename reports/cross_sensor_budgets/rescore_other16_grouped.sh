#!/bin/bash
# Research log entry 79, second part: entry 26's other16 fold K rescored at its own budgets (30, 120 and
# 600 s, the labels alone) with each budget's jobs in a fleet of their own.
#   bash reports/cross_sensor_budgets/rescore_other16_grouped.sh K
set -euo pipefail
k=$1
export OMP_NUM_THREADS=1 PYTHONPATH=research
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k \
  --registry data/other16 --out reports/cross_sensor_budgets/other16_grouped_seed$k \
  --response-model "reports/cross_sensor_response_start/other16_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.intervals=null"
