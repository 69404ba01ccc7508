#!/bin/bash
# Research log entry 92: one other16 fold ($1) as entry 91's cover_informative_v (the default-spread models),
# the exchanges kept to one force level (force_cells.py), into entry90/force_cells_v/other16_seed$1.
k=$1
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry90/force_cells_v/other16_seed$k \
  reports/cross_sensor_response_gpu/entry90/force_cells.py \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v
