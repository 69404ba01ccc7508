#!/bin/bash
# Research log entry 219: `bash reports/cross_sensor_designs/entry219/run.sh CORE "DRAWS" "FOLDS"` rescores the pad's
# committed fold runs (reports/cross_sensor_designs/pad_plans_seedK, their response models and references) at
# budget 0 alone, the label-free fit reading search draw D (`options.response.label_free.search_draw`), into
# reports/cross_sensor_designs/entry219/drawD_seedK, one run after another on CPU core CORE. Each run's log
# (logs/drawD_seedK.log) names every unit's final objective.
set -euo pipefail
core=$1 draws=$2 folds=$3
here=reports/cross_sensor_designs
mkdir -p $here/entry219/logs
for k in $folds; do
  for d in $draws; do
    out=$here/entry219/draw${d}_seed${k}
    [ -f "$out/metrics.json" ] && continue
    OMP_NUM_THREADS=1 taskset -c "$core" python scripts/rescore_response.py "$here/pad_plans_seed${k}" \
      --registry data/pad24p --out "$out" --set "options.budgets=[0]" \
      --set "options.response.label_free.search_draw=${d}" > "$here/entry219/logs/draw${d}_seed${k}.log" 2>&1
  done
done
