#!/bin/bash
# Research log entries 76-77: entry 46's fleet88 fold K rescored at S seconds, with and without ordinary use.
#   bash reports/cross_sensor_budgets/rescore_fleet88_use.sh K S    (entry 76: S=60, entry 77: S=30)
set -euo pipefail
k=$1 s=$2
export OMP_NUM_THREADS=1 PYTHONPATH=research
python scripts/rescore_response.py reports/cross_sensor_response_label_free/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_budgets/fleet88_use${s}_seed$k \
  --response-model "reports/cross_sensor_response_label_free/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[$s]" --set "options.intervals=null"
