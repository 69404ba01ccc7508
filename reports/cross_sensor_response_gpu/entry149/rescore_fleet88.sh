#!/bin/bash
# Research log entry 149: entry 147's designed arm at 600 s: entry 146's fleet88 rescoring of fold $1 at 600 s (today's
# recipe, `designed` alone, the design of 750 s cut at 600 s: `designed_scale: 1.25`, alone and with 600 s of ordinary
# use) with entry 110's intervals (5 press folds, level 0.9, 24 factor units) and every unit tested on both its sessions,
# on data/fleet88h, `--paired-only` (only the intervals are read). Into entry149/at600/fleet88_seed$1.
#   bash reports/cross_sensor_response_gpu/entry149/rescore_fleet88.sh K   # K = 0, 1
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 FOLD" >&2; exit 2; }
export OMP_NUM_THREADS=1 PYTHONPATH=research
REGISTRY=data/fleet88h bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" 1 10 entry149/at600 \
  --added-protocol plan120 --added-protocol plan600 --added-protocol plan750 --added-protocol retest --paired-only \
  --set "data.protocol=[full, short, quick, plan120, plan600, plan750, retest]" \
  --set "options.plan_strategies=[designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[600]" \
  --set options.designed_scale=1.25 \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set splits.test_rows=all_sessions
