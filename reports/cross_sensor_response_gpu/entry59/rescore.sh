#!/bin/bash
# Research log entry 59 (exploratory): one other16 fold ($1), entry 57's rescoring with `cover` plans of 90 robot-s,
# about the contact time of entry 58's designed 120 s plans.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16 \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 90]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry59/other16_seed$k
