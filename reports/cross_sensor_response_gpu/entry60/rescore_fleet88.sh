#!/bin/bash
# Research log entry 60: one fleet88 fold ($1), entry 58's rescoring with each unit's plan120 runs of the chosen design
# (data/fleet88d: design_protocol of the entry's second commit), `cover` and `designed` plans side by side.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k --registry data/fleet88d \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[cover, designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/fleet88_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.transfer_from=registry \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.extra_units=null \
  --out reports/cross_sensor_response_gpu/entry60/fleet88_seed$k
