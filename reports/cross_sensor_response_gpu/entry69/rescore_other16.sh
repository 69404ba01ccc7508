#!/bin/bash
# Research log entry 69: one other16 fold ($2) of re-mount rule $1 (n1: the rule in place, two orientations when
# the re-mount costs at most a quarter of the budget; n2: at most half), entry 58's rescoring at 90 s on a
# registry holding each unit's plan90 runs of that rule (data/other16$1), the designed plan alone as strategy.
v=$1
k=$2
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16$v \
  --added-protocol plan90 --set "data.protocol=[full, short, quick, plan90]" \
  --set "options.plan_strategies=[designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 90]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry69/other16${v}_seed$k
