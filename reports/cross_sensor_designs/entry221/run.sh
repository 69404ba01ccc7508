#!/bin/bash
# Research log entry 221: `bash reports/cross_sensor_designs/entry221/run.sh CORE "FOLDS"` rescores the pad's
# committed fold runs (reports/cross_sensor_designs/pad_plans_seedK) at budget 0 alone, the label-free search
# reading every one of the 128,000 source rows as a candidate (`options.response.label_free.candidates=131072`),
# into reports/cross_sensor_designs/entry221/all_seedK, one run after another on CPU core CORE.
set -euo pipefail
core=$1 folds=$2
here=reports/cross_sensor_designs
mkdir -p $here/entry221/logs
for k in $folds; do
  out=$here/entry221/all_seed${k}
  [ -f "$out/metrics.json" ] && continue
  OMP_NUM_THREADS=1 taskset -c "$core" python scripts/rescore_response.py "$here/pad_plans_seed${k}" \
    --registry data/pad24p --out "$out" --set "options.budgets=[0]" \
    --set "options.response.label_free.candidates=131072" > "$here/entry221/logs/all_seed${k}.log" 2>&1
done
