#!/bin/bash
# Research log entry 80: one other16 fold ($1) rescored as entry 55 did (batches of 512, lr 0.02, 60
# epochs, budgets 0 and 120 s, ordinary use), with the response model whose 1,024 extra units were
# drawn at twice the default spread.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16 \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768_severe.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry80/other16_seed$k
