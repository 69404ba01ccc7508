#!/bin/bash
# Research log entry 153: today's recipe on fleet88 (entry 101's driver: the CPU response models, the registry
# code prior, the converged code fit, criterion v, the plan's residual correction, centred with ordinary use)
# at 10, 30, 60 and 120 s, `cover_informative` alone and with 600 s of ordinary use, fold $1, on data/fleet88,
# into entry153/fleet88_seed$1.
#   bash reports/cross_sensor_response_gpu/entry153/rescore_fleet88.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" 1 10 entry153 \
  --set "options.plan_strategies=[cover_informative]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set "options.budgets=[10, 30, 60, 120]"
