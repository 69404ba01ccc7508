#!/bin/bash
# Research log entry 61: one other16 fold ($2) of design $1 (w0: the design in place, data/other16p; w4, w2, wc; code of
# the entry's commit with design_protocol changed to that design), entry 58's rescoring on a registry holding
# each unit's plan120 runs of that design (data/other16$1), the designed plan alone as strategy.
v=$1
k=$2
reg=other16$v; [ "$v" = w0 ] && reg=other16p
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/$reg \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --set "options.plan_strategies=[designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry61/other16${v}_seed$k
