#!/bin/bash
# Research log entry 151, in the variant's worktree: entry 146's fleet88 arm at 120 s (today's recipe,
# `designed_scale: 1.25`, the designed plan alone and with ordinary use) for fold $1 on data/fleet88i$1 (each unit's
# plan150 pressed at fold $1's informative design), into entry151/at120/fleet88_seed$1.
#   bash reports/cross_sensor_response_gpu/entry151/rescore_fleet88.sh K
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1
REGISTRY=data/fleet88i$k bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$k" 1 10 \
  entry151/at120 --added-protocol plan120 --added-protocol plan150 \
  --set "data.protocol=[full, short, quick, plan120, plan150]" --set "options.plan_strategies=[designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[120]" \
  --set options.designed_scale=1.25
