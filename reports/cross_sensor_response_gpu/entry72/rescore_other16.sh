#!/bin/bash
# Research log entry 72: one other16 fold ($1), entry 58's rescoring with each unit's designed and cover jobs' codes
# swapped (the plan alone; the variant of variant.patch, code of the entry's worktree).
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16p \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[cover, designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry72/other16x_seed$k
