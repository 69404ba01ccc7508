#!/bin/bash
# Research log entry 106: entry 105's on arm (entry 101's fleet88 rescoring of fold $1, CPU response models,
# `cover_informative` alone, the plan's residual correction at length 1, ratio 10, each unit's 600 s of ordinary
# use in its codes' fit) with entry 104's intervals (24 factor units beside the fold's 4 validation units, no
# transfer-only check), into entry106/fleet88_cpu_use/fleet88_seed$1.
[ $# -eq 1 ] || { echo "usage: $0 FOLD" >&2; exit 2; }
bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" 1 10 entry106/fleet88_cpu_use \
  --set "options.plan_strategies=[cover_informative]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}"
