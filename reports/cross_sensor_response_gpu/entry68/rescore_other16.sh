#!/bin/bash
# Research log entry 68: one other16 fold ($2) of arm $1 (warm: each unit's plan120 runs with 240 s at rest before
# the first press, data/other16w, `cover` and `designed`; cold: the plan in place, data/other16p, `designed`),
# entry 58's rescoring, code of the entry's worktree (the variant's simulator and power-up tare).
arm=$1
k=$2
if [ "$arm" = warm ]; then reg=data/other16w; strategies="[cover, designed]"; else reg=data/other16p; strategies="[designed]"; fi
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry $reg \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=$strategies" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry68/other16${arm}_seed$k
