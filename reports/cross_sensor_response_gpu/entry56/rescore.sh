#!/bin/bash
# Research log entry 56: one fleet88 fold ($1), entry 52's rescoring with 4,000 source rows per training
# unit for 74 epochs (the same steps as 8,000 rows for 40 on a 120 s plan).
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k --registry data/fleet88 \
  --response-model 'reports/cross_sensor_response_gpu/models/fleet88_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.transfer_from=registry \
  --set "options.intervals={folds: 5, level: 0.9, transfer_check: false, factor_units: 24}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.extra_units=null \
  --set options.response.source_rows=4000 --set options.response.inverse_epochs=74 \
  --out reports/cross_sensor_response_gpu/entry56/fleet88_seed$k
