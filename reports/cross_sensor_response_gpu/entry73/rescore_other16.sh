#!/bin/bash
# Research log entry 73: one other16 fold ($1), entry 68's `cold` rescoring (data/other16p, the designed plan alone)
# with each designed job's codes shifted by its training units' mean cover-minus-designed codes (the variant of
# variant.patch, code of the entry's worktree).
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16p \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry73/other16c_seed$k
