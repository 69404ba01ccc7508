#!/bin/bash
# Research log entry 148: entry 147's designed arm (fleet88, fold $1, 120 s, both sessions) with each unit's network also
# trained on its transferred rows alone (`options.intervals.transfer_check: true`), whose residuals on the plan's rows,
# which it never saw, give the `transfer_` fields of the plan alone's rows. Into entry148/at120/fleet88_seed$1.
#   bash reports/cross_sensor_response_gpu/entry148/rescore_fleet88.sh K   # K = 0, 1
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 FOLD" >&2; exit 2; }
export OMP_NUM_THREADS=1 PYTHONPATH=research
REGISTRY=data/fleet88h bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" 1 10 entry148/at120 \
  --added-protocol plan120 --added-protocol plan150 --added-protocol retest --paired-only \
  --set "data.protocol=[full, short, quick, plan120, plan150, retest]" --set "options.plan_strategies=[designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[120]" \
  --set options.designed_scale=1.25 \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: true, factor_units: 24}" \
  --set splits.test_rows=all_sessions
