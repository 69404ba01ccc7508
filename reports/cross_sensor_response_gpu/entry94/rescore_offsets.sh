#!/bin/bash
# Research log entry 95: one other16 fold ($1) rescored as entry 91's cover_informative_v cells, each plan's
# codes fitted with each press's own offset (entry94/press_offsets.py), into entry94/offsets/other16_seed$1
# with the default-spread models, or entry94/severe_offsets_d$2/other16_seed$1 with entry 80's severe models
# in start draw $2. Controls: entry90/cover_informative_v and entry90/severe_cover_informative_v_d$2.
k=$1; d=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
plans=(--set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v)
if [ -z "$d" ]; then
  other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry94/offsets/other16_seed$k \
    reports/cross_sensor_response_gpu/entry94/press_offsets.py "${plans[@]}"
else
  # the start network's draw and the press offsets both wrap rescore_response.py: the draw's wrapper runs
  # the offsets' script in its place
  RESCORE_SCRIPT=reports/cross_sensor_response_gpu/entry94/press_offsets.py other16_rescore $k \
    "$TWICE_THE_SPREAD" 60 reports/cross_sensor_response_gpu/entry94/severe_offsets_d$d/other16_seed$k \
    reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 "${plans[@]}"
fi
