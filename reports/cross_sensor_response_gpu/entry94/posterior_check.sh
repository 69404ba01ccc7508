#!/bin/bash
# Research log entry 94's diagnostic: other16 fold $1 as entry 91's cover_informative_v cells (default-spread
# models), each validation and held-out unit's plan codes, their Laplace covariance and its whole-calibration
# codes compared, into entry94/posterior_check/other16_seed$1 (no network trains).
k=$1
. reports/cross_sensor_response_gpu/entry83/other16.sh
other16_rescore $k "$DEFAULT_SPREAD" 60 reports/cross_sensor_response_gpu/entry94/posterior_check/other16_seed$k \
  reports/cross_sensor_response_gpu/entry94/posterior_check.py \
  --set "options.plan_strategies=[cover_informative]" --set options.response.plan_criterion=v
