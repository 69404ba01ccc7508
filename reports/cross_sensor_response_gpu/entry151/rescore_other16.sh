#!/bin/bash
# Research log entry 151, in the variant's worktree: entry 146's 120 s arm (today's recipe, `designed_scale: 1.25`)
# for fold $1 in start draw $2, the designed plan only, on data/other16i$1 (each unit's plan150 pressed at fold $1's
# informative design), into entry151/at120/other16_severe_d$2/other16_seed$1. Entry 152 gives its registry's
# letter as $3 (data/other16<letter>$1) and its output directory under cross_sensor_response_gpu/ as $4.
#   bash reports/cross_sensor_response_gpu/entry151/rescore_other16.sh K D
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 d=$2 letter=${3:-i} out=${4:-entry151/at120}
REGISTRY=data/other16$letter$k bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$k" \
  "$d" "$out" --added-protocol plan150 --set "data.protocol=[full, short, quick, plan120, plan150]" \
  --set options.designed_scale=1.25 --set "options.plan_strategies=[designed]"
