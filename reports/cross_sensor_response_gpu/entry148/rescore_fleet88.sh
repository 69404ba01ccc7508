#!/bin/bash
# Research log entry 148: entry 147's designed arm (fleet88, fold $1, 120 s, both sessions) with each unit's network also
# trained on its transferred rows alone (`options.intervals.transfer_check: true`), whose residuals on the plan's rows,
# which it never saw, give the `transfer_` fields of the plan alone's rows. Into entry148/at120/fleet88_seed$1.
#   bash reports/cross_sensor_response_gpu/entry148/rescore_fleet88.sh K   # K = 0, 1
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 FOLD" >&2; exit 2; }
bash reports/cross_sensor_response_gpu/entry147/rescore_fleet88.sh "$1" entry148/at120 \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: true, factor_units: 24}"
