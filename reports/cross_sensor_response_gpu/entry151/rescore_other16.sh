#!/bin/bash
# Research log entry 151, in the variant's worktree: entry 146's 120 s arm (today's recipe, `designed_scale: 1.25`)
# for fold $1 in start draw $2, the designed plan only, on data/other16i$1 (each unit's plan150 pressed at fold $1's
# informative design), into entry151/at120/other16_severe_d$2/other16_seed$1.
#   bash reports/cross_sensor_response_gpu/entry151/rescore_other16.sh K D
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 d=$2
REGISTRY=data/other16i$k bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$k" "$d" \
  entry151/at120 --added-protocol plan150 --set "data.protocol=[full, short, quick, plan120, plan150]" \
  --set options.designed_scale=1.25 --set "options.plan_strategies=[designed]"
