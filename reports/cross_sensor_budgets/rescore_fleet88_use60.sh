#!/bin/bash
# Research log entry 76: entry 46's fleet88 fold K rescored at 60 s, with and without ordinary use.
#   bash reports/cross_sensor_budgets/rescore_fleet88_use60.sh K
set -euo pipefail
k=$1
export OMP_NUM_THREADS=1 PYTHONPATH=research
python scripts/rescore_response.py reports/cross_sensor_response_label_free/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_budgets/fleet88_use60_seed$k \
  --response-model "reports/cross_sensor_response_label_free/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[60]" --set "options.intervals=null"
