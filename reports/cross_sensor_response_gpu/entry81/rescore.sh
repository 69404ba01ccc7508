#!/bin/bash
# Research log entry 81: one other16 fold ($1) rescored as entry 57 did (the default-spread 1,024-unit
# models, batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s, ordinary use), with $2 steps of the
# joint fit of the codes (30: the recipe, the control).
k=$1; n=$2
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16 \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false, iterations: $n}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry81/it${n}/other16_seed$k
