#!/bin/bash
# Research log entry 93: other16 fold $1 as entry 91's cover_informative_v with the low-force presses kept
# (keep_low.py): the default-spread models into entry90/keep_low_v/other16_seed$1, or with $2 = D the
# severe model's draw D (as entry 83's severe_dD) into entry90/severe_keep_low_v_dD/other16_seed$1.
k=$1; d=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
if [ -z "$d" ]; then
  other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry90/keep_low_v/other16_seed$k \
    reports/cross_sensor_response_gpu/entry90/keep_low.py \
    --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v
else
  other16_rescore $k "$TWICE_THE_SPREAD" 60 reports/cross_sensor_response_gpu/entry90/severe_keep_low_v_d$d/other16_seed$k \
    reports/cross_sensor_response_gpu/entry90/keep_low.py reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 \
    --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v
fi
