#!/bin/bash
# Research log entry 97: fleet88 fold $1 as entry 91's rule 4 (the CPU response models, the registry code prior,
# 120 s alone), `cover` and `cover_informative` (criterion v) in one rescoring, so that each validation unit is
# scored under both, into entry97/fleet88_cpu/fleet88_seed$1.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_response_gpu/entry97/fleet88_cpu/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v
