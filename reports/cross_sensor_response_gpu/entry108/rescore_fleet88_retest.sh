#!/bin/bash
# Research log entry 108: entry 106's rescoring of fold $1 (the recipe with ordinary use and the plan's residual
# correction, fleet88's CPU response models, `cover_informative`, 24 factor units) with every unit tested in a
# session of its own: data/fleet88r is fleet88 plus each unit's test session (`anytip data simulate --registry
# data/fleet88r --units 88 --seed 40 --protocols full,short,quick,retest` into a copy of data/fleet88). Plans,
# networks and the plans' own half-widths are entry 106's; the validation, factor and held-out units' test rows
# (their test patches) are the session's. fleet88's runs saved no per-unit references, so `--paired-only`: the
# per_unit rows are the run's, scored on its own test rows, and only the intervals are read here. A later entry
# may give another directory under cross_sensor_response_gpu/ as $2 and more `--set` options after it.
[ $# -ge 1 ] || { echo "usage: $0 FOLD [OUTDIR [--set KEY=VALUE ...]]" >&2; exit 2; }
k=$1; out=${2:-entry108/fleet88r_use}; shift $(( $# < 2 ? $# : 2 ))
bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$k" 1 10 "$out" \
  --set "options.plan_strategies=[cover_informative]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --registry data/fleet88r --added-protocol retest --paired-only --set "data.protocol=[full, short, quick, retest]" "$@"
