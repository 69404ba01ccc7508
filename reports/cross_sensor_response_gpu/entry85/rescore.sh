#!/bin/bash
# Research log entry 85: one other16 fold ($1) rescored as entry 83's e60_d0 (entry 81's 10-step arm:
# the default-spread 1,024-unit models, batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s,
# ordinary use), each unit's network warming up over $2 of its steps, into entry85/w$2/other16_seed$1.
k=$1; w=$2
python reports/cross_sensor_response_gpu/entry85/warmup.py $w reports/cross_sensor_response_start/other16_seed$k \
  --registry data/other16 \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry85/w$w/other16_seed$k
