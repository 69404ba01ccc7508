#!/bin/bash
# Research log entry 122: entry 105's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# the converged code fit, criterion v, the plan's residual correction of length 1 and ratio 10, 600 s of
# ordinary use in the codes' fit: the recipe `anytip calibrate --ordinary-use 600` runs) on data/fleet88p,
# fleet88 with each unit's designed 120 s calibration added (plan120), `cover_informative` and `designed`
# side by side, into entry122/fleet88_seed$1. The registry is simulated again (entry 101's same_rows.py). A later
# entry may give another directory under cross_sensor_response_gpu/ as $2 and more `--set` options after it
# (the last wins).
k=$1; out=${2:-entry122}; shift $(( $# < 2 ? $# : 2 ))
python reports/cross_sensor_response_gpu/entry101/same_rows.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88p --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --out reports/cross_sensor_response_gpu/$out/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover_informative, designed]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4 \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10 \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" "$@"
