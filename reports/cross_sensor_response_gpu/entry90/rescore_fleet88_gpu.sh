#!/bin/bash
# Research log entry 91, fleet88's 1,024-unit models: fleet88 fold $1 as entry 86's fleet88_registry (the GPU
# response models of 1,040 units, the registry code prior, 120 s with ordinary use, 24 factor units), its
# plans cover_informative (criterion v), into entry90/fleet88_gpu_cover_informative_v/fleet88_seed$1.
# Control: entry86/fleet88_registry/fleet88_seed$1.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k --registry data/fleet88 \
  --response-model 'reports/cross_sensor_response_gpu/models/fleet88_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false, plan_iterations: 10}" \
  --set options.response.transfer_from=registry \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 --set options.extra_units=null \
  --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v \
  --out reports/cross_sensor_response_gpu/entry90/fleet88_gpu_cover_informative_v/fleet88_seed$k
