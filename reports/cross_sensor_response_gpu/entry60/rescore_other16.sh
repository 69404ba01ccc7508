#!/bin/bash
# Research log entry 60: one other16 fold ($2) of design variant $1 (1, 2 or 4 presses per point; code of
# the entry's commit with DESIGNED_PRESS set to that variant), entry 58's rescoring on a registry holding
# each unit's plan120 runs of that design (data/other16v$1), the designed plan alone as strategy.
v=$1
k=$2
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16v$v \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry60/other16v${v}_seed$k
