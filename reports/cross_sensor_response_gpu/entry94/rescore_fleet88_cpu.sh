#!/bin/bash
# Research log entry 94, stage 3: fleet88 fold $1 as entry 86's fleet88_cpu_registry (entry 26's CPU response
# models of 16 registry and 128 simulated units, the registry code prior, `cover` plans, 120 s alone), each
# transferred row's codes drawn from their posterior at scale $2, into entry94/fleet88_cpu_scale$2/fleet88_seed$1.
k=$1; scale=$2
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_response_gpu/entry94/fleet88_cpu_scale$scale/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set options.response.code_draw_scale=$scale
