#!/bin/bash
# Research log entry 104: entry 101's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# the converged code fit, 120 s alone), `cover_informative` alone, with intervals learnt by 24 factor units beside
# the fold's 4 validation units (entry 50's `factor_units: 24`, no transfer-only check), the plan's residual
# correction on (`$2` = on: length 1, ratio 10, the recipe's) or off (`$2` = off: length 0), into
# entry104/fleet88_cpu_$2/fleet88_seed$1.
case $2 in on) length=1 ;; off) length=0 ;; *) echo "usage: $0 FOLD on|off" >&2; exit 2 ;; esac
bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" "$length" 10 entry104/fleet88_cpu_$2 \
  --set "options.plan_strategies=[cover_informative]" \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}"
