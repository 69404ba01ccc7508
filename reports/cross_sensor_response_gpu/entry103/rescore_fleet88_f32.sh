#!/bin/bash
# Research log entry 103: entry 101's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# the converged code fit, the plan's residual correction of length 1 and ratio 10: the recipe's), `cover_informative`
# alone, with the code of the checkout it runs from (the correction's kernel over the query rows in float32), into
# entry103/fleet88_cpu/fleet88_seed$1. Control: entry101/fleet88_cpu. The registry is simulated again (same_rows.py).
k=$1
python reports/cross_sensor_response_gpu/entry101/same_rows.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_response_gpu/entry103/fleet88_cpu/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4 \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10
