#!/bin/bash
# Research log entry 147: entry 146's fleet88 rescoring of fold $1 at 120 s (today's recipe, `designed` alone, the
# design of 150 s cut at 120 s: `options.designed_scale: 1.25`, alone and with 600 s of ordinary use) with entry 110's
# intervals (5 press folds, level 0.9, 24 factor units beside the fold's validation units) and every unit tested on
# both its sessions (`splits.test_rows: all_sessions`: its main rows at its test patches and its test session's
# there), on data/fleet88h (entry 146's data/fleet88g plus each unit's test session). fleet88's runs saved no per-unit
# references, so `--paired-only`: the per_unit rows are the run's, scored on its own test rows, and only the
# intervals are read. Into entry147/at120/fleet88_seed$1; a later entry may give another directory under
# cross_sensor_response_gpu/ as $2 and more `--set` options after it (the last wins).
#   bash reports/cross_sensor_response_gpu/entry147/rescore_fleet88.sh K   # K = 0, 1
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 FOLD [OUTDIR [--set KEY=VALUE ...]]" >&2; exit 2; }
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1; out=${2:-entry147/at120}; shift $(( $# < 2 ? $# : 2 ))
REGISTRY=data/fleet88h bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$k" 1 10 "$out" \
  --added-protocol plan120 --added-protocol plan150 --added-protocol retest --paired-only \
  --set "data.protocol=[full, short, quick, plan120, plan150, retest]" --set "options.plan_strategies=[designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" --set "options.budgets=[120]" \
  --set options.designed_scale=1.25 \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set splits.test_rows=all_sessions "$@"
