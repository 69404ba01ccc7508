#!/bin/bash
# Research log entry 70: one other16 fold ($1), entry 63's rescoring with every unit tested in a session of its
# own without the warm-up (data/other16rc: other16p plus each unit's retest runs with warmup_c 0, the variant
# of variant.patch), the run's saved references scored again there.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/other16_seed$k --registry data/other16rc --added-protocol retest --references reports/cross_sensor_response_folds16/seed$k/models \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120, retest]" \
  --set "options.plan_strategies=[cover, designed]" \
  --response-model 'reports/cross_sensor_response_gpu/models/other16_seed{seed}_extra1024_rps32768.safetensors' \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --out reports/cross_sensor_response_gpu/entry70/other16rc_seed$k
