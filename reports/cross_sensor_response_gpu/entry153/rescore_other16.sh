#!/bin/bash
# Research log entry 153: today's recipe on other16 (entry 121's options: the severe models, criterion v, the
# plan's residual correction, centred with ordinary use, start draw $2) at 10, 30, 60 and 120 s,
# `cover_informative` alone and with 600 s of ordinary use, fold $1, on data/other16, into
# entry153/other16_severe_d$2/other16_seed$1.
#   bash reports/cross_sensor_response_gpu/entry153/rescore_other16.sh K D
set -euo pipefail
export OMP_NUM_THREADS=1 PYTHONPATH=research
k=$1 d=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
RESCORE_SCRIPT=reports/cross_sensor_response_gpu/entry101/same_rows.py \
python reports/cross_sensor_response_gpu/entry83/start_draw.py "$d" 60 \
  reports/cross_sensor_response_start/other16_seed$k --registry data/other16 \
  --response-model "$TWICE_THE_SPREAD" \
  --set options.response.rows_per_step=32768 --set "options.budgets=[10, 30, 60, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10 \
  --out reports/cross_sensor_response_gpu/entry153/other16_severe_d$d/other16_seed$k
