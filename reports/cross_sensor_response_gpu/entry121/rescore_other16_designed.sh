#!/bin/bash
# Research log entry 121: entry 101's other16 rescoring of fold $1 in start draw $2 (the severe models, the
# recipe: `cover_informative` plans by criterion v, the plan's residual correction of length 1 and ratio 10,
# ordinary use; entry 83's options) on data/other16p, other16 with each unit's designed 120 s calibration
# added (plan120), `cover_informative` and `designed` side by side, into
# entry121/other16_severe_d$2/other16_seed$1. The registry is simulated again (entry 101's same_rows.py).
# A later entry may give another directory under cross_sensor_response_gpu/ as $3 and more `--set` options
# after it (the last wins), and another registry as REGISTRY (default data/other16p; entry 126).
k=$1; d=$2; out=${3:-entry121}; shift $(( $# < 3 ? $# : 3 ))
. reports/cross_sensor_response_gpu/entry83/other16.sh
RESCORE_SCRIPT=reports/cross_sensor_response_gpu/entry101/same_rows.py \
python reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 \
  reports/cross_sensor_response_start/other16_seed$k --registry "${REGISTRY:-data/other16p}" \
  --added-protocol plan120 --set "data.protocol=[full, short, quick, plan120]" \
  --response-model "$TWICE_THE_SPREAD" \
  --set options.response.rows_per_step=32768 --set "options.budgets=[0, 120]" \
  --set "options.response.label_free={with_plans: true, zero_shot: false}" \
  --set options.response.inverse_batch=512 --set options.response.inverse_lr=0.02 \
  --set options.response.inverse_epochs=60 \
  --set "options.plan_strategies=[cover_informative, designed]" --set options.response.plan_criterion=v \
  --set options.response.residual_length=1 --set options.response.residual_ratio=10 \
  --out reports/cross_sensor_response_gpu/$out/other16_severe_d$d/other16_seed$k "$@"
