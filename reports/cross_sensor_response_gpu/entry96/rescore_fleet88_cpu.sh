#!/bin/bash
# Research log entry 96, stage 3: fleet88 fold $1 as entry 86's fleet88_cpu_registry (the CPU response models,
# the registry code prior, `cover` plans, 120 s alone), each plan's codes fitted on rows weighted to the source
# rows' label cells $2 (entry96/weighted_codes.py), into entry96/fleet88_cpu_$2/fleet88_seed$1.
k=$1; cells=$2
python reports/cross_sensor_response_gpu/entry96/weighted_codes.py $cells reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_response_gpu/entry96/fleet88_cpu_$cells/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry
