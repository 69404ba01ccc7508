#!/bin/bash
# Research log entry 152, in entry 151's variant worktree: entry 151's other16 rescoring of fold $1 in start draw
# $2 on data/other16j$1 (fold $1's within-level design), into entry152/at120/other16_severe_d$2/other16_seed$1.
#   bash reports/cross_sensor_response_gpu/entry152/rescore_other16.sh K D
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 d=$2
REGISTRY=data/other16j$k bash reports/cross_sensor_response_gpu/entry121/rescore_other16_designed.sh "$k" "$d" \
  entry152/at120 --added-protocol plan150 --set "data.protocol=[full, short, quick, plan120, plan150]" \
  --set options.designed_scale=1.25 --set "options.plan_strategies=[designed]"
