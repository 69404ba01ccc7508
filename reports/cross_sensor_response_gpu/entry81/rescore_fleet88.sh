#!/bin/bash
# Research log entry 81, second part: fleet88 fold 0 rescored as entry 52 did (1,024-unit model,
# ordinary use, 24 factor units, batches of 512 at lr 0.02) with today's code and $1 steps of the
# joint fit with the plan (plan_iterations), into entry81/fleet88_it$1.
n=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed0 --registry data/fleet88 \
  --response-model 'reports/cross_sensor_response_gpu/models/fleet88_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false, plan_iterations: $n}" \
  --set options.response.transfer_from=registry \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 --set options.extra_units=null \
  --out reports/cross_sensor_response_gpu/entry81/fleet88_it$n/fleet88_seed0
