#!/bin/bash
# Research log entries 90-91, rule 4: fleet88 fold $1 as entry 86's fourth part (entry 26's CPU response models
# of 16 registry and 128 simulated units, the registry code prior, 120 s alone), its plans $3 (default
# informative) under criterion $2, into entry90/fleet88_cpu_$2/fleet88_seed$1 (informative) or
# entry90/fleet88_cpu_$3_$2/fleet88_seed$1. Control: entry86/fleet88_cpu_registry.
k=$1; c=$2; s=${3:-informative}
out=reports/cross_sensor_response_gpu/entry90/fleet88_cpu_$c
[ "$s" = informative ] || out=reports/cross_sensor_response_gpu/entry90/fleet88_cpu_${s}_$c
python scripts/rescore_response.py reports/cross_sensor_response_start/fleet88_seed$k \
  --registry data/fleet88 --out $out/fleet88_seed$k \
  --response-model "reports/cross_sensor_response_start/fleet88_seed$k/models/response_seed{seed}.safetensors" \
  --set "options.budgets=[120]" --set "options.intervals=null" --set options.response.code_prior=registry \
  --set "options.plan_strategies=[$s]" --set options.response.plan_criterion=$c
