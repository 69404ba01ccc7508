#!/bin/bash
# Research log entry 83, second part: fleet88 fold 0 rescored as entry 81's 10-step arm did (the
# 1,024-unit model, ordinary use, 24 factor units, batches of 512 at lr 0.02, 40 epochs), with start
# network draw $1 (40 epochs, as the recipe trains it), into entry83/fleet88_d$1/fleet88_seed0.
d=$1
python reports/cross_sensor_response_gpu/entry83/start_draw.py $d 40 reports/cross_sensor_response_start/fleet88_seed0 \
  --registry data/fleet88 \
  --response-model 'reports/cross_sensor_response_gpu/models/fleet88_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.transfer_from=registry \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 --set options.extra_units=null \
  --out reports/cross_sensor_response_gpu/entry83/fleet88_d$d/fleet88_seed0
