#!/bin/bash
# Research log entries 90-91's diagnostic: other16 fold $1 as entry 83's e60_d0, each validation and held-out
# unit's codes from its `cover` plan, its plan $3 (default informative) under criterion $2 and its whole
# calibration, scored on that calibration per |F| band, into entry90/code_residuals/$2/other16_seed$1
# (informative) or entry90/code_residuals/$3_$2/other16_seed$1 (no network trains).
k=$1; c=$2; s=${3:-informative}
out=reports/cross_sensor_response_gpu/entry90/code_residuals/$c
[ "$s" = informative ] || out=reports/cross_sensor_response_gpu/entry90/code_residuals/${s}_$c
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 $out/other16_seed$k \
  reports/cross_sensor_response_gpu/entry90/code_residuals.py \
  --set "options.plan_strategies=[cover, $s]" --set options.response.plan_criterion=$c
