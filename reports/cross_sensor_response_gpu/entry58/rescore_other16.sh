#!/bin/bash
# Research log entry 58: one other16 fold ($1), entry 57's rescoring (entry 54's taken arm) on other16 with
# each unit's designed 120 s calibration added (data/other16p), `cover` and `designed` plans side by side.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16p \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[cover, designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry58/other16_seed$k
