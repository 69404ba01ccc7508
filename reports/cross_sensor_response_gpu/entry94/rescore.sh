#!/bin/bash
# Research log entry 94: one other16 fold ($1) rescored as entry 91's cover_informative_v cells, each
# transferred row's codes drawn from the codes' Laplace posterior with its covariance times $2
# (`options.response.code_draw_scale`), into entry94/scale$2/other16_seed$1 with the default-spread
# models, or entry94/severe_scale$2_d$3/other16_seed$1 with entry 80's severe models in start draw $3.
# Controls: entry90/cover_informative_v/other16_seed$1 and entry90/severe_cover_informative_v_d$3.
k=$1; scale=$2; d=$3
. reports/cross_sensor_response_gpu/entry83/other16.sh
draws=(--set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v
       --set options.response.code_draw_scale=$scale)
if [ -z "$d" ]; then
  other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry94/scale$scale/other16_seed$k \
    scripts/rescore_response.py "${draws[@]}"
else
  other16_rescore $k "$TWICE_THE_SPREAD" 60 \
    reports/cross_sensor_response_gpu/entry94/severe_scale${scale}_d$d/other16_seed$k \
    reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 "${draws[@]}"
fi
