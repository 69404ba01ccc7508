#!/bin/bash
# Research log entry 54: one other16 fold ($1) of one arm ($2: b512 or b512e60), entry 51's command
# with the unit network in batches of 512 at lr 0.02 (and 60 epochs for b512e60).
k=$1; arm=$2
extra=(); [ "$arm" = b512e60 ] && extra=(--set options.response.inverse_epochs=60)
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16 \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 "${extra[@]}" \
  --out reports/cross_sensor_response_gpu/entry54/$arm/other16_seed$k
