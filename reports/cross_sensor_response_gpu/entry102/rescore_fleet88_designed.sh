#!/bin/bash
# Research log entry 102: entry 101's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# 120 s alone, the converged code fit: the recipe's) on data/fleet88p, which also holds each unit's designed
# 120 s calibration (plan120), `cover_informative` and `designed` plans side by side, with the plan's residual
# correction of kernel length $2 and noise-to-signal $3 (length 0: none, the control), into
# entry102/fleet88_cpu_$4/fleet88_seed$1. The registry is simulated again (entry 101's same_rows.py).
k=$1; length=$2; ratio=$3; arm=$4
python reports/cross_sensor_response_gpu/entry101/same_rows.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88p --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --out reports/cross_sensor_response_gpu/entry102/fleet88_cpu_$arm/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover_informative, designed]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4 \
  --set options.response.residual_length=$length --set options.response.residual_ratio=$ratio
