#!/bin/bash
# Research log entry 75: entry 54's other16 fold K rescored at 10-120 s, with and without ordinary use
# (the 1,034-unit response models trained on a GPU, scored on a CPU; 2.2 GB, 7-8 min per fold).
#   bash reports/cross_sensor_budgets/rescore_other16.sh K
# Entry 79: the same with each budget's jobs in a fleet of their own, into other16_use_grouped_seedK:
#   bash reports/cross_sensor_budgets/rescore_other16.sh K grouped
set -euo pipefail
k=$1 out=other16_seed$1
[ "${2:-}" = grouped ] && out=other16_use_grouped_seed$1
export OMP_NUM_THREADS=1 PYTHONPATH=research
python scripts/rescore_response.py reports/cross_sensor_response_gpu/entry54/b512e60/other16_seed$k \
  --registry data/other16 --out reports/cross_sensor_budgets/$out \
  --response-model "reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors" \
  --set "options.budgets=[10, 30, 60, 120]" --set "options.intervals=null"
