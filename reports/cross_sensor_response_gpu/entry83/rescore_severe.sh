#!/bin/bash
# Research log entry 83, third part: one other16 fold ($1) rescored as entry 80 did (the 1,024 extra
# units drawn at twice the default spread; batches of 512, lr 0.02, 60 epochs, budgets 0 and 120 s,
# ordinary use) with today's recipe (10 steps of the joint fit) and start network draw $2 (60 epochs),
# into entry83/severe_d$2/other16_seed$1.
k=$1; d=$2
python reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 reports/cross_sensor_response_start/other16_seed$k \
  --registry data/other16 \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768_severe.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry83/severe_d$d/other16_seed$k
