#!/bin/bash
# Research log entry 220: `bash reports/cross_sensor_designs/entry220/run.sh CORE "FOLDS"` rescores the pad's
# committed fold runs (reports/cross_sensor_designs/pad_plans_seedK) at budget 0 alone, the label-free fit run
# from search draws 0-3 in turn and each unit given the mean of their codes (`options.response.label_free.starts=4`),
# into reports/cross_sensor_designs/entry220/mean4_seedK, one run after another on CPU core CORE.
set -euo pipefail
core=$1 folds=$2
here=reports/cross_sensor_designs
mkdir -p $here/entry220/logs
for k in $folds; do
  out=$here/entry220/mean4_seed${k}
  [ -f "$out/metrics.json" ] && continue
  OMP_NUM_THREADS=1 taskset -c "$core" python scripts/rescore_response.py "$here/pad_plans_seed${k}" \
    --registry data/pad24p --out "$out" --set "options.budgets=[0]" \
    --set "options.response.label_free.starts=4" > "$here/entry220/logs/mean4_seed${k}.log" 2>&1
done
