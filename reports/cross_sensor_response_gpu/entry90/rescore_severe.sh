#!/bin/bash
# Research log entries 90-91, rule 4: one other16 fold ($1) as entry 83's severe_d$3 (entry 80's models of
# 1,024 extra units drawn at twice the default spread, the headline's), its plans $4 (default informative)
# under criterion $2, into entry90/severe_$2_d$3/other16_seed$1 (informative) or
# entry90/severe_$4_$2_d$3/other16_seed$1. Control: entry83/severe_d$3.
k=$1; c=$2; d=$3; s=${4:-informative}
out=reports/cross_sensor_response_gpu/entry90/severe_${c}_d$d
[ "$s" = informative ] || out=reports/cross_sensor_response_gpu/entry90/severe_${s}_${c}_d$d
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$TWICE_THE_SPREAD" 60 $out/other16_seed$k \
  reports/cross_sensor_response_gpu/entry83/start_draw.py $d 60 \
  --set "options.plan_strategies=[$s]" --set options.response.plan_criterion=$c
