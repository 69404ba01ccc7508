#!/bin/bash
# Research log entry 74: entry 26's fleet88 fold K rescored at 10-600 s (the plan's labels alone).
# One fold at a time: each peaks at 14.7 GB.   bash reports/cross_sensor_budgets/rescore_fleet88.sh K
# Entry 79: the same with each budget's jobs in a fleet of their own (the code since), into
# fleet88_grouped_seedK.                      bash reports/cross_sensor_budgets/rescore_fleet88.sh K grouped
set -euo pipefail
k=$1 tag=${2:+_$2}
export OMP_NUM_THREADS=1 PYTHONPATH=research
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_budgets/fleet88${tag}_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[10, 30, 60, 120, 600]" --set "options.intervals=null"
