#!/bin/bash
# Research log entry 99: entry 97's fleet88 rescoring of fold $1 (CPU response models, the registry code prior,
# 120 s alone, `cover` and `cover_informative`) with the codes fitted to convergence (at most 40 Gauss-Newton
# steps, tolerance 1e-4), into entry99/fleet88_cpu/fleet88_seed$1. Control: entry97/fleet88_cpu.
k=$1
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out reports/cross_sensor_response_gpu/entry99/fleet88_cpu/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[cover, cover_informative]" --set options.response.plan_criterion=v \
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4
