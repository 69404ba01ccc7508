#!/bin/bash
# Research log entry 105: entry 101's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# the converged code fit), `cover_informative` alone, with each unit's 600 s of ordinary use in the fit of its
# codes beside its plan (`label_free: {with_plans: true, zero_shot: false}`, as entries 45-46), the plan's
# residual correction on (`$2` = on: length 1, ratio 10) or off (`$2` = off), into
# entry105/fleet88_cpu_use_$2/fleet88_seed$1. No intervals (entry 104 scored them).
case $2 in on) length=1 ;; off) length=0 ;; *) echo "usage: $0 FOLD on|off" >&2; exit 2 ;; esac
bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$1" "$length" 10 entry105/fleet88_cpu_use_$2 \
  --set "options.plan_strategies=[cover_informative]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}"
