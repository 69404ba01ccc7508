#!/bin/bash
# Research log entry 64: one other16 fold ($1), entry 58's rescoring on other16 simulated without the dome's
# warm-up (data/other16u), `cover` and `designed` plans side by side, paired only (the references are other16's).
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16u --paired-only \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[cover, designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry64/other16u_seed$k
