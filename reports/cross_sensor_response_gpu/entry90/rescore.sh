#!/bin/bash
# Research log entries 90-91: one other16 fold ($1) rescored as entry 83's e60_d0, its plans $3 (default
# informative) under criterion $2 (d or v), into entry90/$2/other16_seed$1 (informative) or
# entry90/$3_$2/other16_seed$1. Control: entry83/e60_d0/other16_seed$1.
k=$1; c=$2; s=${3:-informative}
out=reports/cross_sensor_response_gpu/entry90/$c
[ "$s" = informative ] || out=reports/cross_sensor_response_gpu/entry90/${s}_$c
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 $out/other16_seed$k scripts/rescore_response.py \
  --set "options.plan_strategies=[$s]" --set options.response.plan_criterion=$c
