#!/bin/bash
# Research log entry 122: entry 105's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# the converged code fit, criterion v, the plan's residual correction of length 1 and ratio 10, 600 s of
# ordinary use in the codes' fit: the recipe `anytip calibrate --ordinary-use 600` runs) on data/fleet88p,
# fleet88 with each unit's designed 120 s calibration added (plan120), `cover_informative` and `designed`
# side by side, into entry122/fleet88_seed$1: entry 101's driver with the registry and these options after its
# own. A later entry may give another directory under cross_sensor_response_gpu/ as $2 and more `--set`
# options after it (the last wins).
k=$1; out=${2:-entry122}; shift $(( $# < 2 ? $# : 2 ))
REGISTRY=data/fleet88p bash reports/cross_sensor_response_gpu/entry101/rescore_fleet88_cpu.sh "$k" 1 10 \
  "$out" --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[cover_informative, designed]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" "$@"
