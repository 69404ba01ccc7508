#!/bin/bash
# Research log entry 86, second part: one other16 fold ($1) rescored as entry 83's severe_d$2 (entry
# 80's models of 1,024 extra units drawn at twice the default spread, today's recipe, start network
# draw $2), a new unit's codes fitted under the registry prior, into entry86/severe_registry_d$2/other16_seed$1.
k=$1; d=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$TWICE_THE_SPREAD" 60 reports/cross_sensor_response_gpu/entry86/severe_registry_d$d/other16_seed$k \
  reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 --set options.response.code_prior=registry
