#!/bin/bash
# Research log entry 94's diagnostic on the default fingertip: fleet88 fold $1 as entry 86's fleet88_cpu_registry
# (entry 26's CPU response models, the registry code prior, `cover` plans, 120 s alone), each validation and
# held-out unit's plan codes, their Laplace covariance and its whole-calibration codes compared, into
# entry94/posterior_check/fleet88_seed$1 (no network trains).
k=$1
python reports/cross_sensor_response_gpu/entry94/posterior_check.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_response_gpu/entry94/posterior_check/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry
