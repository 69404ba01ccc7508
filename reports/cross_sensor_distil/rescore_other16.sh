#!/bin/bash
# Research log entry 78: entry 54's other16 fold K rescored at 120 s with ARM = none, fitted or oracle
# (`options.response.label_free.distil`, 4 repeats), without intervals.
#   bash reports/cross_sensor_distil/rescore_other16.sh K ARM
set -euo pipefail
k=$1 arm=$2
export OMP_NUM_THREADS=1 PYTHONPATH=research
python scripts/rescore_response.py reports/cross_sensor_response_gpu/entry54/b512e60/other16_seed$k \
  --registry data/other16 --out reports/cross_sensor_distil/other16_${arm}_seed$k \
  --response-model "reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" \
  --set "options.response.label_free.distil=$arm" --set "options.response.label_free.distil_repeat=4"
