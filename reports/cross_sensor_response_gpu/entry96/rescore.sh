#!/bin/bash
# Research log entry 96: one other16 fold ($1) rescored as entry 91's cover_informative_v cells, each plan's
# codes fitted on rows weighted to the source rows' label cells $2 (f or fp; entry96/weighted_codes.py), into
# entry96/$2/other16_seed$1 with the default-spread models, or entry96/severe_$2_d$3/other16_seed$1 with entry
# 80's severe models in start draw $3. Controls: entry90/cover_informative_v and entry90/severe_cover_informative_v_d$3.
k=$1; cells=$2; d=$3
. reports/cross_sensor_response_gpu/entry83/other16.sh
plans=(--set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v)
script=reports/cross_sensor_response_gpu/entry96/weighted_codes.py
if [ -z "$d" ]; then
  other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry96/$cells/other16_seed$k \
    $script $cells "${plans[@]}"
else
  RESCORE_SCRIPT=$script other16_rescore $k "$TWICE_THE_SPREAD" 60 \
    reports/cross_sensor_response_gpu/entry96/severe_${cells}_d$d/other16_seed$k \
    reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 $cells "${plans[@]}"
fi
