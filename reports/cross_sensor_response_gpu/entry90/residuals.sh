#!/bin/bash
# Research log entry 90's diagnostic: other16 fold $1 as entry 83's e60_d0, each validation and held-out
# unit's codes from its `cover` and its `informative` (criterion $2) plan and from its whole calibration,
# scored on that calibration per |F| band, into entry90/code_residuals/$2/other16_seed$1 (no network trains).
k=$1; c=$2
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry90/code_residuals/$c/other16_seed$k \
  reports/cross_sensor_response_gpu/entry90/code_residuals.py \
  --set "options.plan_strategies=[cover, informative]" --set options.response.plan_criterion=$c
