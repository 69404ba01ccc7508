#!/bin/bash
# Research log entry 74: entry 26's fleet88 fold K rescored at 10-600 s (the plan's labels alone).
# One fold at a time: each peaks at 14.7 GB.   bash reports/cross_sensor_budgets/rescore_fleet88.sh K
set -euo pipefail
k=$1
export OMP_NUM_THREADS=1 PYTHONPATH=research
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_budgets/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[10, 30, 60, 120, 600]" --set "options.intervals=null"
