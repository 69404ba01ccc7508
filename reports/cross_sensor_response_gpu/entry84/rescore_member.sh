#!/bin/bash
# Research log entry 84, second part: one other16 fold ($1) rescored as entry 83's e60_d0, each unit's
# network one member alone trained $2 epochs from the same start network (draw 0, 60 epochs), into
# entry84/member$2/other16_seed$1.
k=$1; e=$2
python reports/cross_sensor_response_gpu/entry83/start_draw.py 0 60 reports/cross_sensor_response_start/other16_seed$k \
  --registry data/other16 \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=$e \
  --out reports/cross_sensor_response_gpu/entry84/member$e/other16_seed$k
