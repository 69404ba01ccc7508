#!/bin/bash
# Research log entry 97, second part: other16 fold $1 with the severe models in start draw $2 (entry 83's
# severe_d$2), `cover` and `cover_informative` (criterion v) in one rescoring, into
# entry97/other16_severe_d$2/other16_seed$1. Controls: entry83/severe_d$2 and entry90/severe_cover_informative_v_d$2.
k=$1; d=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$TWICE_THE_SPREAD" 60 reports/cross_sensor_response_gpu/entry97/other16_severe_d$d/other16_seed$k \
  reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v
